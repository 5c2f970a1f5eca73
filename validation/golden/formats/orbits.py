"""The golden periodic orbits and bifurcation points, read (``gear-rattle check --orbits``; docs/reference/golden_formats.md,
"Periodic orbits, Floquet multipliers and bifurcation points"): the records and an implementation's values.

Records: ``validation/golden/orbits/<id>.json`` (:mod:`.catalog.orbit_records` certifies and writes
them).  An implementation writes one ``<id>.json`` per record into a directory, with plain numbers::

    {"points": [{"tau_mod_2pi": 5.135..., "sdot": 1.409..., "wall": 0}, ...],   (one per impact)
     "multipliers": [{"re": -0.437..., "im": 0.0}, {"re": -0.0837..., "im": 0.0}],
     "value": 0.8214404475801...}                                              (bifurcation points)

``points`` and ``multipliers`` are required for a periodic orbit, ``value`` for a fold or period
doubling (whose ``points`` and ``multipliers``, the orbit at the bifurcation, are scored when given):
:func:`required`.  :mod:`..scoring.orbits` scores them.  Only numpy is needed here.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..boundary import check_id, check_tolerance, shown
from ..paths import DEFAULT_ORBITS
from .cases import MalformedFile, checked_at, checked_ids, read_suite_json, select_ids
from .jsonformat import JsonDoc, read_json
from .textformat import position
from .version import MANIFEST_SUFFIX

#: The level of every record (docs/golden.md: periodic orbits and bifurcation points are level 2).
LEVEL = 2
KINDS = ("periodic-orbit", "fold", "period-doubling")
COLUMNS = ("tau_mod_2pi", "sdot", "multipliers", "value")
#: Most impacts per period of a record.
MAX_PERIOD = 1000


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
