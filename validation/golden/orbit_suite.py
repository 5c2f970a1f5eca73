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
from pathlib import Path

import numpy as np

from .suite import DIGITS_CAP, MalformedFile, circular_distance, select_ids

#: Where the committed records live.
DEFAULT_ORBITS = Path(__file__).resolve().parent / "orbits"
KINDS = ("periodic-orbit", "fold", "period-doubling")
COLUMNS = ("tau_mod_2pi", "sdot", "multipliers", "value")
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
    value: tuple | None
    tolerances: dict


def _read_json(path: Path) -> dict:
    try:
        d = json.loads(path.read_text())
    except FileNotFoundError:
        raise MalformedFile(f"{path}: missing file") from None
    except (OSError, UnicodeDecodeError) as e:
        raise MalformedFile(f"{path}: cannot read: {e}") from None
    except json.JSONDecodeError as e:
        raise MalformedFile(f"{path}: line {e.lineno}: invalid JSON: {e.msg}") from None
    if not isinstance(d, dict):
        raise MalformedFile(f"{path}: line 1: expected a JSON object")
    return d


def _num(x, path, where: str) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
        raise MalformedFile(f"{path}: {where}: {x!r} is not a finite number")
    return float(x)


def _pair(x, path, where: str) -> tuple[float, float]:
    if not (isinstance(x, list) and len(x) == 2):
        raise MalformedFile(f"{path}: {where}: expected an interval [lo, hi]")
    lo, hi = (_num(v, path, where) for v in x)
    if not lo <= hi:
        raise MalformedFile(f"{path}: {where}: lo > hi")
    return lo, hi


def load_record(path: str | Path) -> Record:
    """Load and validate one golden record."""
    path = Path(path)
    d = _read_json(path)
    for k in ("id", "kind", "params", "impacts_per_period", "turns", "points", "multipliers", "tolerances"):
        if k not in d:
            raise MalformedFile(f"{path}: missing key {k!r}")
    if d["kind"] not in KINDS:
        raise MalformedFile(f"{path}: kind {d['kind']!r} is not one of {', '.join(KINDS)}")
    pts = np.array([[*_pair(p.get("tau_mod_2pi"), path, f"points[{i}].tau_mod_2pi"),
                     *_pair(p.get("sdot"), path, f"points[{i}].sdot")] for i, p in enumerate(d["points"])])
    walls = np.array([p.get("wall") for p in d["points"]])
    if pts.shape != (d["impacts_per_period"], 4) or not np.isin(walls, (0, -1)).all():
        raise MalformedFile(f"{path}: points: expected {d['impacts_per_period']} points with wall 0 or -1")
    mult = np.array([[*_pair(m.get("re"), path, f"multipliers[{i}].re"), *_pair(m.get("im"), path, f"multipliers[{i}].im")]
                     for i, m in enumerate(d["multipliers"])])
    value = None
    if d["kind"] != "periodic-orbit":
        if "value" not in d or d.get("parameter") not in ("r", "alpha"):
            raise MalformedFile(f"{path}: a {d['kind']} needs 'parameter' (r or alpha) and 'value'")
        value = _pair(d["value"], path, "value")
    tol = d["tolerances"]
    need = ("tau_mod_2pi", "sdot", "multipliers") + (("value",) if value is not None else ())
    for c in need:
        if not (isinstance(tol.get(c), (int, float)) and tol[c] >= 0):
            raise MalformedFile(f"{path}: tolerances[{c!r}] must be a number >= 0")
    return Record(d["id"], d["kind"], d, pts, walls.astype(np.int64), mult, value, dict(tol))


def record_ids(folder: str | Path = DEFAULT_ORBITS) -> list[str]:
    folder = Path(folder)
    if not folder.is_dir():
        raise MalformedFile(f"{folder}: orbit suite directory not found")
    return sorted(p.stem for p in folder.glob("*.json"))


