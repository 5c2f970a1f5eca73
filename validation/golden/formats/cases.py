"""A case folder of the golden suite, read (docs/reference/golden_formats.md, "File formats" and "What check reads"): its
layout, the impact-sequence CSV that ``expected.csv`` and an implementation's output share, loading and
validating a case and a suite.

Layout (one folder per case, as in the SBML test suite)::

    validation/golden/cases/<case-id>/settings.json    parameters, initial state, impacts, tolerances
    validation/golden/cases/<case-id>/expected.csv     certified impact sequence (+ radius columns)
    validation/golden/cases/<case-id>/provenance.json  how every number was obtained

An implementation under test writes one ``<case-id>.csv`` per case with the header
``n,tau,tau_mod_2pi,wall,sdot,kind`` (the :class:`core.results.ImpactSequence` layout; extra
trailing columns are ignored), read by :func:`read_sequence`; :mod:`..scoring.cases` scores it against
``expected.csv``.  This module needs only numpy (no interval library), so ``gear-rattle check`` runs
anywhere.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import numpy as np

from ..boundary import MAX_CASE_IMPACTS, MAX_CASES, MAX_TOLERANCE, check_id, check_tolerance, shown
from ..paths import DEFAULT_SUITE
from .csvformat import Table, decimal_value, integer_value, is_absent, read_csv
from .jsonformat import read_json
from .textformat import MAX_LINES, MalformedFile, MissingFile

#: Columns of an impact-sequence CSV, in order (``core.results.COLUMNS``, restated: numpy only here).
COLUMNS = ("n", "tau", "tau_mod_2pi", "wall", "sdot", "kind")
#: Extra columns of ``expected.csv``: a proven bound on ``|printed value - true value|``.
RADIUS_COLUMNS = ("tau_radius", "tau_mod_2pi_radius", "sdot_radius")
#: Columns compared with tolerances; the others must match exactly.
TOLERANCE_COLUMNS = ("tau", "tau_mod_2pi", "sdot")
#: Extra columns of ``expected.csv`` (suite 2.0.0): the absolute tolerance of each row, per tolerance column.
ROW_TOLERANCE_COLUMNS = {"tau": "tau_tol", "tau_mod_2pi": "tau_mod_2pi_tol", "sdot": "sdot_tol"}
#: ``settings.json``'s ``row_tolerances``: where the per-row tolerances are.  A case without it (a suite
#: built before 2.0.0) has one absolute tolerance per column, ``tolerances[c]["abs"]``, for every row.
ROW_TOLERANCES_POINTER = {"file": "expected.csv", "columns": ROW_TOLERANCE_COLUMNS}
_TOLERANCE_OF = {v: k for k, v in ROW_TOLERANCE_COLUMNS.items()}
EXACT_COLUMNS = ("n", "wall", "kind")
KINDS = ("impact", "stick", "release")
#: The levels of the cases (docs/golden.md, "Cases"); the orbit records are level 2.
LEVELS = (1, 2, 3)


@dataclass
class Sequence:
    """A parsed impact-sequence CSV (columns as numpy arrays; ``sdot`` NaN where empty)."""

    path: str
    n: np.ndarray
    tau: np.ndarray
    tau_mod_2pi: np.ndarray
    wall: np.ndarray
    sdot: np.ndarray
    kind: np.ndarray
    extra: dict = field(default_factory=dict)
    lines: list | None = None  # the file line of each row (None: row k on line k + 2)

    def __len__(self) -> int:
        return int(self.n.size)

    def line(self, row: int) -> int:
        """The file line of data row ``row`` (0-based)."""
        return self.lines[row] if self.lines is not None else row + 2


@dataclass
class Case:
    """One golden case: its folder, settings and expected sequence, and the absolute tolerance of each row
    per tolerance column (``row_tol``; ``None`` for a case without per-row tolerances)."""

    id: str
    folder: Path
    settings: dict
    expected: Sequence
    row_tol: dict | None = None

    @property
    def tolerances(self) -> dict:
        """``settings.json``'s ``tolerances``: per column ``{"abs": a, "rel": q}`` (``a``: the case's loosest
        row)."""
        return self.settings["tolerances"]

    def row_tolerances(self, column: str) -> tuple[np.ndarray, float]:
        """``(abs, rel)`` of a tolerance column: the absolute tolerance of every row (an array of the
        expected rows' length: ``expected.csv``'s per-row column, or ``settings.json``'s ``abs`` for every
        row of a case without them; 0 where a row has no value) and the relative one; a value ``x`` of row
        ``i`` passes when ``|x - golden_i| <= abs[i] + rel |golden_i|``."""
        rel = float(self.tolerances[column]["rel"])
        if self.row_tol is None:
            return np.full(len(self.expected), float(self.tolerances[column]["abs"])), rel
        return np.nan_to_num(np.asarray(self.row_tol[column], dtype=float), nan=0.0), rel

    @property
    def level(self) -> int | None:
        """The case's level (1, 2 or 3; ``None`` for a suite without levels)."""
        return self.settings.get("level")


