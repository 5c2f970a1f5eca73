"""An orbit record scored (``gear-rattle check --orbits``; docs/reference/golden_commands.md, "Periodic orbit
records"): an implementation's values (:class:`.formats.orbits.Values`) against a record's intervals.

The points may start anywhere on the orbit (the rotation that matches the record's walls and is closest
is used) and the multipliers may come in any order (the closest pairing is used).  A value passes when
its distance to the record's interval is at most the record's tolerance for its column, decided exactly
(rationals); phases are compared on the circle.  The score of a record is an :class:`OrbitScore`;
:mod:`.results` makes it the record's result.  Only numpy: scoring runs anywhere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from ..formats.orbits import COLUMNS, LEVEL, Record, Values, required
from .cases import DIGITS_CAP, TWO_PI, circular_distance_exact
from .differences import Difference, problem


@dataclass
class Column:
    column: str
    passed: bool
    error: float  # largest distance to the record's interval
    tolerance: float
    digits: float  # -log10(largest error / scale), capped at DIGITS_CAP
    index: int = -1  # the record's point or multiplier (0 for value) with the largest error
    expected: object = None  # its interval: [lo, hi], or {"re": [lo, hi], "im": [lo, hi]} for a multiplier
    actual: object = None  # the value given for it (a multiplier: {"re", "im"})
    where: tuple = ()  # its place in the output file (a JSON path)


@dataclass
class OrbitScore:
    """The score of one record; ``level`` is :data:`..formats.orbits.LEVEL`, ``no_output`` true when the file is missing."""

    id: str
    passed: bool
    columns: dict = field(default_factory=dict)
    message: str = ""
    level: int = LEVEL
    no_output: bool = False
    #: The first failure, placed and structured (:class:`.differences.Difference`), None when it passes.
    first_failing: Difference | None = None

    @property
    def column_digits(self) -> dict:
        """Digits of accuracy per scored column."""
        return {k: c.digits for k, c in self.columns.items()}

    @property
    def worst_ratio(self) -> float | None:
        """The largest error / tolerance over the scored columns (``None`` when none was scored)."""
        ratios = [
            c.error / c.tolerance if c.tolerance > 0 else (math.inf if c.error > 0 else 0.0)
            for c in self.columns.values()
        ]
        return max(ratios) if ratios else None


def no_output_score(rec: Record, path) -> OrbitScore:
    """The score of a record whose output file is missing: it fails ("no output"), the run goes on."""
    msg = f"no output ({path} missing)"
    return OrbitScore(rec.id, False, {}, msg, LEVEL, True, problem("no-output", msg, str(path)))


def problem_score(rec: Record, kind: str, message: str, path=None, line=None, column=None) -> OrbitScore:
    """The score of a record whose output could not be scored (``malformed``: an error of this record)."""
    diff = problem(kind, message, None if path is None else str(path), line, column)
    return OrbitScore(rec.id, False, {}, message, LEVEL, False, diff)


def _dist(x, lo, hi, circular=False) -> list:
    """The exact distance (rationals) of each float64 ``x`` to its interval ``[lo, hi]`` (on the
    circle: to the arc of the interval)."""
    out = []
    for xi, a, b in zip(*(np.asarray(v, float).ravel() for v in (x, lo, hi))):
        fx, fa, fb = Fraction(float(xi)), Fraction(float(a)), Fraction(float(b))
        if circular:
            out.append(max(circular_distance_exact(fx - (fa + fb) / 2) - (fb - fa) / 2, Fraction(0)))
        else:
            out.append(max(fa - fx, fx - fb, Fraction(0)))
    return out


def _digits(err: list, scale: float) -> float:
    worst = float(max(err)) / scale if err else 0.0
    return DIGITS_CAP if worst <= 0 else float(min(DIGITS_CAP, -math.log10(worst)))


def _column(name: str, err: list, tol: float, scale: float, expected=(), actual=(), where=()) -> Column:
    """Passes when the largest error is at most the tolerance, decided exactly; ``expected``, ``actual``
    and ``where`` (per item: the record's interval, the value given, its JSON path) name the worst item."""
    e = max(err) if err else Fraction(0)
    k = err.index(e) if err else -1
    pick = lambda xs: xs[k] if 0 <= k < len(xs) else None  # noqa: E731
    return Column(
        name, bool(e <= Fraction(tol)), float(e), tol, _digits(err, scale), k, pick(expected), pick(actual),
        pick(where) or (),
    )  # fmt: skip


def _score_points(rec: Record, got: Values, cols: dict) -> str:
    points, walls = got.points, got.walls
    assert points is not None and walls is not None, "an output's points carry their walls (values_from_doc)"
    n = rec.points.shape[0]
    if points.shape[0] != n:
        return f"{points.shape[0]} points, expected {n} (impacts per period)"
    best = None
    for k in range(n):  # rotation: got[(i + k) % n] <-> record[i]
        idx = (np.arange(n) + k) % n
        if not np.array_equal(walls[idx], rec.walls):
            continue
        et = _dist(points[idx, 0], rec.points[:, 0], rec.points[:, 1], circular=True)
        es = _dist(points[idx, 1], rec.points[:, 2], rec.points[:, 3])
        if best is None or max(et + es) < max(best[0] + best[1]):
            best = (et, es, idx)
    if best is None:
        return "the walls of the points match no rotation of the record's walls"
    et, es, idx = best
    for c, err, scale, k in (
        ("tau_mod_2pi", et, TWO_PI, 0),
        ("sdot", es, float(np.abs(rec.points[:, 2:]).max()), 1),
    ):
        exp = [[float(rec.points[i, 2 * k]), float(rec.points[i, 2 * k + 1])] for i in range(n)]
        act = [float(points[idx[i], k]) for i in range(n)]
        cols[c] = _column(c, err, rec.tolerances[c], scale, exp, act, [("points", int(idx[i]), c) for i in range(n)])
    return ""


def _score_multipliers(rec: Record, got: Values, cols: dict) -> str:
    m, got_m = rec.multipliers, got.multipliers
    assert got_m is not None, "scored where given"
    if got_m.size != m.shape[0]:
        return f"{got_m.size} multipliers, expected {m.shape[0]}"
    best: tuple | None = None
    for perm in ([0, 1], [1, 0]) if m.shape[0] == 2 else [list(range(m.shape[0]))]:
        z = got_m[perm]
        e = [max(u, v) for u, v in zip(_dist(z.real, m[:, 0], m[:, 1]), _dist(z.imag, m[:, 2], m[:, 3]))]
        if best is None or max(e) < max(best[0]):
            best = (e, perm)
    assert best is not None, "one permutation at least"
    err, perm = best
    exp = [{"re": [float(r[0]), float(r[1])], "im": [float(r[2]), float(r[3])]} for r in m]
    act = [{"re": float(got_m[k].real), "im": float(got_m[k].imag)} for k in perm]
    where = [("multipliers", int(k)) for k in perm]
    scale = max(1.0, float(np.abs(m).max()))
    cols["multipliers"] = _column("multipliers", err, rec.tolerances["multipliers"], scale, exp, act, where)
    return ""


def score_values(rec: Record, got: Values) -> OrbitScore:
    """Score an implementation's values for one record (module docstring)."""
    cols: dict[str, Column] = {}
    orbit = rec.kind == "periodic-orbit"
    missing = [k for k in required(rec) if getattr(got, k) is None]
    if missing:
        msg = f"missing {', '.join(missing)} in {got.path}"
        return OrbitScore(
            rec.id, False, cols, msg, first_failing=problem("missing-key", msg, got.path, column=missing[0])
        )
    found = []
    if got.points is not None:
        found.append(("points", _score_points(rec, got, cols)))
    if got.multipliers is not None:
        found.append(("multipliers", _score_multipliers(rec, got, cols)))
    if not orbit:
        assert rec.value is not None, "a bifurcation record has its value (load_record)"
        lo, hi = rec.value
        cols["value"] = _column(
            "value", _dist([got.value], [lo], [hi]), rec.tolerances["value"], max(1.0, abs(hi)), [[lo, hi]],
            [got.value], [("value",)],
        )  # fmt: skip
    diffs = [Difference(kind, msg, file=got.path, line=got.line((kind,)), column=kind) for kind, msg in found if msg]
    diffs += [_value_difference(got, cols[c]) for c in COLUMNS if c in cols and not cols[c].passed]
    return OrbitScore(
        rec.id, not diffs, cols, "; ".join(d.message for d in diffs), first_failing=next(iter(diffs), None)
    )


def _value_difference(got: Values, c: Column) -> Difference:
    """The :class:`.differences.Difference` of a column beyond its tolerance (its worst item)."""
    item = {"tau_mod_2pi": "point", "sdot": "point", "multipliers": "multiplier"}.get(c.column)
    where = f" ({item} {c.where[1]})" if item and len(c.where) > 1 else ""
    ratio = c.error / c.tolerance if c.tolerance > 0 else math.inf
    return Difference(
        "value", f"{c.column}: error {c.error:.3g} > tolerance {c.tolerance:g}{where}", file=got.path,
        line=got.line(c.where), column=c.column, expected=c.expected, actual=c.actual, error=c.error,
        tolerance=c.tolerance, over_tolerance=ratio, index=c.where[1] if len(c.where) > 1 else None,
    )  # fmt: skip
