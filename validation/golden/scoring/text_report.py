"""What ``gear-rattle check`` prints (docs/reference/golden_commands.md, "What a failing case reports"): the aligned table
(one line per case or record scored), the details of each failure -- expected against got, with the
rows around it as a diff shows them -- and the summary line (:func:`report_text`).  Built from the typed
results of :mod:`.results` alone (the JUnit failures carry the same details: :mod:`.junit`).  A number
shows as the JSON document has it (:func:`.differences.plain`: not finite, nothing).  Standard library
only.
"""

from __future__ import annotations

from ..formats.cases import COLUMNS as ROW_COLUMNS, TOLERANCE_COLUMNS as CASE_COLUMNS
from ..formats.orbits import COLUMNS as ORBIT_COLUMNS
from .differences import ContextRow, Difference, plain, show
from .results import FAILING, CaseResult, CheckRun, Result

__all__ = [
    "WORDS",
    "ONE_LINE",
    "aligned",
    "table",
    "summary_line",
    "context_lines",
    "details",
    "details_block",
    "report_text",
]

#: The table's word for each verdict.
WORDS = {"pass": "PASS", "fail": "FAIL", "error": "ERROR", "xfail": "XFAIL", "xpass": "XPASS", "skipped": "SKIP"}


def aligned(rows: list[list[str]], right: set[int]) -> list[str]:
    """Lines of ``rows`` (the first is the header) in columns as wide as their widest cell, two spaces
    apart (columns in ``right`` right-aligned; the last column is not padded)."""
    widths = [max(len(r[k]) for r in rows) for k in range(len(rows[0]))]
    out = []
    for r in rows:
        cells = [
            c.rjust(w) if k in right else (c if k == len(r) - 1 else c.ljust(w))
            for k, (c, w) in enumerate(zip(r, widths))
        ]
        out.append("  ".join(cells).rstrip())
    return out


def _digits_cell(d: float | None) -> str:
    return "-" if d is None else f"{d:.1f}"


def table(results: list[Result], orbits: bool = False) -> list[str]:
    """The table's lines: header, rule, one line per result scored (skipped ones are counted in the
    summary line instead; columns aligned for any id length)."""
    cols = ORBIT_COLUMNS if orbits else CASE_COLUMNS
    names = {"tau_mod_2pi": "tau%2pi", "multipliers": "mult"}
    head = ["orbit / bifurcation point" if orbits else "case", "result", *(names.get(c, c) for c in cols)]
    head += ["note"] if orbits else ["n/wall/kind", "note"]
    rows = [head]
    for r in results:
        if r.verdict == "skipped":
            continue
        row = [r.id, WORDS[r.verdict], *(_digits_cell(r.digits[c]) for c in cols)]
        if not orbits:
            assert isinstance(r, CaseResult), "a case's result"
            row.append(
                "ok" if r.exact_columns_match else ("MISMATCH" if r.compared_rows or r.event_difference else "-")
            )
        rows.append(row + [r.note])
    lines = aligned(rows, right=set(range(2, 2 + len(cols))))
    return [lines[0], "-" * len(lines[0])] + lines[1:]


def summary_line(results: list[Result], orbits: bool = False, suite: str = "") -> str:
    """``N/M cases pass, K skipped (suite ...; digits ...)`` (M: the cases scored) and the ids of those
    that fail the run: ``; failing: a, b``, ``; errors: c``, ``; known failures that now pass: d``
    (``suite``: the suite's version label, so that ``--summary`` alone says what was scored against)."""
    scored = [r for r in results if r.verdict != "skipped"]
    n_pass = sum(r.verdict == "pass" for r in scored)
    what = "orbits and bifurcation points" if orbits else "cases"
    scale = (
        "min over values of -log10 of the error relative to the scale"
        if orbits
        else "min over rows of -log10 relative error"
    )
    extra = ""
    n_skip, n_xfail = len(results) - len(scored), sum(r.verdict == "xfail" for r in scored)
    if n_xfail:
        extra += f", {n_xfail} known failure{'s' if n_xfail > 1 else ''} (xfail)"
    if n_skip:
        extra += f", {n_skip} skipped"
    line = (
        f"{n_pass}/{len(scored)} {what} pass{extra} "
        f"({f'golden suite {suite}; ' if suite else ''}digits: {scale}, capped at 17)"
    )
    for verdict, label in (("fail", "failing"), ("error", "errors"), ("xpass", "known failures that now pass")):
        ids = [r.id for r in scored if r.verdict == verdict]
        line += f"; {label}: {', '.join(ids)}" if ids else ""
    return line


# ------------------------------------------------------------------------------------------ details


def _headline(r: Result, first: Difference) -> str:
    where = f" of {first.file}" if first.file and first.kind not in ("no-output", "malformed") else ""
    return f"{WORDS[r.verdict]} {r.id}: {first.message or r.note}{where}"