def _field(table: Table, rec, k: int, col: str, read):
    """``read(value)`` of field ``k`` of a record; its ValueError becomes a :class:`MalformedFile` there."""
    try:
        return read(rec.values[k])
    except ValueError as e:
        raise table.error(rec, k, f"column {col!r}: {rec.values[k]!r} {e}") from None


def row_tolerance_value(value: str, column: str, kind: str) -> float:
    """The one check of a per-row tolerance cell (``expected.csv``'s ``*_tol`` columns, docs/golden.md): a
    decimal literal, finite and ``>= 0``; the ``sdot`` tolerance of a stick or release row (which has no
    velocity) is empty, NaN here.  ``ValueError`` says what is wrong."""
    if column == "sdot" and kind != "impact":
        if not is_absent(value):
            raise ValueError(f"on a {kind} row (must be empty: a stick/release row has no velocity)")
        return math.nan
    if is_absent(value):
        raise ValueError("is missing (every row has a tolerance for this column)")
    v = decimal_value(value)
    if not v >= 0:
        raise ValueError("is negative (a tolerance is >= 0)")
    if not v < MAX_TOLERANCE:  # the bound of every tolerance a suite states (boundary.check_tolerance)
        raise ValueError(f"is out of range: allowed a tolerance 0 <= t < {MAX_TOLERANCE:g}")
    return v


def read_sequence(
    path: str | Path, *, expected_rows: int | None = None, required_extra=(), inside: str | Path | None = None
) -> Sequence:
    """Parse an impact-sequence CSV strictly (:func:`.csvformat.read_csv`, then the column forms of
    docs/golden.md; a per-row tolerance column of :data:`ROW_TOLERANCE_COLUMNS` among ``required_extra``
    through :func:`row_tolerance_value`); raise :class:`MalformedFile` with a one-line message naming file,
    line and column (:class:`MissingFile` when there is no file).  ``inside``: the folder the file must lie in, its links
    resolved (a regular file only, whether or not it is given: :func:`.textformat.read_bytes`)."""
    table = read_csv(path, inside)
    header, hrec = table.header.values, table.header
    for k, col in enumerate(COLUMNS):
        if col not in header:
            raise table.error(
                hrec, min(k, len(header)), f"missing column {col!r} (header must start with {','.join(COLUMNS)})"
            )
        if k >= len(header) or header[k] != col:
            raise table.error(hrec, k, f"wrong header {','.join(header)!r}: must start with {','.join(COLUMNS)}")
    for col in required_extra:
        if col not in header:
            raise table.error(hrec, len(header), f"missing column {col!r}")
    data = table.records
    if expected_rows is not None and len(data) != expected_rows:
        last = data[-1].line if data else hrec.line
        raise MalformedFile(
            f"{table.path}: line {last}: wrong row count: {len(data)} data rows, expected {expected_rows}"
        )
    idx = {h: i for i, h in enumerate(header)}
    cols: dict[str, list] = {c: [] for c in (*COLUMNS, *required_extra)}
    for r in data:
        cols["n"].append(_field(table, r, 0, "n", integer_value))
        for k, c in ((1, "tau"), (2, "tau_mod_2pi")):
            cols[c].append(_field(table, r, k, c, decimal_value))
        w = _field(table, r, 3, "wall", integer_value)
        if w not in (0, -1):
            raise table.error(r, 3, f"column 'wall': {w} is not 0 or -1")
        cols["wall"].append(w)
        kind = r.values[5]
        if kind not in KINDS:
            raise table.error(r, 5, f"column 'kind': {kind!r} is not one of {', '.join(KINDS)}")
        cols["kind"].append(kind)
        if kind == "impact":
            cols["sdot"].append(_field(table, r, 4, "sdot", decimal_value))
        elif is_absent(r.values[4]):
            cols["sdot"].append(math.nan)
        else:
            raise table.error(
                r,
                4,
                f"column 'sdot': {r.values[4]!r} on a {kind} row "
                "(must be empty or nan: a stick/release row has no pre-impact velocity)",
            )
        for c in required_extra:
            if c in _TOLERANCE_OF:
                cols[c].append(_field(table, r, idx[c], c, lambda v: row_tolerance_value(v, _TOLERANCE_OF[c], kind)))
            else:
                cols[c].append(_field(table, r, idx[c], c, lambda v: math.nan if is_absent(v) else decimal_value(v)))
    extra = {c: np.asarray(cols[c], dtype=float) for c in required_extra}
    return Sequence(
        table.path,
        np.asarray(cols["n"], dtype=np.int64),
        np.asarray(cols["tau"], dtype=float),
        np.asarray(cols["tau_mod_2pi"], dtype=float),
        np.asarray(cols["wall"], dtype=np.int64),
        np.asarray(cols["sdot"], dtype=float),
        np.asarray(cols["kind"], dtype=object),
        extra,
        [r.line for r in data],
    )