def load_records(folder: str | Path = DEFAULT_ORBITS, ids: list[str] | None = None) -> list[Record]:
    """Every record of a folder (or the listed ids)."""
    return [load_record(Path(folder) / f"{i}.json") for i in select_ids(record_ids(folder), ids, folder, "orbit")]


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


def values_from_dict(d, path: str) -> Values:
    """Validate an implementation's values (the layout of the module docstring)."""
    if not isinstance(d, dict):
        raise MalformedFile(f"{path}: line 1: expected a JSON object")
    out = Values(path)
    if "points" in d:
        if not (isinstance(d["points"], list) and d["points"]):
            raise MalformedFile(f"{path}: points: expected a non-empty list")
        rows, walls = [], []
        for i, p in enumerate(d["points"]):
            if not isinstance(p, dict):
                raise MalformedFile(f"{path}: points[{i}]: expected an object with tau_mod_2pi, sdot, wall")
            rows.append([_num(p.get("tau_mod_2pi"), path, f"points[{i}].tau_mod_2pi"),
                         _num(p.get("sdot"), path, f"points[{i}].sdot")])
            w = p.get("wall")
            if w not in (0, -1) or isinstance(w, bool):
                raise MalformedFile(f"{path}: points[{i}].wall: {w!r} is not 0 or -1")
            walls.append(w)
        out.points, out.walls = np.array(rows), np.array(walls, dtype=np.int64)
    if "multipliers" in d:
        if not (isinstance(d["multipliers"], list) and d["multipliers"]):
            raise MalformedFile(f"{path}: multipliers: expected a non-empty list")
        zs = []
        for i, m in enumerate(d["multipliers"]):
            if not isinstance(m, dict):
                raise MalformedFile(f"{path}: multipliers[{i}]: expected an object with re, im")
            zs.append(complex(_num(m.get("re"), path, f"multipliers[{i}].re"),
                              _num(m.get("im", 0.0), path, f"multipliers[{i}].im")))
        out.multipliers = np.array(zs)
    if "value" in d:
        out.value = _num(d["value"], path, "value")
    return out


def required(rec: Record) -> tuple:
    """The keys an implementation's file must hold for ``rec``."""
    return ("points", "multipliers") if rec.kind == "periodic-orbit" else ("value",)


def read_values(path: str | Path, rec: Record | None = None) -> Values:
    """Read and validate an implementation's file (with ``rec``: the keys it requires must be there)."""
    path = Path(path)
    d = _read_json(path)
    missing = [k for k in (required(rec) if rec is not None else ()) if k not in d]
    if missing:
        raise MalformedFile(f"{path}: missing key {missing[0]!r} (a {rec.kind} needs {', '.join(required(rec))})")
    return values_from_dict(d, str(path))


# ------------------------------------------------------------------------------------------------
# scoring


@dataclass
class Column:
    column: str
    passed: bool
    error: float          # largest distance to the record's interval
    tolerance: float
    digits: float         # -log10(largest error / scale), capped at DIGITS_CAP


@dataclass
class OrbitScore:
    id: str
    passed: bool
    columns: dict = field(default_factory=dict)
    message: str = ""


def _dist(x, lo, hi, circular=False):
    x, lo, hi = (np.asarray(a, float) for a in (x, lo, hi))
    if circular:
        mid = (lo + hi) / 2
        return np.maximum(circular_distance(x, mid) - (hi - lo) / 2, 0.0)
    return np.maximum(np.maximum(lo - x, x - hi), 0.0)


def _digits(err: np.ndarray, scale: float) -> float:
    worst = float(np.max(err)) / scale if err.size else 0.0
    return DIGITS_CAP if worst <= 0 else float(min(DIGITS_CAP, -math.log10(worst)))


def _column(name: str, err: np.ndarray, tol: float, scale: float) -> Column:
    e = float(np.max(err)) if err.size else 0.0
    return Column(name, bool(e <= tol), e, tol, _digits(err, scale))