def _expected_got(d: Difference) -> list[str]:
    """``expected X (golden line L), got Y: |error| E, tolerance T (this row's), M x`` of a value."""
    col = d.column
    if d.kind not in ("value", "n", "wall", "kind") or col is None:
        return []
    e, a = plain(d.expected), plain(d.actual)
    ev = e.get(col) if isinstance(e, dict) and col in e else e
    av = a.get(col) if isinstance(a, dict) and col in a else a
    gl = f" (golden line {d.golden_line})" if d.golden_line is not None else ""
    line = f"  {col}: expected {show(ev)}{gl}, got {show(av)}"
    error, tolerance, ratio = plain(d.error), plain(d.tolerance), plain(d.over_tolerance)
    if error is not None and tolerance is not None:
        line += f": |error| {error:.3g}, tolerance {tolerance:.3g}"
        line += " (this row's)" if isinstance(e, dict) else ""
        line += f", {ratio:.3g} x" if ratio is not None else ", infinitely many times"
    return [line]


def context_lines(context: list[ContextRow]) -> list[str]:
    """A diff of rows: `` `` both sides agree, ``-`` a golden row, ``+`` an output row; a row of the same
    event whose values differ (``~``) or another event in its place (``!``) shows as ``-`` then ``+``,
    with the columns that differ named at the end."""
    if not context:
        return []
    rows = [["", "golden", "output", *ROW_COLUMNS, ""]]

    def cells(mark, gline, line, row, note=""):
        row = plain(row)
        return [mark, show(gline) or "", show(line) or "", *(show(row.get(c)) for c in ROW_COLUMNS), note]

    for c in context:
        op = c.op
        if op == "=":
            rows.append(cells(" ", c.golden_line, c.line, c.actual))
        elif op == "-":
            rows.append(cells("-", c.golden_line, None, c.expected, "golden only"))
        elif op == "+":
            rows.append(cells("+", None, c.line, c.actual, "output only"))
        else:
            rows.append(cells("-", c.golden_line, None, c.expected))
            rows.append(cells("+", None, c.line, c.actual, "<- " + ", ".join(c.columns)))
    return ["    " + line for line in aligned(rows, right={1, 2, 3, 6})]


def _diff_lines(d: Difference) -> list[str]:
    """The context of a difference, and how many of its missing or extra rows it does not show."""
    context = d.context
    out = context_lines(context)
    op = {"missing-rows": "-", "extra-rows": "+"}.get(d.kind)
    hidden = (d.count or 0) - sum(c.op == op for c in context) if op else 0
    what = "golden rows missing" if op == "-" else "extra rows"
    return out + ([f"    ... {hidden} more {what} (not shown)"] if hidden > 0 else [])


def details(r: Result) -> list[str]:
    """The details of a result that fails the run (or is a known failure): the first failure, expected
    against got, the rows around it, and where other than there the event sequences part and the worst
    value; ``[note]`` where there is nothing structured to show."""
    first = r.first_failing
    if first is None:
        return [f"{WORDS[r.verdict]} {r.id}: {r.note}"]
    out = [_headline(r, first)]
    if first.golden_file:
        out.append(f"  golden: {first.golden_file}")
    out += _expected_got(first)
    out += _diff_lines(first)
    event = r.event_difference if isinstance(r, CaseResult) else None
    if event is not None and event.message != first.message:
        out.append(f"  then the event sequences part: {event.message}")
        out += _diff_lines(event)
    worst = r.worst if isinstance(r, CaseResult) else None
    if worst is not None:
        out.append(f"  worst: {worst.message}")
        out += _expected_got(worst)
    if r.verdict in ("xfail", "xpass"):
        out.append(f"  known failure: {r.reason}")
    return out


#: Kinds of failure whose note says it all (the table's line, and stderr for a malformed file).
ONE_LINE = ("no-output", "malformed")


def details_block(results: list[Result]) -> list[str]:
    """The details of every result that fails the run on its values or events, one block each, a blank
    line before each (a missing or malformed file has its table line only)."""
    out: list[str] = []
    for r in results:
        if r.verdict in FAILING and (r.first_failing.kind if r.first_failing else None) not in ONE_LINE:
            out += ["", *details(r)]
    return out


def report_text(run: CheckRun, summary_only: bool = False) -> str:
    """What ``check`` prints on stdout: the suite's line, the table, the details of each failure and the
    summary line (with ``summary_only``, the summary line alone)."""
    results = list(run.results)
    lines = [summary_line(results, run.orbits, run.suite.label)]
    if not summary_only:
        blocks = details_block(results)
        lines = [f"suite: {run.suite.line()}", *table(results, run.orbits), *blocks, *([""] if blocks else []), *lines]
    return "\n".join(lines) + "\n"