def read_suite_json(path: Path, inside: str | Path | None = None):
    """A suite JSON file (:func:`.jsonformat.read_json`, a regular file inside the folder ``inside``); a
    missing one is malformed here."""
    try:
        return read_json(path, inside)
    except MissingFile as e:
        raise MalformedFile(str(e)) from None


SETTINGS_KEYS = (
    "id",
    "description",
    "params",
    "initial_state",
    "n_impacts",
    "stick_time",
    "expected_rows",
    "expected_status",
    "tolerances",
)
#: The endings a case may expect (``expected_status``).
STATUSES = ("active", "stuck_forever", "no_impact")


def checked_at(doc, where: tuple, check, *args):
    """``check(*args)``; its ValueError or TypeError becomes a :class:`MalformedFile` at ``where``."""
    try:
        return check(*args)
    except (ValueError, TypeError) as e:
        raise doc.error(where, str(e)) from None


def _check_start(settings: dict) -> None:
    """``initial_state`` and ``params``: what ``check --self`` runs (:func:`run_settings`), checked as the
    library checks them (:func:`core.checks.check_start`, :func:`core.params.check_value`)."""
    from ....core.checks import check_real, check_start
    from ....core.params import PARAM_NAMES, check_value

    params, ini = settings["params"], settings["initial_state"]
    if not (isinstance(params, dict) and sorted(params) == sorted(PARAM_NAMES)):
        raise ValueError(f"must be an object with the keys {', '.join(PARAM_NAMES)}")
    for k in PARAM_NAMES:
        if isinstance(params[k], bool):
            raise ValueError(f"{k}={params[k]!r} is not a number")
        check_value(k, params[k])
    kinds = {"pre-impact": {"kind", "tau0", "sdot0"}, "free-flight": {"kind", "tau0", "sdot0", "s0"}}
    if not (isinstance(ini, dict) and ini.get("kind") in kinds and set(ini) == kinds[ini["kind"]]):
        raise ValueError(
            "initial_state must be {kind: pre-impact, tau0, sdot0} or {kind: free-flight, tau0, s0, sdot0}"
        )
    for k in ini.keys() - {"kind"}:
        if isinstance(ini[k], bool):
            raise ValueError(f"initial_state.{k}={ini[k]!r} is not a number")
    check_start(ini["tau0"], ini["sdot0"], ini.get("s0"))
    check_real("sdot0", ini["sdot0"], -1e6, 1e6)
    check_real("stick_time", settings["stick_time"], 0.0, 1.0)


def _check_settings(doc, folder: Path) -> None:
    """Every field of ``settings.json`` that ``check`` uses, within its bounds (docs/reference/golden_formats.md,
    "What check reads"): the id (:func:`.boundary.check_id`, the folder's name), counts, tolerances
    (:func:`.boundary.check_tolerance`), the start and parameters."""
    settings = doc.value
    for k in SETTINGS_KEYS:
        if k not in settings:
            raise doc.error((), f"missing key {k!r}")
    cid = checked_at(doc, ("id",), check_id, settings["id"], "id")
    name = Path(os.path.abspath(folder)).name
    if cid != name:
        raise doc.error(("id",), f"{shown(cid)} is not its folder's name {shown(name)} (a case's id names its folder)")
    from ....core.checks import check_int

    count = partial(check_int, strict=True)
    checked_at(doc, ("expected_rows",), count, "expected_rows", settings["expected_rows"], 0, MAX_LINES)
    checked_at(doc, ("n_impacts",), count, "n_impacts", settings["n_impacts"], 0, MAX_CASE_IMPACTS)
    if settings["expected_status"] not in STATUSES:
        raise doc.error(("expected_status",), f"must be one of {', '.join(STATUSES)}")
    if "level" in settings and settings["level"] not in LEVELS:
        raise doc.error(("level",), f"must be one of {', '.join(map(str, LEVELS))}")
    tols = settings["tolerances"]
    for c in TOLERANCE_COLUMNS:
        tol = tols.get(c) if isinstance(tols, dict) else None
        if not (isinstance(tol, dict) and {"abs", "rel"} <= set(tol)):
            raise doc.error(("tolerances", c), f"must be {{'abs': a, 'rel': q}}, numbers 0 <= a, q < {MAX_TOLERANCE:g}")
        for k in ("abs", "rel"):
            checked_at(doc, ("tolerances", c, k), check_tolerance, tol[k], f"tolerances.{c}.{k}")
    checked_at(doc, ("params",), _check_start, settings)


