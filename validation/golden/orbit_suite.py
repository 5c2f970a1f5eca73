"""The golden periodic orbits and bifurcation points: loading the records, reading an implementation's
values and scoring them (``gear-rattle check --orbits``; docs/golden.md).

Records: ``validation/golden/orbits/<id>.json`` (:mod:`.orbit_certify`).  An implementation writes
one ``<id>.json`` per record into a directory, with plain numbers::

    {"points": [{"tau_mod_2pi": 5.135..., "sdot": 1.409..., "wall": 0}, ...],   (one per impact)
     "multipliers": [{"re": -0.437..., "im": 0.0}, {"re": -0.0837..., "im": 0.0}],
     "value": 0.8214404475801...}                                              (bifurcation points)

``points`` and ``multipliers`` are required for a periodic orbit, ``value`` for a fold or period
doubling (whose ``points`` and ``multipliers``, the orbit at the bifurcation, are scored when given).
The points may start anywhere on the orbit (the rotation that matches the record's walls and is
closest is used) and the multipliers may come in any order (the closest pairing is used).  A value
passes when its distance to the record's interval is at most the record's tolerance for its column;
phases are compared on the circle.  Only numpy is needed here: scoring runs anywhere.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import numpy as np

from .differences import Difference, problem
from .boundary import check_id, check_tolerance, shown
from .jsonformat import JsonDoc, read_json
from .textformat import position
from .paths import DEFAULT_ORBITS
from .suite import (
    DIGITS_CAP,
    MalformedFile,
    MissingFile,
    checked_at,
    checked_ids,
    circular_distance_exact,
    read_suite_json,
    select_ids,
)
from .version import MANIFEST_SUFFIX

__all__ = ["DEFAULT_ORBITS", "MalformedFile", "MissingFile"]  # re-exported
#: The level of every record (docs/golden.md: periodic orbits and bifurcation points are level 2).
LEVEL = 2
KINDS = ("periodic-orbit", "fold", "period-doubling")
COLUMNS = ("tau_mod_2pi", "sdot", "multipliers", "value")
#: Most impacts per period of a record.
MAX_PERIOD = 1000
TWO_PI = 2.0 * math.pi


@dataclass
class Record:
    """A golden record: ``points`` rows ``(tau lo, tau hi, sdot lo, sdot hi)``, ``walls``,
    ``multipliers`` rows ``(re lo, re hi, im lo, im hi)``, ``value`` ``(lo, hi)`` or ``None``."""

    id: str
    kind: str
    data: dict
    points: np.ndarray
    walls: np.ndarray
    multipliers: np.ndarray
    value: tuple[float, float] | None
    tolerances: dict

    @property
    def level(self) -> int:
        """Every record is level 2 (:data:`LEVEL`)."""
        return LEVEL


def _show(x) -> str:
    """A value as JSON writes it (``true``, ``null``, ``"1.5"``), cut to 60 characters."""
    text = json.dumps(x)
    return text if len(text) <= 60 else text[:57] + "..."


def _num(doc: JsonDoc, where: tuple, x) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise doc.error(
            where, f"{_show(x)} is not a finite number" if x is not None else "missing (a number is needed)"
        )
    return float(x)


def _pair(doc: JsonDoc, where: tuple, x) -> tuple[float, float]:
    if not (isinstance(x, list) and len(x) == 2):
        raise doc.error(where, "expected an interval [lo, hi]")
    lo, hi = (_num(doc, where + (i,), v) for i, v in enumerate(x))
    if not lo <= hi:
        raise doc.error(where, "lo > hi")
    return lo, hi


def _objects(doc: JsonDoc, key: str, what: str) -> list:
    """``doc.value[key]``: a non-empty list of objects (``what`` names their keys)."""
    items = doc.value.get(key)
    if not (isinstance(items, list) and items):
        raise doc.error((key,), "expected a non-empty list")
    for i, p in enumerate(items):
        if not isinstance(p, dict):
            raise doc.error((key, i), f"expected an object with {what}")
    return items


def load_record(path: str | Path, inside: str | Path | None = None) -> Record:
    """Load and validate one golden record (a regular file inside the folder ``inside``, default its own;
    its id the file's name, :func:`.boundary.check_id`; its tolerances :func:`.boundary.check_tolerance`)."""
    path = Path(path)
    doc = read_suite_json(path, path.parent if inside is None else inside)
    d = doc.value
    for k in ("id", "kind", "params", "impacts_per_period", "turns", "points", "multipliers", "tolerances"):
        if k not in d:
            raise doc.error((), f"missing key {k!r}")
    rid = checked_at(doc, ("id",), check_id, d["id"], "id")
    if rid + ".json" != path.name:
        raise doc.error(
            ("id",), f"{shown(rid)} is not its file's name {shown(path.name)} (a record's id names its file)"
        )
    ipp = d["impacts_per_period"]
    if not (isinstance(ipp, int) and not isinstance(ipp, bool) and 1 <= ipp <= MAX_PERIOD):
        raise doc.error(("impacts_per_period",), f"must be an integer 1 <= impacts_per_period <= {MAX_PERIOD}")
    if d["kind"] not in KINDS:
        raise doc.error(("kind",), f"{d['kind']!r} is not one of {', '.join(KINDS)}")
    points = _objects(doc, "points", "tau_mod_2pi, sdot, wall")
    pts = np.array(
        [
            [
                *_pair(doc, ("points", i, "tau_mod_2pi"), p.get("tau_mod_2pi")),
                *_pair(doc, ("points", i, "sdot"), p.get("sdot")),
            ]
            for i, p in enumerate(points)
        ]
    )
    walls = [p.get("wall") for p in points]
    if len(points) != d["impacts_per_period"] or any(w not in (0, -1) or isinstance(w, bool) for w in walls):
        raise doc.error(("points",), f"expected {d['impacts_per_period']!r} points with wall 0 or -1")
    mult = np.array(
        [
            [*_pair(doc, ("multipliers", i, "re"), m.get("re")), *_pair(doc, ("multipliers", i, "im"), m.get("im"))]
            for i, m in enumerate(_objects(doc, "multipliers", "re, im"))
        ]
    )
    value = None
    if d["kind"] != "periodic-orbit":
        if "value" not in d or d.get("parameter") not in ("r", "alpha"):
            raise doc.error((), f"a {d['kind']} needs 'parameter' (r or alpha) and 'value'")
        value = _pair(doc, ("value",), d["value"])
    tol = d["tolerances"]
    need = ("tau_mod_2pi", "sdot", "multipliers") + (("value",) if value is not None else ())
    if not isinstance(tol, dict):
        raise doc.error(("tolerances",), f"must be an object with {', '.join(need)}")
    for c in need:
        checked_at(doc, ("tolerances", c), check_tolerance, tol.get(c), f"tolerances.{c}")
    return Record(d["id"], d["kind"], d, pts, np.array(walls, dtype=np.int64), mult, value, dict(tol))


def record_ids(folder: str | Path = DEFAULT_ORBITS) -> list[str]:
    """Sorted record ids: the names of the folder's ``*.json`` files (but the bookkeeping of
    :data:`.version.MANIFEST_SUFFIX`); a :class:`MalformedFile` where one is not an id
    (:func:`.boundary.check_id`) or there are more than :data:`.boundary.MAX_CASES`."""
    folder = Path(folder)
    if not folder.is_dir():
        raise MalformedFile(f"{folder}: orbit suite directory not found")
    names = (p.stem for p in folder.glob("*.json") if not p.name.endswith(MANIFEST_SUFFIX))
    return checked_ids(folder, names, "orbit record file")


def load_records(
    folder: str | Path = DEFAULT_ORBITS, ids: list[str] | None = None, levels: list[int] | None = None
) -> list[Record]:
    """Every record of a folder (or the listed ids); none when ``levels`` is given without
    :data:`LEVEL` (every record is level 2)."""
    if levels and LEVEL not in levels:
        return []
    return [
        load_record(Path(folder) / f"{i}.json", folder) for i in select_ids(record_ids(folder), ids, folder, "orbit")
    ]


# ------------------------------------------------------------------------------------------------
# an implementation's values


@dataclass
class Values:
    """An implementation's values for one record: ``points`` (n, 2) ``(tau_mod_2pi, sdot)``,
    ``walls``, ``multipliers`` (complex), ``value``; ``None`` where not given."""

    path: str
    points: np.ndarray | None = None
    walls: np.ndarray | None = None
    multipliers: np.ndarray | None = None
    value: float | None = None
    doc: JsonDoc | None = None

    def line(self, where: tuple) -> int | None:
        """The file line of the value at ``where`` (a JSON path), or of its nearest enclosing value."""
        if self.doc is None or not self.doc.text:
            return None
        while where not in self.doc.offsets and where:
            where = where[:-1]
        return position(self.doc.text, self.doc.offsets.get(where, 0))[0]


def values_from_doc(doc: JsonDoc) -> Values:
    """Validate an implementation's values (the layout of the module docstring)."""
    d = doc.value
    out = Values(doc.path, doc=doc)
    if "points" in d:
        rows, walls = [], []
        for i, p in enumerate(_objects(doc, "points", "tau_mod_2pi, sdot, wall")):
            rows.append(
                [
                    _num(doc, ("points", i, "tau_mod_2pi"), p.get("tau_mod_2pi")),
                    _num(doc, ("points", i, "sdot"), p.get("sdot")),
                ]
            )
            w = p.get("wall")
            if w not in (0, -1) or isinstance(w, bool):
                raise doc.error(("points", i, "wall"), f"{_show(w)} is not 0 or -1")
            walls.append(int(w))
        out.points, out.walls = np.array(rows), np.array(walls, dtype=np.int64)
    if "multipliers" in d:
        zs = []
        for i, m in enumerate(_objects(doc, "multipliers", "re, im")):
            zs.append(
                (
                    _num(doc, ("multipliers", i, "re"), m.get("re")),
                    _num(doc, ("multipliers", i, "im"), m.get("im", 0.0)),
                )
            )
        out.multipliers = np.array([complex(*z) for z in zs])
    if "value" in d:
        out.value = _num(doc, ("value",), d["value"])
    return out


def values_from_dict(d: dict, path: str) -> Values:
    """:func:`values_from_doc` for values held in memory (our own solvers)."""
    return values_from_doc(JsonDoc(path, "", d, {}))


def required(rec: Record) -> tuple:
    """The keys an implementation's file must hold for ``rec``."""
    return ("points", "multipliers") if rec.kind == "periodic-orbit" else ("value",)


def read_values(path: str | Path, rec: Record | None = None, inside: str | Path | None = None) -> Values:
    """Read and validate an implementation's file (with ``rec``: the keys it requires must be there; a
    regular file, inside the folder ``inside`` where given)."""
    doc = read_json(path, inside)  # MissingFile when there is none: check scores it as "no output"
    missing = [k for k in (required(rec) if rec is not None else ()) if k not in doc.value]
    if rec is not None and missing:
        raise doc.error((), f"missing key {missing[0]!r} (a {rec.kind} needs {', '.join(required(rec))})")
    return values_from_doc(doc)


# ------------------------------------------------------------------------------------------------
# scoring


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
    """The score of one record; ``level`` is :data:`LEVEL`, ``no_output`` true when the file is missing."""

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


def score(rec: Record, got: Values) -> OrbitScore:
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
