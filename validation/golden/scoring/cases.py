"""A case scored (docs/reference/golden_commands.md, "What a failing case reports"; docs/golden_tolerances.md): an
implementation's impact sequence against ``expected.csv``, column by column, each value against its row's tolerance
(decided exactly, in rationals), where the event sequences part (:func:`.differences.compare_events`), and the digits
of accuracy.  The score of a case is a :class:`CaseScore`; :mod:`.results` makes it the case's result.  Only numpy:
``gear-rattle check`` scores anywhere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import numpy as np

from ..formats.cases import COLUMNS, EXACT_COLUMNS, TOLERANCE_COLUMNS, Case, Sequence, read_sequence
from .differences import Comparison, Difference, compare_events, problem, value_difference


#: Digits of accuracy are capped here (a float64 carries ~16-17).
DIGITS_CAP = 17.0
TWO_PI = 2.0 * math.pi


@dataclass
class ColumnScore:
    column: str
    passed: bool
    max_error: float  # largest |x - e| (circular_distance for tau_mod_2pi; mismatch count for exact columns)
    worst_row: int  # 0-based data row of the largest |error| / tolerance (exact columns: first mismatch), -1 if none
    digits: float  # min over rows of -log10(relative error), capped at DIGITS_CAP
    first_row: int = -1  # 0-based data row of the first failure, -1 if none
    worst_ratio: float = 0.0  # |error| / tolerance on worst_row (inf for a missing value, 0 for exact columns)


@dataclass
class CaseScore:
    """The score of one case.  ``columns`` are scored over the first ``compared_rows`` rows: those that
    pair one to one with the golden rows (all of them, unless the event sequences part: then the rows
    before the first missing, extra or other event).  ``first_row`` is the 0-based golden row of the
    first failure (-1 when the case passes), ``level`` the case's level, ``no_output`` true when the
    output file is missing.  ``first_failing`` is the first failure, placed and structured
    (:class:`.differences.Difference`: file, line, column, expected and actual rows, error, tolerance);
    ``event_difference`` where the event sequences part (None when they do not), and ``worst`` the value
    furthest beyond its tolerance (None when none is, or it is the first failing one); ``message`` is the
    one-line note of the table."""

    case: str
    passed: bool
    columns: dict
    message: str = ""
    level: int | None = None
    first_row: int = -1
    no_output: bool = False
    first_failing: Difference | None = None
    event_difference: Difference | None = None
    worst: Difference | None = None
    compared_rows: int = 0

    @property
    def digits(self) -> float:
        if not self.columns or not self.compared_rows:  # no row compared value by value
            return 0.0
        return min((c.digits for k, c in self.columns.items() if k in TOLERANCE_COLUMNS), default=DIGITS_CAP)

    @property
    def column_digits(self) -> dict:
        """Digits of accuracy per tolerance column (``{}`` when no row was compared)."""
        if not self.compared_rows:
            return {}
        return {k: c.digits for k, c in self.columns.items() if k in TOLERANCE_COLUMNS}

    @property
    def worst_ratio(self) -> float | None:
        """The largest ``|error| / tolerance`` over the tolerance columns (``None`` when no row was compared)."""
        ratios = [c.worst_ratio for k, c in self.columns.items() if k in TOLERANCE_COLUMNS]
        return max(ratios) if ratios and self.compared_rows else None


def no_output_score(case: Case, path) -> CaseScore:
    """The score of a case whose output file is missing: it fails ("no output"), the run goes on."""
    msg = f"no output ({path} missing)"
    return CaseScore(case.id, False, {}, msg, case.level, 0, True, problem("no-output", msg, str(path)))


def problem_score(case: Case, kind: str, message: str, path=None, line=None, column=None) -> CaseScore:
    """The score of a case whose output could not be scored: ``malformed`` (its file is not in the
    format: an error of this case only) or ``crash`` (our own track raised on it)."""
    diff = problem(kind, message, None if path is None else str(path), line, column)
    return CaseScore(case.id, False, {}, message, case.level, 0, False, diff)


def accuracy_digits(err: np.ndarray, scale: np.ndarray) -> float:
    """``min(DIGITS_CAP, -log10(max(err / |scale|)))``; where the scale (the golden value) is 0 it is 1
    (the absolute error); no error at all gives DIGITS_CAP."""
    if err.size == 0:
        return DIGITS_CAP
    sc = np.abs(scale)
    rel = err / np.where(sc > 0, sc, 1.0)
    worst = float(np.max(rel))
    if worst <= 0.0:
        return DIGITS_CAP
    return float(min(DIGITS_CAP, -math.log10(worst)))


def _pi_fixed(bits: int) -> int:
    """``pi 2^bits`` rounded down, to within one unit, by Machin's formula in integers (32 guard bits)."""
    guard = 32
    one = 1 << (bits + guard)

    def atan_inv(x: int) -> int:  # atan(1/x) * one
        total = term = one // x
        k, x2 = 1, x * x
        while term:
            term //= x2
            total += (-1) ** k * (term // (2 * k + 1))
            k += 1
        return total

    return (4 * (4 * atan_inv(5) - atan_inv(239))) >> guard


#: 2 pi as an integer multiple of 2^-TWO_PI_BITS (error < 2^-1199): the reduction of any float64
#: difference (``|d| < 2^1025``) is then exact to 2^-170, far below any distance a float64 can show.
TWO_PI_BITS = 1200
_TWO_PI_FIXED = 2 * _pi_fixed(TWO_PI_BITS)


def circular_distance_exact(d: Fraction) -> Fraction:
    """``|d - 2 pi round(d / 2 pi)|`` for a rational ``d``, with 2 pi to 1200 bits (error below
    ``|d| 2^-1199``)."""
    num, den = d.numerator << TWO_PI_BITS, d.denominator * _TWO_PI_FIXED  # d / 2 pi = num / den
    k = (2 * num + den) // (2 * den)  # nearest integer
    return abs(Fraction((d.numerator << TWO_PI_BITS) - k * _TWO_PI_FIXED * d.denominator, d.denominator << TWO_PI_BITS))


def _circular_distance_1(x: float, g: float) -> float:
    """``|d - 2 pi round(d / 2 pi)|`` with ``d = x - g`` exactly (rationals), correctly rounded."""
    if not (math.isfinite(x) and math.isfinite(g)):
        return math.nan
    return float(circular_distance_exact(Fraction(x) - Fraction(g)))  # x - g: exact, a dyadic rational


def outside_tolerance(x: float, golden: float, abs_tol: float, rel_tol: float, circular: bool = False) -> bool:
    """``|x - golden| > abs_tol + rel_tol |golden|`` decided **exactly** on the float64 numbers (rationals;
    the circular distance for a phase): no rounding can pass a value outside its tolerance.  A NaN or
    infinite ``x`` is outside."""
    if not math.isfinite(x):
        return True
    d = Fraction(x) - Fraction(golden)
    err = circular_distance_exact(d) if circular else abs(d)
    return err > Fraction(abs_tol) + Fraction(rel_tol) * abs(Fraction(golden))


def circular_distance(a, b) -> np.ndarray:
    """Distance between phases on the circle of length 2 pi, in [0, pi], for any finite inputs.

    The difference ``d = a - b`` is reduced **exactly** (rational arithmetic with 2 pi to 1200 bits),
    so the distance is the true one, correctly rounded, however large ``a`` is: a phase printed as
    2 pi (rounding just below it), -0.0 or unreduced denotes the phase it is congruent to, and a wrong
    value (1e17, 1e300, the largest double) is compared as the phase it really denotes, never closer.
    In float64, ``|d - 2 pi round(d / 2 pi)|`` is 0 for every ``|d|`` above ~1e16.  NaN and inf
    give NaN.
    """
    x, y = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    out = [_circular_distance_1(float(u), float(v)) for u, v in zip(x.ravel(), y.ravel())]
    return np.asarray(out, dtype=float).reshape(x.shape)


def _comparison(case: Case, got: Sequence) -> Comparison:
    """The golden and the output rows, and the comparison of a tolerance value with its row's tolerance
    (decided exactly where the float64 distance is within 1e-9 of the tolerance, as :func:`_score_column`)."""
    exp = case.expected
    tols = {c: case.row_tolerances(c) for c in TOLERANCE_COLUMNS}

    def compare(column: str, i: int, j: int) -> tuple[float, float, bool]:
        a, e = float(getattr(got, column)[j]), float(getattr(exp, column)[i])
        abs_tol, rel = tols[column]
        if math.isnan(e):  # a stick or release row: no velocity to compare
            return (0.0, 0.0, False) if math.isnan(a) else (math.inf, 0.0, True)
        allowed = float(abs_tol[i]) + rel * abs(e)
        circular = column == "tau_mod_2pi"
        err = _circular_distance_1(a, e) if circular else abs(a - e)
        err = math.inf if math.isnan(err) else err
        if err < allowed * (1.0 - 1e-9) and allowed > 1e-280:
            return err, allowed, False
        return err, allowed, outside_tolerance(a, e, float(abs_tol[i]), rel, circular)

    return Comparison(exp, got, COLUMNS, TOLERANCE_COLUMNS, compare, str(case.settings.get("expected_status")))


def score_sequence(case: Case, got: Sequence) -> CaseScore:
    """Score one output against a case: where the event sequences part (:func:`.differences.compare_events`),
    then pass/fail per column and digits of accuracy over the rows before it."""
    exp = case.expected
    cmp = _comparison(case, got)
    p, event = compare_events(cmp)
    cols: dict[str, ColumnScore] = {}
    for c in EXACT_COLUMNS:
        a, e = getattr(got, c)[:p], getattr(exp, c)[:p]
        bad = np.nonzero(a != e)[0]
        i0 = int(bad[0]) if bad.size else -1
        cols[c] = ColumnScore(c, bad.size == 0, float(bad.size), i0, DIGITS_CAP if bad.size == 0 else 0.0, i0)
    for c in TOLERANCE_COLUMNS:
        abs_tol, rel_tol = case.row_tolerances(c)
        cols[c] = _score_column(c, abs_tol[:p], rel_tol, getattr(got, c)[:p], getattr(exp, c)[:p])
    if event is None and all(s.passed for s in cols.values()):
        return CaseScore(case.id, True, cols, "", case.level, -1, compared_rows=p)
    bad_cols = [s for s in cols.values() if not s.passed]
    if bad_cols:
        f = min(bad_cols, key=lambda s: (s.first_row, COLUMNS.index(s.column)))
        first = value_difference(cmp, f.column, f.first_row, p)
    else:
        assert event is not None, "a failing case has a failing column or an event difference"
        first = event
    tol_bad = [s for s in bad_cols if s.column in TOLERANCE_COLUMNS]
    w = max(tol_bad, key=lambda s: s.worst_ratio) if tol_bad else None
    worst = None
    if w is not None and (w.column, w.worst_row) != (first.column, first.golden_row):
        worst = value_difference(cmp, w.column, w.worst_row, p, context=False)
    note = f"first failing: {first.message}" + (f"; worst: {worst.message}" if worst else "")
    if event is not None and event is not first:
        note += f"; the events part: {event.message}"
    if len(got) != len(exp):
        note = f"wrong number of events: {len(got)} rows, expected {len(exp)}; {note}"
    assert first.golden_row is not None, "a row difference names its golden row"
    return CaseScore(
        case.id, False, cols, f"{note} of {got.path}", case.level, first.golden_row,
        first_failing=first, event_difference=event, worst=worst, compared_rows=p,
    )  # fmt: skip


def _score_column(c: str, abs_tol: np.ndarray, rel_tol: float, a: np.ndarray, e: np.ndarray) -> ColumnScore:
    """One tolerance column (``abs_tol``: the absolute tolerance of each row, ``rel_tol`` the relative one):
    pass/fail, largest error, first and worst failing rows, digits."""
    if c == "sdot":
        mask = ~np.isnan(e)  # stick/release rows have no velocity
        missing = np.nonzero(mask & np.isnan(a))[0]  # (files cannot have one: the parser refuses NaN on impacts)
    else:
        mask = np.ones(e.shape, dtype=bool)
        missing = np.empty(0, dtype=np.int64)
    diff = circular_distance(a, e) if c == "tau_mod_2pi" else np.abs(a - e)
    diff = np.where(mask, diff, 0.0)
    diff = np.where(np.isnan(diff), np.inf, diff)
    allowed = abs_tol + rel_tol * np.abs(np.where(mask, e, 0.0))
    ratio = np.where(mask, diff / np.maximum(allowed, 1e-300), 0.0)
    # pass/fail exactly (rationals), not by the rounded float64 differences above; those decide only
    # rows certainly inside (1e-9 below the tolerance: the roundings are ~1e-16 relative)
    near = mask & ~((diff < allowed * (1.0 - 1e-9)) & (allowed > 1e-280))
    failing = np.array(
        [
            i
            for i in np.nonzero(near)[0]
            if outside_tolerance(float(a[i]), float(e[i]), float(abs_tol[i]), rel_tol, c == "tau_mod_2pi")
        ],
        dtype=np.int64,
    )
    ok = failing.size == 0
    # the largest |error| / tolerance, passing or not (each row against its own tolerance)
    worst = int(missing[0]) if missing.size else (int(np.argmax(ratio)) if mask.any() else -1)
    # relative error; the scale is 2 pi for the phase and at least 1 for the elapsed time
    scale = np.full(e.shape, TWO_PI) if c == "tau_mod_2pi" else (np.maximum(np.abs(e), 1.0) if c == "tau" else e)
    return ColumnScore(
        c,
        ok,
        float(np.max(diff[mask])) if mask.any() else 0.0,
        worst,
        accuracy_digits(diff[mask], scale[mask]),
        int(failing[0]) if failing.size else -1,
        float(ratio[worst]) if worst >= 0 else 0.0,
    )


def score_file(case: Case, path: str | Path) -> CaseScore:
    """Read ``path`` strictly and score it (a different number of events fails the case)."""
    got = read_sequence(path)
    return score_sequence(case, got)