def _score_points(rec: Record, got: Values, cols: dict) -> str:
    n = rec.points.shape[0]
    if got.points.shape[0] != n:
        return f"{got.points.shape[0]} points, expected {n} (impacts per period)"
    best = None
    for k in range(n):  # rotation: got[(i + k) % n] <-> record[i]
        idx = (np.arange(n) + k) % n
        if not np.array_equal(got.walls[idx], rec.walls):
            continue
        et = _dist(got.points[idx, 0], rec.points[:, 0], rec.points[:, 1], circular=True)
        es = _dist(got.points[idx, 1], rec.points[:, 2], rec.points[:, 3])
        if best is None or max(et.max(), es.max()) < max(best[0].max(), best[1].max()):
            best = (et, es)
    if best is None:
        return "the walls of the points match no rotation of the record's walls"
    cols["tau_mod_2pi"] = _column("tau_mod_2pi", best[0], rec.tolerances["tau_mod_2pi"], TWO_PI)
    cols["sdot"] = _column("sdot", best[1], rec.tolerances["sdot"], float(np.abs(rec.points[:, 2:]).max()))
    return ""


def _score_multipliers(rec: Record, got: Values, cols: dict) -> str:
    m = rec.multipliers
    if got.multipliers.size != m.shape[0]:
        return f"{got.multipliers.size} multipliers, expected {m.shape[0]}"
    best = None
    for perm in ([0, 1], [1, 0]) if m.shape[0] == 2 else [list(range(m.shape[0]))]:
        z = got.multipliers[perm]
        e = np.maximum(_dist(z.real, m[:, 0], m[:, 1]), _dist(z.imag, m[:, 2], m[:, 3]))
        if best is None or e.max() < best.max():
            best = e
    cols["multipliers"] = _column("multipliers", best, rec.tolerances["multipliers"],
                                  max(1.0, float(np.abs(m).max())))
    return ""


def score(rec: Record, got: Values) -> OrbitScore:
    """Score an implementation's values for one record (module docstring)."""
    cols: dict[str, Column] = {}
    orbit = rec.kind == "periodic-orbit"
    missing = [k for k in required(rec) if getattr(got, k) is None]
    if missing:
        return OrbitScore(rec.id, False, cols, f"missing {', '.join(missing)} in {got.path}")
    msgs = []
    if got.points is not None:
        msgs.append(_score_points(rec, got, cols))
    if got.multipliers is not None:
        msgs.append(_score_multipliers(rec, got, cols))
    if not orbit:
        lo, hi = rec.value
        cols["value"] = _column("value", _dist([got.value], [lo], [hi]), rec.tolerances["value"], max(1.0, abs(hi)))
    msgs = [m for m in msgs if m]
    bad = [c for c in cols.values() if not c.passed]
    msgs += [f"{c.column}: error {c.error:.3g} > tolerance {c.tolerance:g}" for c in bad]
    return OrbitScore(rec.id, not msgs, cols, "; ".join(msgs))


def summary_table(scores: list[OrbitScore]) -> str:
    """Plain-text table: record, verdict, digits per column (``-``: not scored), first problem."""
    head = f"{'orbit / bifurcation point':<40} {'result':<6} {'tau%2pi':>7} {'sdot':>6} {'mult':>6} {'value':>6}  note"
    lines = [head, "-" * len(head)]
    for s in scores:
        d = [f"{s.columns[c].digits:.1f}" if c in s.columns else "-" for c in COLUMNS]
        lines.append(f"{s.id:<40} {'PASS' if s.passed else 'FAIL':<6} {d[0]:>7} {d[1]:>6} {d[2]:>6} {d[3]:>6}  {s.message}")
    n_pass = sum(s.passed for s in scores)
    lines.append(f"{n_pass}/{len(scores)} orbits and bifurcation points pass (digits: min over values of -log10 "
                 f"of the error relative to the scale, capped at {DIGITS_CAP:g})")
    return "\n".join(lines)
