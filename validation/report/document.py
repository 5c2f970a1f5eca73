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

    Built by :func:`.verdict.row`, which judges it.  ``key`` is stable across runs (summary.json,
    docs/report.md); ``value``/``error`` are the computed number and its standard error (``None``
    where there is none); ``paper_value`` the :class:`.paper.PaperValue` compared with (``None``:
    not in the paper); ``outcome`` the :class:`.verdict.Verdict`.  The text columns (``paper`` ...
    ``explanation``) are what the tables show; ``verdict`` is "agrees", "disagrees" or "not compared".
    """

    key: str
    quantity: str
    paper: str
    computed: str
    error_bar: str
    deviation: str
    verdict: str
    explanation: str
    where: str = ""
    value: float | int | None = None
    error: float | None = None
    paper_value: object = None
    outcome: object = None

    @property
    def check(self) -> str:
        """``pass``/``fail`` of an internal check against its stated tolerance ("" when there is none)."""
        return (getattr(self.outcome, "check", None) or "") if self.outcome is not None else ""

    def as_json(self, section: str) -> dict:
        """The row for summary.json: stable key, numeric value and error (null when none), the paper's
        value/error/kind/where/quote, the verdict with deviation and z, and the text columns."""
        pv, o = self.paper_value, self.outcome
        return {
            "key": self.key, "quantity": self.quantity, "value": _json_num(self.value), "error": _json_num(self.error),
            "paper_value": None if pv is None else (_json_num(pv.value) if pv.numeric else pv.value),
            "paper_error": None if pv is None else _json_num(pv.error),
            "paper_sigma": None if pv is None or not pv.numeric else _json_num(pv.sigma),
            "paper_kind": None if pv is None else pv.kind,
            "paper_where": None if pv is None else pv.where,
            "paper_quote": None if pv is None else pv.quote,
            "deviation_value": None if o is None else _json_num(o.deviation),
            "z": None if o is None else _json_num(o.z),
            "verdict": self.verdict, "check": self.check or None,
            "tolerance": None if o is None else _json_num(o.tolerance),
            "paper": self.paper, "computed": self.computed, "error_bar": self.error_bar, "deviation": self.deviation,
            "explanation": self.explanation, "where": self.where, "section": section,
        }


def _json_num(x):
    """A JSON-safe number: Python int/float, ``None`` for None, NaN and infinities."""
    if x is None or isinstance(x, bool):
        return None if x is None else x
    try:
        f = float(x)
    except (TypeError, ValueError):
        return None
    if not math.isfinite(f):
        return None
    if isinstance(x, int) or (hasattr(x, "dtype") and getattr(x.dtype, "kind", "") in "iu"):
        return int(x)
    return f


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


def _md_table(header, rows) -> str:
    esc = lambda s: str(s).replace("|", "\\|").replace("\n", " ")  # noqa: E731
    out = ["| " + " | ".join(esc(h) for h in header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(esc(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


SUMMARY_HEADER = ["key", "quantity", "paper", "computed", "error bar", "deviation", "verdict", "internal check",
                  "explanation", "section"]
SUMMARY_TITLE = "Summary: the paper's numbers beside ours"


def summary_rows(sections: list[Section]) -> list[list[str]]:
    return [[n.key, n.quantity, n.paper, n.computed, n.error_bar, n.deviation, n.verdict, n.check, n.explanation,
             s.title] for s in sections for n in s.numbers]


def check_keys(sections: list[Section]) -> None:
    """Every summary row has a key, and no key is used twice (summary.json is read by key)."""
    seen: dict[str, str] = {}
    for s in sections:
        for n in s.numbers:
            if n.key in seen:
                raise ValueError(f"summary key {n.key!r} is used twice (sections {seen[n.key]!r} and {s.key!r})")
            seen[n.key] = s.key


def verdict_counts(sections: list[Section]) -> dict[str, int]:
    """How many rows agree, disagree, are not compared; how many internal checks pass and fail."""
    rows = [n for s in sections for n in s.numbers]
    c = {v: sum(n.verdict == v for n in rows) for v in ("agrees", "disagrees", "not compared")}
    c.update({f"check {v}": sum(n.check == v for n in rows) for v in ("pass", "fail")})
    c["sections failed"] = sum(not s.ok for s in sections)
    return c


def counts_line(sections: list[Section]) -> str:
    c = verdict_counts(sections)
    line = (f"Verdicts: {c['agrees']} agree, {c['disagrees']} disagree, {c['not compared']} not compared "
            f"(internal checks: {c['check pass']} pass, {c['check fail']} fail).")
    if c["sections failed"]:
        line += f" {c['sections failed']} section(s) FAILED."
    return line


def _heading(s: Section) -> str:
    return f"{s.title}{'' if s.ok else ' — FAILED'}"


def md_slug(heading: str) -> str:
    """The anchor GitHub-flavoured Markdown gives a heading: lower case, punctuation dropped, spaces -> '-'."""
    out = []
    for ch in heading.strip().lower():
        if ch.isalnum() or ch in "-_":
            out.append(ch)
        elif ch == " ":
            out.append("-")
    return "".join(out)


def render_markdown(title: str, preamble: list[str], sections: list[Section], out_dir: Path) -> str:
    lines = [f"# {title}", ""]
    lines += [*preamble, ""]
    lines += [f"**{counts_line(sections)}**", ""]
    lines += ["Contents:", "", f"* [{SUMMARY_TITLE}](#{md_slug(SUMMARY_TITLE)})"]
    lines += [f"* [{_heading(s)}](#{md_slug(_heading(s))})" for s in sections] + [""]
    lines += [f"## {SUMMARY_TITLE}", "", _md_table(SUMMARY_HEADER, summary_rows(sections)), ""]
    for s in sections:
        lines += [f"## {_heading(s)}", "", f"*run time {s.seconds:.1f} s*", ""]
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
pre{background:#f6f6f6;padding:.6em;overflow-x:auto}.failed{color:#b00}.agrees{color:#070}.disagrees{color:#b00}
.not{color:#555}.pass{color:#070}.fail{color:#b00}.counts{font-weight:bold}"""


