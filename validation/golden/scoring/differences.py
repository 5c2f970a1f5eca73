"""Expected against got: where an implementation's output first differs from the golden values, as
structured data (docs/reference/golden_commands.md, "What a failing case reports").

A :class:`Difference` is one failure, placed: its kind (:data:`KINDS`), the implementation's file and
line, the golden file and line, the column, the golden and the actual row (or value), the ``|error|``,
the tolerance of that row and their ratio, and -- where the event sequences part -- a few rows of
context from both sides (:class:`ContextRow`), aligned as a diff aligns lines (:func:`align`: by event,
i.e. kind and wall, and by time), so that a missing or an extra row shows as such and a wrong wall or
kind is named as such.  The reports (:mod:`.results`) render it; nothing needs to parse a message.

The scorers give the numbers: :func:`compare_events` and :func:`value_difference` work on a
:class:`Comparison` built by :func:`.cases.score_sequence` (the two sequences and the comparison of one
value with its row's tolerance).  Standard library only.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any

#: The kinds of difference, and what each means.
KINDS = {
    "value": "a value beyond its row's tolerance",
    "n": "the impact counter n differs",
    "wall": "the event is on the other wall",
    "kind": "the event is of another kind (impact, stick or release)",
    "missing-rows": "golden rows that have no counterpart in the output",
    "extra-rows": "output rows that have no counterpart in the golden sequence",
    "points": "the points of an orbit do not match the record's (their number, or their walls)",
    "multipliers": "the number of multipliers differs from the record's",
    "missing-key": "a key the record needs is missing from the output",
    "malformed": "the output file is not in the documented format",
    "no-output": "the output file is missing",
    "crash": "our own track raised an error on the case (check --self)",
}
#: Rows aligned at most, from where the sequences part (each side).
WINDOW = 40
#: Rows of context shown before and after a difference.
CONTEXT = 2
#: Rows of a context shown at most (a longer run of missing or extra rows is cut, and says so).
MAX_CONTEXT = 10


@dataclass
class ContextRow:
    """One line of a diff: ``op`` is ``=`` (the same event, its values within their tolerances), ``~``
    (the same event, some value beyond its tolerance: ``columns``), ``!`` (another event in its place:
    ``columns`` names kind and/or wall), ``-`` (a golden row only), ``+`` (an output row only);
    ``golden_line`` and ``line`` are the rows' lines in the golden and the output file (None where the
    side has no row), ``expected`` and ``actual`` the rows."""

    op: str
    golden_line: int | None
    line: int | None
    expected: dict | None
    actual: dict | None
    columns: list = field(default_factory=list)


@dataclass
class Difference:
    """One failure, placed (module docstring).  Every field but ``kind`` and ``message`` may be None
    where it does not apply: ``line``/``row`` of an output row (for missing rows: the row after the gap,
    None at the end of the file), ``golden_line``/``golden_row`` likewise in the golden file (rows are
    0-based data rows, lines 1-based file lines), ``expected``/``actual`` the two rows (a case) or values
    (an orbit record: the record's interval and the value given), ``count`` the rows missing or extra in
    the first run, ``rows``/``expected_rows`` the lengths of the two sequences, ``expected_status`` how
    the golden orbit ends where a difference lies at its end, ``index`` the point or multiplier of an
    orbit record."""

    kind: str
    message: str
    file: str | None = None
    line: int | None = None
    row: int | None = None
    golden_file: str | None = None
    golden_line: int | None = None
    golden_row: int | None = None
    column: str | None = None
    expected: Any = None
    actual: Any = None
    error: float | None = None
    tolerance: float | None = None
    over_tolerance: float | None = None
    count: int | None = None
    rows: int | None = None
    expected_rows: int | None = None
    expected_status: str | None = None
    index: int | None = None
    context: list = field(default_factory=list)

    def as_dict(self) -> dict:
        """The JSON form: every field (``context`` as a list of objects); non-finite numbers are null."""
        out = {f.name: plain(getattr(self, f.name)) for f in fields(self) if f.name != "context"}
        out["context"] = [{f.name: plain(getattr(c, f.name)) for f in fields(c)} for c in self.context]
        return out


def plain(x):
    """``x`` as the JSON form has it: a float that is not finite is None (in dicts, lists and tuples too,
    a tuple becoming a list)."""
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [plain(v) for v in x]
    return x


def problem(kind: str, message: str, file: str | None, line: int | None = None, column=None) -> Difference:
    """A difference that is not a comparison of values: ``malformed``, ``no-output`` or ``crash``."""
    if kind not in KINDS:
        raise ValueError(f"kind={kind!r} is out of range: allowed one of {', '.join(KINDS)}")
    return Difference(kind, message, file=file, line=line, column=column)


# ------------------------------------------------------------------------------------ impact sequences


@dataclass
class Comparison:
    """What :func:`compare_events` and :func:`value_difference` need of a scored case: the golden
    sequence ``exp`` and the output ``got`` (:class:`..formats.cases.Sequence`), the columns in file order, the
    tolerance columns, and ``compare(column, i, j) -> (|error|, tolerance, outside)`` of a tolerance
    column between golden row ``i`` and output row ``j`` (the row's tolerance; decided exactly)."""

    exp: Any
    got: Any
    columns: tuple
    tolerance_columns: tuple
    compare: Callable[[str, int, int], tuple[float, float, bool]]
    expected_status: str = "active"

    def row(self, side: Any, i: int) -> dict:
        """Row ``i`` of a sequence as a dict (numbers as Python numbers; an absent ``sdot`` None)."""
        out: dict[str, Any] = {}
        for c in self.columns:
            v = getattr(side, c)[i]
            if c == "kind":
                out[c] = str(v)
            elif c in ("n", "wall"):
                out[c] = int(v)
            else:
                out[c] = None if math.isnan(float(v)) else float(v)
        return out

    def event(self, side: Any, i: int) -> tuple:
        return (str(side.kind[i]), int(side.wall[i]))

    def close(self, i: int, j: int) -> tuple[bool, float]:
        """Whether every tolerance value of output row ``j`` is within golden row ``i``'s tolerance, and
        the ``|error|`` of ``tau`` (the alignment's tie-break)."""
        ok = all(not self.compare(c, i, j)[2] for c in self.tolerance_columns)
        err = self.compare("tau", i, j)[0]
        return ok, (err if math.isfinite(err) else 1e300)

    def failing_columns(self, i: int, j: int) -> list[str]:
        """The columns of output row ``j`` that differ from golden row ``i`` (exact or beyond tolerance)."""
        exact = [c for c in self.columns if c not in self.tolerance_columns]
        bad = [c for c in exact if getattr(self.exp, c)[i] != getattr(self.got, c)[j]]
        return sorted(bad + [c for c in self.tolerance_columns if self.compare(c, i, j)[2]], key=self.columns.index)


def align(cmp: Comparison, start: int, window: int = WINDOW) -> list[tuple[str, int | None, int | None]]:
    """The alignment of golden rows ``start..`` with output rows ``start..`` (at most ``window`` of each),
    as diff ops ``(op, i, j)`` (:class:`ContextRow`'s ops; ``i``/``j`` the golden/output row, None on the
    side without one).  Cost: 1 for each ``!``, ``-`` and ``+``, 1/2 for each ``~``; rows beyond the
    window count by the difference of the rows left on each side; among alignments of equal cost, the
    smallest sum of ``|tau|`` differences.  Quadratic in ``window`` (1600 cells at most)."""
    n_exp, n_got = len(cmp.exp), len(cmp.got)
    A, B = min(window, n_exp - start), min(window, n_got - start)
    cost: list[list[tuple[float, float]]] = [[(math.inf, math.inf)] * (B + 1) for _ in range(A + 1)]
    back: list[list[str]] = [[""] * (B + 1) for _ in range(A + 1)]
    cost[0][0] = (0.0, 0.0)
    for i in range(A + 1):
        for j in range(B + 1):
            cands = []
            if i:
                c = cost[i - 1][j]
                cands.append(((c[0] + 1, c[1]), "-"))
            if j:
                c = cost[i][j - 1]
                cands.append(((c[0] + 1, c[1]), "+"))
            if i and j:
                c = cost[i - 1][j - 1]
                gi, gj = start + i - 1, start + j - 1
                if cmp.event(cmp.exp, gi) == cmp.event(cmp.got, gj):
                    ok, dist = cmp.close(gi, gj)
                    cands.append(((c[0] + (0.0 if ok else 0.5), c[1] + dist), "=" if ok else "~"))
                else:
                    cands.append(((c[0] + 1, c[1] + 1e300), "!"))
            if cands:
                cost[i][j], back[i][j] = min(cands, key=lambda x: x[0])
    ends = [(i, j) for i in range(A + 1) for j in range(B + 1) if i == A or j == B]
    rest = lambda i, j: abs((n_exp - start - i) - (n_got - start - j))  # noqa: E731
    i, j = min(ends, key=lambda e: (cost[e[0]][e[1]][0] + rest(*e), cost[e[0]][e[1]][1]))
    ops: list[tuple[str, int | None, int | None]] = []
    while i or j:
        op = back[i][j]
        ops.append((op, start + i - 1 if op != "+" else None, start + j - 1 if op != "-" else None))
        i, j = i - (op != "+"), j - (op != "-")
    return ops[::-1]


def _parting(cmp: Comparison) -> int:
    """The first row whose event (kind, wall) differs, or the length of the shorter sequence."""
    n = min(len(cmp.exp), len(cmp.got))
    return next((k for k in range(n) if cmp.event(cmp.exp, k) != cmp.event(cmp.got, k)), n)


def compare_events(cmp: Comparison) -> tuple[int, Difference | None]:
    """``(p, difference)``: the rows ``0 .. p-1`` pair one to one (the same events, row for row), and
    where the event sequences part the difference (``None`` when they never do: same length, same
    events).  The alignment starts before the first differing event at the first of the rows just
    before it whose values already fail, row for row (a missing or extra row among rows of the same
    event shows first so: the events agree, the times do not)."""
    n_exp, n_got = len(cmp.exp), len(cmp.got)
    k = _parting(cmp)
    if k == n_exp == n_got:
        return k, None
    start = k
    while start > 0 and not cmp.close(start - 1, start - 1)[0]:
        start -= 1
    ops = align(cmp, start)
    first = next((t for t, (op, _, _) in enumerate(ops) if op in "!-+"), None)
    if first is None:  # the difference lies beyond the window: at k, row for row
        ops = [("=" if cmp.close(r, r)[0] else "~", r, r) for r in range(start, k)] + _plain_ops(cmp, k)
        first = k - start
    p = start + first  # before the first edit, the ops are diagonal
    before = [("=" if cmp.close(r, r)[0] else "~", r, r) for r in range(max(0, p - CONTEXT), start)]
    ops = before + ops
    first += len(before)
    return p, _event_difference(cmp, ops, first)


def _plain_ops(cmp: Comparison, k: int) -> list:
    """Ops at ``k`` without an alignment: another event in its place, or the rows left of the longer side."""
    n_exp, n_got = len(cmp.exp), len(cmp.got)
    if k < min(n_exp, n_got):
        return [("!", k, k)]
    if n_exp > n_got:
        return [("-", i, None) for i in range(k, min(n_exp, k + MAX_CONTEXT))]
    return [("+", None, j) for j in range(k, min(n_got, k + MAX_CONTEXT))]


def _context(cmp: Comparison, ops: list, first: int) -> list[ContextRow]:
    """The diff lines around ``ops[first]``: CONTEXT ops before, the first run of edits, CONTEXT after
    (MAX_CONTEXT lines at most)."""
    end = first
    while end < len(ops) and ops[end][0] == ops[first][0]:
        end += 1
    lo = max(0, first - CONTEXT)
    hi = min(len(ops), end + CONTEXT, lo + MAX_CONTEXT)
    out = []
    for op, i, j in ops[lo:hi]:
        cols = cmp.failing_columns(i, j) if op in "~!" and i is not None and j is not None else []
        out.append(
            ContextRow(
                op,
                cmp.exp.line(i) if i is not None else None,
                cmp.got.line(j) if j is not None else None,
                cmp.row(cmp.exp, i) if i is not None else None,
                cmp.row(cmp.got, j) if j is not None else None,
                [c for c in cols if c in ("kind", "wall")] if op == "!" else cols,
            )
        )
    return out


def _describe(row: dict) -> str:
    return f"{row['kind']} (n {row['n']}, wall {row['wall']})"


def _span(lines: list[int]) -> str:
    return f"line {lines[0]}" if len(lines) == 1 else f"lines {lines[0]}-{lines[-1]}"


def _next_row(ops: list, first: int, side: int) -> int:
    """The row of one side (1: golden, 2: output) that comes next at ``ops[first]`` (the ops start on
    the diagonal: their first golden row and output row are the same row)."""
    prev = [o[side] for o in ops[:first] if o[side] is not None]
    return prev[-1] + 1 if prev else (ops[0][1] if ops[0][1] is not None else ops[0][2])


def _event_difference(cmp: Comparison, ops: list, first: int) -> Difference:
    """The :class:`Difference` of the first edit ``ops[first]``: a wrong wall or kind, or a run of
    missing or extra rows."""
    op, i, j = ops[first]
    run = ops[first:]
    run = run[: next((t for t, o in enumerate(run) if o[0] != op), len(run))]
    n_exp, n_got = len(cmp.exp), len(cmp.got)
    got_path, exp_path = str(cmp.got.path), str(cmp.exp.path)
    common: dict[str, Any] = dict(file=got_path, golden_file=exp_path, rows=n_got, expected_rows=n_exp)
    context = _context(cmp, ops, first)
    if op == "!":
        assert i is not None and j is not None
        e, a = cmp.row(cmp.exp, i), cmp.row(cmp.got, j)
        kind = "kind" if e["kind"] != a["kind"] else "wall"
        what = f"{a[kind]} instead of {e[kind]}" + (": an event on the other wall" if kind == "wall" else "")
        msg = f"{kind} at line {cmp.got.line(j)} ({what}; golden line {cmp.exp.line(i)}: {_describe(e)})"
        return Difference(
            kind, msg, line=cmp.got.line(j), row=j, golden_line=cmp.exp.line(i), golden_row=i, column=kind,
            expected=e, actual=a, context=context, **common,
        )  # fmt: skip
    if op == "-":
        rows_i = [o[1] for o in run]
        after = _next_row(ops, first, 2)  # the output row after the gap
        at_end = after >= n_got  # the output has ended: every golden row from there on is missing
        if at_end:
            rows_i = list(range(rows_i[0], n_exp))
        where = "at the end of the file" if at_end else f"before line {cmp.got.line(after)}"
        shown = [cmp.row(cmp.exp, r) for r in rows_i]
        msg = (
            f"{len(rows_i)} golden row{'s' if len(rows_i) > 1 else ''} missing {where} "
            f"(golden {_span([cmp.exp.line(r) for r in rows_i])}: {', '.join(_describe(r) for r in shown[:3])}"
            f"{', ...' if len(shown) > 3 else ''})"
        )
        return Difference(
            "missing-rows", msg, line=None if at_end else cmp.got.line(after), row=None if at_end else after,
            golden_line=cmp.exp.line(rows_i[0]), golden_row=rows_i[0], expected=shown[0], count=len(rows_i),
            expected_status=cmp.expected_status if at_end else None, context=context, **common,
        )  # fmt: skip
    rows_j = [o[2] for o in run]
    nxt = _next_row(ops, first, 1)  # the golden row after the extra rows
    past_end = nxt >= n_exp  # the golden sequence has ended: every output row from there on is extra
    if past_end:
        rows_j = list(range(rows_j[0], n_got))
    shown = [cmp.row(cmp.got, r) for r in rows_j]
    msg = (
        f"{len(rows_j)} extra row{'s' if len(rows_j) > 1 else ''} at {_span([cmp.got.line(r) for r in rows_j])} "
        f"({', '.join(_describe(r) for r in shown[:3])}{', ...' if len(shown) > 3 else ''})"
        + (
            f": the golden sequence ends before them ({cmp.expected_status})"
            if past_end
            else f", not in the golden sequence (next golden row: line {cmp.exp.line(nxt)})"
        )
    )
    return Difference(
        "extra-rows", msg, line=cmp.got.line(rows_j[0]), row=rows_j[0],
        golden_line=None if past_end else cmp.exp.line(nxt), golden_row=nxt if not past_end else n_exp,
        actual=shown[0], count=len(rows_j), expected_status=cmp.expected_status if past_end else None,
        context=context, **common,
    )  # fmt: skip


def value_difference(cmp: Comparison, column: str, row: int, p: int, context: bool = True) -> Difference:
    """The :class:`Difference` of ``column`` at row ``row`` of the paired rows (``row < p``): an ``n``
    that differs or a value beyond its row's tolerance, with the rows around it (``context``)."""
    e, a = cmp.row(cmp.exp, row), cmp.row(cmp.got, row)
    line, gline = cmp.got.line(row), cmp.exp.line(row)
    common: dict[str, Any] = dict(
        file=str(cmp.got.path), line=line, row=row, golden_file=str(cmp.exp.path), golden_line=gline,
        golden_row=row, column=column, expected=e, actual=a, rows=len(cmp.got), expected_rows=len(cmp.exp),
    )  # fmt: skip
    ctx = []
    if context:
        ops = [("=" if not cmp.failing_columns(r, r) else "~", r, r) for r in range(max(0, row - CONTEXT), p)]
        ctx = _context(cmp, ops, row - max(0, row - CONTEXT))[: 2 * CONTEXT + 1]
    if column not in cmp.tolerance_columns:
        msg = f"{column} at line {line} ({a[column]} instead of {e[column]})"
        return Difference(column if column in KINDS else "value", msg, context=ctx, **common)
    err, tol, _ = cmp.compare(column, row, row)
    ratio = err / max(tol, 1e-300)
    msg = f"{column} at line {line} (|error| {err:.3g}, {ratio:.3g} x tolerance)"
    return Difference(
        "value", msg, error=err, tolerance=tol, over_tolerance=ratio, context=ctx, **common
    )  # fmt: skip


def show(x) -> str:
    """A value as the reports print it: integers and words as they are, floats as the shortest text that
    reads back to them (``repr``), an absent value as nothing."""
    if x is None:
        return ""
    if isinstance(x, float):
        return repr(x)
    return str(x)