def load_case(folder: str | Path, suite: str | Path | None = None) -> Case:
    """Load and validate one case folder (its files read inside ``suite``, default the folder itself:
    regular files, no link out; :func:`.textformat.read_bytes`)."""
    folder = Path(folder)
    inside = folder if suite is None else suite
    doc = read_suite_json(folder / "settings.json", inside)
    if not isinstance(doc.value, dict):
        raise doc.error((), "expected a JSON object")
    _check_settings(doc, folder)
    settings = doc.value
    per_row = "row_tolerances" in settings
    if per_row and settings["row_tolerances"] != ROW_TOLERANCES_POINTER:
        raise doc.error(("row_tolerances",), f"must be {json.dumps(ROW_TOLERANCES_POINTER)}")
    extra = RADIUS_COLUMNS + (tuple(ROW_TOLERANCE_COLUMNS.values()) if per_row else ())
    exp = read_sequence(
        folder / "expected.csv", expected_rows=settings["expected_rows"], required_extra=extra, inside=inside
    )
    row_tol = {c: exp.extra[k] for c, k in ROW_TOLERANCE_COLUMNS.items()} if per_row else None
    return Case(settings["id"], folder, settings, exp, row_tol)


def case_ids(suite: str | Path = DEFAULT_SUITE) -> list[str]:
    """Sorted case ids (folder names that contain an entry settings.json, of whatever kind: the reader
    refuses what is not a regular file; hidden names, starting with ``.``, are never cases); a
    :class:`MalformedFile` where such a folder's name is not an id (:func:`.boundary.check_id`) or the
    suite holds more than :data:`.boundary.MAX_CASES` of them."""
    suite = Path(suite)
    if not suite.is_dir():
        raise MalformedFile(f"{suite}: suite directory not found")
    names = (
        p.name
        for p in suite.iterdir()
        if not p.name.startswith(".") and p.is_dir() and os.path.lexists(p / "settings.json")
    )
    return checked_ids(suite, names, "case folder")


def checked_ids(folder: Path, names, what: str) -> list[str]:
    """The sorted ``names`` found in ``folder``, each an id (:func:`.boundary.check_id`) and at most
    :data:`.boundary.MAX_CASES` of them; a :class:`MalformedFile` naming the folder otherwise."""
    ids = []
    for name in names:
        try:
            ids.append(check_id(name, what))
        except ValueError as e:
            raise MalformedFile(f"{folder}: {e}") from None
        if len(ids) > MAX_CASES:
            raise MalformedFile(f"{folder}: more than {MAX_CASES} {what}s (the limit of a suite)")
    return sorted(ids)


def select_ids(known: list[str], wanted: list[str] | None, where, what: str = "case") -> list[str]:
    """The ``known`` ids that are ``wanted`` (all when ``wanted`` is empty); an unknown wanted id is a
    :class:`MalformedFile` naming ``where`` and the known ids."""
    if not wanted:
        return known
    unknown = [c for c in wanted if c not in known]
    if unknown:
        raise MalformedFile(
            f"{where}: unknown {what} id(s): {', '.join(map(shown, unknown))} (known: {', '.join(known)})"
        )
    return [c for c in known if c in wanted]


def load_suite(
    suite: str | Path = DEFAULT_SUITE, cases: list[str] | None = None, levels: list[int] | None = None
) -> list[Case]:
    """Load every case of a suite directory, or those listed in ``cases`` and (if given) of a level
    in ``levels`` (both: the cases in both selections).  Every file is read inside the suite."""
    loaded = [load_case(Path(suite) / i, suite) for i in select_ids(case_ids(suite), cases, suite)]
    return [c for c in loaded if not levels or c.level in levels]


def sequence_from_impacts(seq, path: str = "<memory>") -> Sequence:
    """A :class:`Sequence` from a :class:`core.results.ImpactSequence` (any track)."""
    return Sequence(
        path,
        np.asarray(seq.n, dtype=np.int64),
        np.asarray(seq.tau, dtype=float),
        np.asarray(seq.theta, dtype=float),
        np.asarray(seq.wall, dtype=np.int64),
        np.asarray(seq.sdot, dtype=float),
        np.asarray(seq.kind, dtype=object),
    )
