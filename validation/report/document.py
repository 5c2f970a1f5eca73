"""The report's document model, its two renderings (Markdown and self-contained HTML) and its JSON form.

A report (:class:`Document`) is a title, an introduction, the run's provenance and a list of
:class:`Section` objects, each a list of blocks (paragraphs, tables, figures, preformatted text)
plus rows (:class:`Number`) of paper-vs-computed numbers.  Figures are PNG files written by the
sections; the HTML embeds them (base64) so the page stands alone.

The page, in both renderings: the title, one paragraph, the verdict counts naming every row that
disagrees, then the **verdict table** (one short line per row: key, paper, ours +- error, verdict
with a mark, one-line reason; disagreements marked by a cross, capitals and a shaded row, not by
colour alone), then each row's details (the paper's words, the full error bar, how it was computed;
folded in HTML), the contents, the provenance of the run, and the sections.

:func:`document_json` / :func:`sections_from_json` write and read the model (``document.json``), so
that a report can be drawn again without computing anything (``builder.rerender``).
"""

from __future__ import annotations

import base64
import html
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

from ..paper import PaperValue


class Outcome(Protocol):
    """What a row shows of its verdict (a :class:`.verdict.Verdict`, which builds the rows: named here
    by what is read, not imported)."""

    @property
    def deviation(self) -> float | None: ...
    @property
    def z(self) -> float | None: ...
    @property
    def tolerance(self) -> float | None: ...
    @property
    def check(self) -> str | None: ...
    @property
    def bound(self) -> str | None: ...
    @property
    def unit(self) -> float | None: ...
    @property
    def enclosure(self) -> tuple[float, float] | None: ...


