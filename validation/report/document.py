"""The report's document model and its two renderings: Markdown and self-contained HTML.

A report is a list of :class:`Section` objects, each a list of blocks (paragraphs, tables, figures,
preformatted text) plus rows for the summary table of paper-vs-computed numbers.  Figures are PNG
files written by the sections; the HTML embeds them (base64) so the page stands alone.
"""

from __future__ import annotations

import base64
import html
import math
from dataclasses import dataclass, field
from pathlib import Path


@dataclass
class Number:
    """One row of the summary table: a quantity of the paper beside the computed value.

    ``verdict`` is "agrees", "disagrees" or "not compared"; ``explanation`` says why.
    """

    quantity: str
    paper: str
    computed: str
    error_bar: str
    deviation: str
    verdict: str
    explanation: str
    where: str = ""


@dataclass
class Section:
    """A report section: title, blocks ("p", text) / ("table", header, rows) / ("fig", path, caption) /
    ("pre", text), summary numbers, and its run time and status."""

    key: str
    title: str
    blocks: list = field(default_factory=list)
    numbers: list[Number] = field(default_factory=list)
    seconds: float = 0.0
    ok: bool = True
    error: str = ""

    def p(self, text: str) -> None:
        self.blocks.append(("p", text))

    def table(self, header: list[str], rows: list[list]) -> None:
        self.blocks.append(("table", header, [[fmt(x) for x in r] for r in rows]))

    def fig(self, path: str | Path, caption: str) -> None:
        self.blocks.append(("fig", str(path), caption))

    def pre(self, text: str) -> None:
        self.blocks.append(("pre", text))


def fmt(x, digits: int = 6) -> str:
    """Format a number for a table (general format, NaN/inf spelled out)."""
    if isinstance(x, bool) or x is None:
        return str(x)
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return f"{x:.{digits}g}"
    return str(x)


def deviation(computed: float, paper: float, err: float | None = None) -> str:
    """Absolute and relative deviation, and in units of the error bar when one is given."""
    d = computed - paper
    s = f"{d:+.3g} ({d / paper:+.2%})" if paper else f"{d:+.3g}"
    if err and err > 0 and math.isfinite(err):
        s += f", {abs(d) / err:.1f} sigma"
    return s


def _md_table(header, rows) -> str:
    esc = lambda s: str(s).replace("|", "\\|").replace("\n", " ")  # noqa: E731
    out = ["| " + " | ".join(esc(h) for h in header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(esc(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


SUMMARY_HEADER = ["quantity", "paper", "computed", "error bar", "deviation", "verdict", "explanation", "section"]


def summary_rows(sections: list[Section]) -> list[list[str]]:
    return [[n.quantity, n.paper, n.computed, n.error_bar, n.deviation, n.verdict, n.explanation, s.title]
            for s in sections for n in s.numbers]


def render_markdown(title: str, preamble: list[str], sections: list[Section], out_dir: Path) -> str:
    lines = [f"# {title}", ""]
    lines += [*preamble, ""]
    lines += ["## Summary: the paper's numbers beside ours", "", _md_table(SUMMARY_HEADER, summary_rows(sections)), ""]
    for s in sections:
        status = "" if s.ok else " — FAILED"
        lines += [f"## {s.title}{status}", "", f"*run time {s.seconds:.1f} s*", ""]
        if not s.ok:
            lines += ["```", s.error, "```", ""]
        for b in s.blocks:
            if b[0] == "p":
                lines += [b[1], ""]
            elif b[0] == "table":
                lines += [_md_table(b[1], b[2]), ""]
            elif b[0] == "fig":
                rel = Path(b[1]).resolve().relative_to(out_dir.resolve())
                lines += [f"![{b[2]}]({rel.as_posix()})", "", f"*{b[2]}*", ""]
            elif b[0] == "pre":
                lines += ["```", b[1], "```", ""]
    return "\n".join(lines) + "\n"


_CSS = """body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;line-height:1.45}
table{border-collapse:collapse;margin:1em 0;font-size:90%}td,th{border:1px solid #bbb;padding:3px 6px;vertical-align:top}
th{background:#eee}img{max-width:100%}figure{margin:1em 0}figcaption{font-style:italic;font-size:90%}
pre{background:#f6f6f6;padding:.6em;overflow-x:auto}.failed{color:#b00}.agrees{color:#070}.disagrees{color:#b00}"""


def _html_table(header, rows, verdict_col: int | None = None) -> str:
    h = "".join(f"<th>{html.escape(str(c))}</th>" for c in header)
    body = []
    for r in rows:
        cells = []
        for i, c in enumerate(r):
            cls = f' class="{html.escape(str(c).split()[0])}"' if i == verdict_col and str(c) else ""
            cells.append(f"<td{cls}>{html.escape(str(c))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><tr>{h}</tr>{''.join(body)}</table>"


def render_html(title: str, preamble: list[str], sections: list[Section]) -> str:
    parts = [f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>",
             f"<style>{_CSS}</style></head><body><h1>{html.escape(title)}</h1>"]
    parts += [f"<p>{html.escape(p)}</p>" for p in preamble]
    parts += ["<h2>Summary: the paper's numbers beside ours</h2>",
              _html_table(SUMMARY_HEADER, summary_rows(sections), verdict_col=5)]
    for s in sections:
        cls = "" if s.ok else " class='failed'"
        parts.append(f"<h2{cls}>{html.escape(s.title)}{'' if s.ok else ' — FAILED'}</h2>")
        parts.append(f"<p><i>run time {s.seconds:.1f} s</i></p>")
        if not s.ok:
            parts.append(f"<pre>{html.escape(s.error)}</pre>")
        for b in s.blocks:
            if b[0] == "p":
                parts.append(f"<p>{html.escape(b[1])}</p>")
            elif b[0] == "table":
                parts.append(_html_table(b[1], b[2]))
            elif b[0] == "fig":
                data = base64.b64encode(Path(b[1]).read_bytes()).decode()
                parts.append(f"<figure><img src='data:image/png;base64,{data}' alt='{html.escape(b[2])}'>"
                             f"<figcaption>{html.escape(b[2])}</figcaption></figure>")
            elif b[0] == "pre":
                parts.append(f"<pre>{html.escape(b[1])}</pre>")
    parts.append("</body></html>")
    return "\n".join(parts)
