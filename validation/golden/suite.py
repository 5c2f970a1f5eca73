"""The golden conformance suite: case layout, loading, validation of output files, and scoring.

Layout (one folder per case, as in the SBML test suite)::

    validation/golden/cases/<case-id>/settings.json    parameters, initial state, impacts, tolerances
    validation/golden/cases/<case-id>/expected.csv     certified impact sequence (+ radius columns)
    validation/golden/cases/<case-id>/provenance.json  how every number was obtained

An implementation under test writes one ``<case-id>.csv`` per case with the header
``n,tau,tau_mod_2pi,wall,sdot,kind`` (the :class:`core.results.ImpactSequence` layout; extra
trailing columns are ignored).  :func:`score_file` compares it with ``expected.csv`` column by column.
This module needs only numpy (no interval library), so ``gear-rattle check`` runs anywhere.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from fractions import Fraction
from functools import partial
from pathlib import Path

import numpy as np

from .boundary import MAX_CASE_IMPACTS, MAX_CASES, MAX_TOLERANCE, check_id, check_tolerance, shown
from .csvformat import Table, decimal_value, integer_value, is_absent, read_csv
from .differences import Comparison, Difference, compare_events, problem, value_difference
from .jsonformat import read_json
from .paths import DEFAULT_SUITE
from .textformat import MAX_LINES, MalformedFile, MissingFile

__all__ = ["DEFAULT_SUITE", "MalformedFile", "MissingFile"]  # re-exported: the suite's names for them
#: Columns of an impact-sequence CSV, in order (``core.results.COLUMNS``, restated: numpy only here).
COLUMNS = ("n", "tau", "tau_mod_2pi", "wall", "sdot", "kind")
#: Extra columns of ``expected.csv``: a proven bound on |printed value - true value|.
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
#: Digits of accuracy are capped here (a float64 carries ~16-17).
DIGITS_CAP = 17.0
TWO_PI = 2.0 * math.pi


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
    from ...core.checks import check_real, check_start
    from ...core.params import PARAM_NAMES, check_value

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
    """Every field of ``settings.json`` that ``check`` uses, within its bounds (docs/golden.md, "What check
    reads"): the id (:func:`.boundary.check_id`, the folder's name), counts, tolerances
    (:func:`.boundary.check_tolerance`), the start and parameters."""
    settings = doc.value
    for k in SETTINGS_KEYS:
        if k not in settings:
            raise doc.error((), f"missing key {k!r}")
    cid = checked_at(doc, ("id",), check_id, settings["id"], "id")
    name = Path(os.path.abspath(folder)).name
    if cid != name:
        raise doc.error(("id",), f"{shown(cid)} is not its folder's name {shown(name)} (a case's id names its folder)")
    from ...core.checks import check_int

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


# ---------------------------------------------------------------------------------------------
# scoring


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
        """The largest |error| / tolerance over the tolerance columns (``None`` when no row was compared)."""
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


def _digits(err: np.ndarray, scale: np.ndarray) -> float:
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
#: difference (|d| < 2^1025) is then exact to 2^-170, far below any distance a float64 can show.
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
        _digits(diff[mask], scale[mask]),
        int(failing[0]) if failing.size else -1,
        float(ratio[worst]) if worst >= 0 else 0.0,
    )


def score_file(case: Case, path: str | Path) -> CaseScore:
    """Read ``path`` strictly and score it (a different number of events fails the case)."""
    got = read_sequence(path)
    return score_sequence(case, got)


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


def run_case(case: Case, track: str = "map"):
    """Run one of our tracks on a case's settings; returns the :class:`ImpactSequence`."""
    return run_settings(case.settings, track)


def run_settings(s: dict, track: str = "map"):
    """Run one of our tracks on a case's ``settings.json`` data (its parameters, initial state, impacts
    and sticking threshold ``stick_time``, default :data:`mapimpl.sticking.STICK_TIME`); returns the
    :class:`ImpactSequence`."""
    from ...core.params import Params
    from ...mapimpl.sticking import STICK_TIME
    from ...mapimpl.tracks import orbit

    p = Params(**s["params"])
    ini = s["initial_state"]
    return orbit(
        p,
        ini["tau0"],
        ini["sdot0"],
        int(s["n_impacts"]),
        s0=ini.get("s0"),
        track=track,
        stick_time=s.get("stick_time", STICK_TIME),
    )