@dataclass
class Number:
    """One row of the verdict table: a quantity of the paper beside the computed value.

    Built by :func:`.verdict.row`, which judges it.  ``key`` is stable across runs (summary.json,
    docs/report.md); ``value``/``error`` are the computed number and its standard error (``None``
    where there is none); ``paper_value`` the :class:`.paper.PaperValue` compared with (``None``:
    not in the paper); ``outcome`` the :class:`.verdict.Verdict`.  The text columns (``paper`` ...
    ``explanation``) are what the tables show; ``verdict`` is "agrees", "disagrees" or "not compared".
    ``spec`` holds the arguments of :func:`.verdict.row` that built it (for ``document.json``).
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
    paper_value: PaperValue | None = None
    outcome: Outcome | None = None
    spec: dict = field(default_factory=dict)

    @property
    def check(self) -> str:
        """``pass``/``fail`` of an internal check against its stated tolerance ("" when there is none)."""
        return (getattr(self.outcome, "check", None) or "") if self.outcome is not None else ""

    def as_json(self, section: str) -> dict:
        """The row for summary.json: stable key, numeric value and error (null when none), the paper's
        value/error/kind/where/quote and printed precision, the verdict with deviation and z (a bound:
        its outcome, margin in units of the paper's last digit and the enclosure judged), and the text
        columns."""
        pv, o = self.paper_value, self.outcome
        bound = getattr(o, "bound", None)
        enc = getattr(o, "enclosure", None)
        return {
            "key": self.key,
            "quantity": self.quantity,
            "value": _json_num(self.value),
            "error": _json_num(self.error),
            "paper_value": None if pv is None else (_json_num(pv.value) if pv.numeric else pv.value),
            "paper_error": None if pv is None else _json_num(pv.error),
            "paper_sigma": None if pv is None or not pv.numeric else _json_num(pv.sigma),
            "paper_kind": None if pv is None else pv.kind,
            "paper_where": None if pv is None else pv.where,
            "paper_quote": None if pv is None else pv.quote,
            "deviation_value": None if o is None else _json_num(o.deviation),
            "z": None if o is None else _json_num(o.z),
            "verdict": self.verdict,
            "check": self.check or None,
            "tolerance": None if o is None else _json_num(o.tolerance),
            "paper_digit": None if pv is None else _json_num(pv.printed_unit),
            "bound": bound,
            "margin_digits": (
                _json_num(o.deviation / o.unit)
                if o is not None and bound and o.unit and o.deviation is not None
                else None
            ),
            "enclosure": None if enc is None else [_json_num(enc[0]), _json_num(enc[1])],
            "paper": self.paper,
            "computed": self.computed,
            "error_bar": self.error_bar,
            "deviation": self.deviation,
            "explanation": self.explanation,
            "where": self.where,
            "section": section,
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


# ------------------------------------------------------------------------------------ the verdict table


@dataclass(frozen=True)
class Mark:
    """How a row's verdict is shown: ``symbol`` (a tick, a cross or a dash: readable without colour),
    ``label`` (capitals for a disagreement) and ``css`` class (``good``/``bad``/``neutral``)."""

    symbol: str
    label: str
    css: str

    @property
    def text(self) -> str:
        return f"{self.symbol} {self.label}"


def mark(n: Number) -> Mark:
    """The verdict column of a row: a bound says satisfied/VIOLATED (and "(proven)" where an enclosure
    decided it), a value agrees/DISAGREES, an internal check passes/FAILS, the rest is not compared."""
    bound = getattr(n.outcome, "bound", None)
    if bound:
        bad = bound.startswith("violated")
        return Mark("✗" if bad else "✓", bound.upper() if bad else bound, "bad" if bad else "good")
    if n.verdict == "agrees":
        return Mark("✓", "agrees", "good")
    if n.verdict == "disagrees":
        return Mark("✗", "DISAGREES", "bad")
    if n.check == "pass":
        return Mark("✓", "check passes", "good")
    if n.check == "fail":
        return Mark("✗", "check FAILS", "bad")
    return Mark("–", "not compared", "neutral")


def ours_text(n: Number) -> str:
    """Our value with its error bar, short: ``0.909 ± 0.003`` (the error bar's parenthesis, e.g.
    "(bootstrap)", and a check's tolerance are left to the details and the reason)."""
    e = n.error_bar.strip()
    if not e or e.startswith("tolerance"):
        return n.computed
    if e.startswith("+-"):
        return f"{n.computed} ± {e[2:].split(' (')[0].strip()}"
    return f"{n.computed} ± {e}"


def reason_text(n: Number) -> str:
    """The one-line reason of the verdict: the deviation and z, a bound's margin, a check against its
    tolerance; for a value the paper does not state, that it does not."""
    return n.deviation or ("not stated in the paper" if n.paper_value is None else "")


VERDICT_HEADER = ["key", "paper", "ours ± error", "verdict", "reason"]
VERDICT_TITLE = "Verdicts: the paper's numbers beside ours"
DETAILS_TITLE = "Details of each row"
ABOUT_TITLE = "About this run"
LEGEND = (
    "✓ agrees with the paper, or a bound of the paper is satisfied, or an internal check passes; "
    "✗ (in capitals, shaded) disagrees, or a bound is violated, or a check fails; – not compared (not "
    "stated in the paper). A satisfied bound counts as agreeing, a violated one as disagreeing."
)


def verdict_rows(sections: list[Section]) -> list[tuple[Number, list[str]]]:
    """Each row with its cells in the verdict table (:data:`VERDICT_HEADER`)."""
    return [
        (n, [n.key, n.paper.replace(" +- ", " ± "), ours_text(n), mark(n).text, reason_text(n)])
        for s in sections
        for n in s.numbers
    ]


def counts_line(sections: list[Section]) -> str:
    """One line: how many rows agree, disagree (naming them), are not compared; the checks' counts."""
    c = verdict_counts(sections)
    rows = [n for s in sections for n in s.numbers]
    bad = [n.key for n in rows if n.verdict == "disagrees"]
    failed = [n.key for n in rows if n.check == "fail"]
    bad_txt = f" ({', '.join(bad)})" if bad else ""
    failed_txt = f": {', '.join(failed)}" if failed else ""
    line = (
        f"Verdicts: {c['agrees']} agree, {c['disagrees']} disagree{bad_txt}, {c['not compared']} not compared "
        f"(internal checks: {c['check pass']} pass, {c['check fail']} fail{failed_txt})."
    )
    if c["sections failed"]:
        line += f" {c['sections failed']} section(s) FAILED."
    return line


def details_items(n: Number, section: Section) -> list[tuple[str, str]]:
    """The details of a row (below its heading "key: quantity"), as (label, text) pairs: the paper's
    statement and its words, ours in full, the verdict with its reason, how ours was computed, where it
    stands."""
    pv = n.paper_value
    m = mark(n)
    if pv is None:
        items = [("paper", "not stated in the paper")]
    else:
        digit = f"; printed to {pv.printed_unit:g}" if pv.printed_unit else ""
        items = [("paper", f"{n.paper}{digit}: “{pv.quote}”")]
    eb = n.error_bar
    ours = n.computed + ("" if not eb else f"; {eb}" if eb.startswith("tolerance") else f", error bar {eb}")
    enc = getattr(n.outcome, "enclosure", None)
    if enc is not None:
        ours += f"; proven enclosure [{enc[0]!r}, {enc[1]!r}]"
    items.append(("ours", ours))
    items.append(("verdict", f"{m.text}" + (f": {reason_text(n)}" if reason_text(n) else "")))
    if n.explanation:
        items.append(("how", n.explanation))
    items.append(("section", section.title + (f" ({n.where})" if n.where else "")))
    return items


# ------------------------------------------------------------------------------------------ the document


@dataclass
class Document:
    """What the report shows: ``title``, ``intro`` (paragraphs under the title), ``about`` (the run's
    provenance and how verdicts are reached, shown after the verdicts) and the ``sections``."""

    title: str
    intro: list[str]
    about: list[str]
    sections: list[Section]


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


def _md_cell(s) -> str:
    return str(s).replace("|", "\\|").replace("\n", " ")


def _md_table(header, rows) -> str:
    out = ["| " + " | ".join(_md_cell(h) for h in header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(_md_cell(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def _md_row_heading(n: Number) -> str:
    return f"{n.key}: {n.quantity}"


def _md_verdict_table(sections: list[Section]) -> str:
    rows = []
    for n, cells in verdict_rows(sections):
        cells = [f"[{cells[0]}](#{md_slug(_md_row_heading(n))})", *cells[1:]]
        if mark(n).css == "bad":  # bold as well as the cross: visible in any renderer
            cells[3] = f"**{cells[3]}**"
        rows.append(cells)
    return _md_table(VERDICT_HEADER, rows)


def _md_details(sections: list[Section]) -> list[str]:
    lines = [f"## {DETAILS_TITLE}", ""]
    for s in sections:
        for n in s.numbers:
            lines += [f"### {_md_row_heading(n)}", ""]
            lines += [f"* *{label}:* {' '.join(text.split())}" for label, text in details_items(n, s)] + [""]
    return lines


def _md_block(b, out_dir: Path) -> list[str]:
    if b[0] == "p":
        return [b[1], ""]
    if b[0] == "table":
        return [_md_table(b[1], b[2]), ""]
    if b[0] == "fig":
        rel = Path(b[1]).resolve().relative_to(out_dir.resolve())
        return [f"![{b[2]}]({rel.as_posix()})", "", f"*{b[2]}*", ""]
    return ["```", b[1], "```", ""]


def render_markdown(doc: Document, out_dir: Path) -> str:
    """The Markdown twin of the page (figures linked from ``out_dir``), in the same order."""
    secs = doc.sections
    lines = [f"# {doc.title}", ""]
    for p in doc.intro:
        lines += [p, ""]
    lines += [f"**{counts_line(secs)}**", "", f"## {VERDICT_TITLE}", "", LEGEND, "", _md_verdict_table(secs), ""]
    toc = [DETAILS_TITLE, ABOUT_TITLE] + [_heading(s) for s in secs]
    lines += ["Contents:", ""] + [f"* [{h}](#{md_slug(h)})" for h in [VERDICT_TITLE] + toc] + [""]
    lines += _md_details(secs)
    lines += [f"## {ABOUT_TITLE}", ""]
    for p in doc.about:
        lines += [p, ""]
    for s in secs:
        lines += [f"## {_heading(s)}", "", f"*run time {s.seconds:.1f} s*", ""]
        if not s.ok:
            lines += ["```", s.error, "```", ""]
        for b in s.blocks:
            lines += _md_block(b, out_dir)
    return "\n".join(lines) + "\n"


_CSS = """body{font-family:system-ui,sans-serif;max-width:1100px;margin:1.5em auto;padding:0 1em;line-height:1.45}
table{border-collapse:collapse;margin:1em 0;font-size:90%}
td,th{border:1px solid #bbb;padding:3px 6px;vertical-align:top}
th{background:#eee;text-align:left}img{max-width:100%;height:auto}figure{margin:1em 0}
figcaption{font-style:italic;font-size:90%}pre{background:#f6f6f6;padding:.6em;overflow-x:auto}
.scroll{max-width:100%;overflow-x:auto}.failed{color:#b00}.counts{font-weight:bold}
table.verdicts{width:100%}table.verdicts td{overflow-wrap:break-word}
table.verdicts td.key{font-family:ui-monospace,monospace;font-size:95%}
table.verdicts td.verdict{white-space:nowrap;font-weight:bold}
tr.bad td{background:#fdeaea}tr.bad td.key{border-left:4px solid #b00}tr.bad td.verdict{color:#a00}
tr.good td.verdict{color:#060}tr.neutral td.verdict{color:#555;font-weight:normal}
.legend{font-size:90%;color:#333}details{margin:.2em 0;padding:.1em .5em;border-left:4px solid #ddd}
details.bad{border-left-color:#b00}details summary{cursor:pointer}details dl{margin:.3em 0 .6em}
details dt{font-weight:bold;float:left;clear:left;width:5.5em}details dd{margin-left:6em;overflow-wrap:break-word}
nav ul{margin:.2em 0}"""


def _esc(x) -> str:
    return html.escape(str(x))


def _html_table(header, rows) -> str:
    h = "".join(f"<th>{_esc(c)}</th>" for c in header)
    body = "".join("<tr>" + "".join(f"<td>{_esc(c)}</td>" for c in r) + "</tr>" for r in rows)
    return f"<div class='scroll'><table><tr>{h}</tr>{body}</table></div>"


def _html_verdict_table(sections: list[Section]) -> str:
    classes = ("key", "paper", "ours", "verdict", "reason")
    body = []
    for n, cells in verdict_rows(sections):
        tds = [f"<td class='key'><a href='#row-{_esc(n.key)}' title='{_esc(n.quantity)}'>{_esc(n.key)}</a></td>"]
        tds += [f"<td class='{c}'>{_esc(x)}</td>" for c, x in zip(classes[1:], cells[1:])]
        body.append(f"<tr class='{mark(n).css}'>{''.join(tds)}</tr>")
    h = "".join(f"<th>{_esc(c)}</th>" for c in VERDICT_HEADER)
    return f"<table class='verdicts' id='verdict-table'><tr>{h}</tr>{''.join(body)}</table>"


def _html_details(sections: list[Section]) -> str:
    out = [f"<h2 id='details'>{_esc(DETAILS_TITLE)}</h2>"]
    for s in sections:
        for n in s.numbers:
            m = mark(n)
            dl = "".join(f"<dt>{_esc(k)}</dt><dd>{_esc(v)}</dd>" for k, v in details_items(n, s))
            out.append(
                f"<details id='row-{_esc(n.key)}' class='{m.css}'><summary><b>{_esc(n.key)}</b>: "
                f"{_esc(n.quantity)} — {_esc(m.text)}</summary><dl>{dl}</dl></details>"
            )
    return "\n".join(out)


def _html_block(b) -> str:
    if b[0] == "p":
        return f"<p>{_esc(b[1])}</p>"
    if b[0] == "table":
        return _html_table(b[1], b[2])
    if b[0] == "fig":
        data = base64.b64encode(Path(b[1]).read_bytes()).decode()
        return (
            f"<figure><img src='data:image/png;base64,{data}' alt='{_esc(b[2])}'>"
            f"<figcaption>{_esc(b[2])}</figcaption></figure>"
        )
    return f"<pre>{_esc(b[1])}</pre>"


def render_html(doc: Document) -> str:
    """The self-contained page (figures embedded, no outside resource), in the order of the module's
    docstring; no element is wider than the page (wide tables of the sections scroll in their box)."""
    secs = doc.sections
    parts = [
        "<!doctype html><html><head><meta charset='utf-8'>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'>"
        f"<title>{_esc(doc.title)}</title><style>{_CSS}</style></head><body><h1>{_esc(doc.title)}</h1>"
    ]
    parts += [f"<p>{_esc(p)}</p>" for p in doc.intro]
    parts.append(f"<p class='counts'>{_esc(counts_line(secs))}</p>")
    parts += [
        f"<h2 id='verdicts'>{_esc(VERDICT_TITLE)}</h2>",
        f"<p class='legend'>{_esc(LEGEND)}</p>",
        _html_verdict_table(secs),
    ]
    toc = [("verdicts", VERDICT_TITLE), ("details", DETAILS_TITLE), ("about", ABOUT_TITLE)]
    toc += [(f"sec-{s.key}", _heading(s)) for s in secs]
    parts.append(
        "<nav><p>Contents:</p><ul>"
        + "".join(f"<li><a href='#{_esc(a)}'>{_esc(t)}</a></li>" for a, t in toc)
        + "</ul></nav>"
    )
    parts.append(_html_details(secs))
    parts.append(f"<h2 id='about'>{_esc(ABOUT_TITLE)}</h2>")
    parts += [f"<p>{_esc(p)}</p>" for p in doc.about]
    for s in secs:
        cls = "" if s.ok else " class='failed'"
        parts.append(f"<h2 id='sec-{_esc(s.key)}'{cls}>{_esc(_heading(s))}</h2>")
        parts.append(f"<p><i>run time {s.seconds:.1f} s</i></p>")
        if not s.ok:
            parts.append(f"<pre>{_esc(s.error)}</pre>")
        parts += [_html_block(b) for b in s.blocks]
    parts.append("</body></html>")
    return "\n".join(parts)


__all__ = [
    "Outcome",
    "Number",
    "Section",
    "fmt",
    "check_keys",
    "verdict_counts",
    "Mark",
    "mark",
    "ours_text",
    "reason_text",
    "VERDICT_HEADER",
    "VERDICT_TITLE",
    "DETAILS_TITLE",
    "ABOUT_TITLE",
    "LEGEND",
    "verdict_rows",
    "counts_line",
    "details_items",
    "Document",
    "md_slug",
    "render_markdown",
    "render_html",
]