def _html_table(header, rows, class_cols: tuple[int, ...] = ()) -> str:
    h = "".join(f"<th>{html.escape(str(c))}</th>" for c in header)
    body = []
    for r in rows:
        cells = []
        for i, c in enumerate(r):
            cls = f' class="{html.escape(str(c).split()[0])}"' if i in class_cols and str(c) else ""
            cells.append(f"<td{cls}>{html.escape(str(c))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><tr>{h}</tr>{''.join(body)}</table>"


def render_html(title: str, preamble: list[str], sections: list[Section]) -> str:
    parts = [f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>",
             f"<style>{_CSS}</style></head><body><h1>{html.escape(title)}</h1>"]
    parts += [f"<p>{html.escape(p)}</p>" for p in preamble]
    parts.append(f"<p class='counts'>{html.escape(counts_line(sections))}</p>")
    toc = [f"<li><a href='#summary'>{html.escape(SUMMARY_TITLE)}</a></li>"]
    toc += [f"<li><a href='#sec-{html.escape(s.key)}'>{html.escape(_heading(s))}</a></li>" for s in sections]
    parts.append("<nav><p>Contents:</p><ul>" + "".join(toc) + "</ul></nav>")
    parts += [f"<h2 id='summary'>{html.escape(SUMMARY_TITLE)}</h2>",
              _html_table(SUMMARY_HEADER, summary_rows(sections), class_cols=(6, 7))]
    for s in sections:
        cls = "" if s.ok else " class='failed'"
        parts.append(f"<h2 id='sec-{html.escape(s.key)}'{cls}>{html.escape(_heading(s))}</h2>")
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
