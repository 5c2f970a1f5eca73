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

import math
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import numpy as np

from .csvformat import Table, decimal_value, integer_value, is_absent, read_csv
from .jsonformat import read_json
from .paths import DEFAULT_SUITE
from .textformat import MalformedFile, MissingFile

__all__ = ["DEFAULT_SUITE", "MalformedFile", "MissingFile"]  # re-exported: the suite's names for them
#: Columns of an impact-sequence CSV, in order (``core.results.COLUMNS``, restated: numpy only here).
COLUMNS = ("n", "tau", "tau_mod_2pi", "wall", "sdot", "kind")
#: Extra columns of ``expected.csv``: a proven bound on |printed value - true value|.
RADIUS_COLUMNS = ("tau_radius", "tau_mod_2pi_radius", "sdot_radius")
#: Columns compared with tolerances; the others must match exactly.
TOLERANCE_COLUMNS = ("tau", "tau_mod_2pi", "sdot")
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
    """One golden case: its folder, settings and expected sequence."""

    id: str
    folder: Path
    settings: dict
    expected: Sequence

    @property
    def tolerances(self) -> dict:
        """``settings.json``'s ``tolerances``: per column ``{"abs": a, "rel": q}`` (the case's loosest row)."""
        return self.settings["tolerances"]

    def row_tolerances(self, column: str) -> tuple[np.ndarray, float]:
        """``(abs, rel)`` of a tolerance column: the absolute tolerance of every row (an array of the
        expected rows' length) and the relative one; a value ``x`` of row ``i`` passes when
        ``|x - golden_i| <= abs[i] + rel |golden_i|``."""
        tol = self.tolerances[column]
        return np.full(len(self.expected), float(tol["abs"])), float(tol["rel"])

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


def read_sequence(path: str | Path, *, expected_rows: int | None = None, required_extra=()) -> Sequence:
    """Parse an impact-sequence CSV strictly (:func:`.csvformat.read_csv`, then the column forms of
    docs/golden.md); raise :class:`MalformedFile` with a one-line message naming file, line and column
    (:class:`MissingFile` when there is no file)."""
    table = read_csv(path)
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


def read_suite_json(path: Path):
    """A suite JSON file (:func:`.jsonformat.read_json`); a missing one is malformed here."""
    try:
        return read_json(path)
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


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def load_case(folder: str | Path) -> Case:
    """Load and validate one case folder."""
    folder = Path(folder)
    doc = read_suite_json(folder / "settings.json")
    settings = doc.value
    for k in SETTINGS_KEYS:
        if k not in settings:
            raise doc.error((), f"missing key {k!r}")
    if not isinstance(settings["id"], str):
        raise doc.error(("id",), "must be a string")
    if not (
        isinstance(settings["expected_rows"], int)
        and not isinstance(settings["expected_rows"], bool)
        and settings["expected_rows"] >= 0
    ):
        raise doc.error(("expected_rows",), "must be an integer >= 0")
    if "level" in settings and settings["level"] not in LEVELS:
        raise doc.error(("level",), f"must be one of {', '.join(map(str, LEVELS))}")
    tols = settings["tolerances"]
    for c in TOLERANCE_COLUMNS:
        tol = tols.get(c) if isinstance(tols, dict) else None
        if not (
            isinstance(tol, dict)
            and {"abs", "rel"} <= set(tol)
            and all(_is_number(tol[k]) and tol[k] >= 0 for k in ("abs", "rel"))
        ):
            raise doc.error(("tolerances", c), "must be {'abs': a number >= 0, 'rel': a number >= 0}")
    exp = read_sequence(folder / "expected.csv", expected_rows=settings["expected_rows"], required_extra=RADIUS_COLUMNS)
    return Case(settings["id"], folder, settings, exp)


def case_ids(suite: str | Path = DEFAULT_SUITE) -> list[str]:
    """Sorted case ids (folder names that contain a settings.json)."""
    suite = Path(suite)
    if not suite.is_dir():
        raise MalformedFile(f"{suite}: suite directory not found")
    return sorted(p.name for p in suite.iterdir() if (p / "settings.json").is_file())


def select_ids(known: list[str], wanted: list[str] | None, where, what: str = "case") -> list[str]:
    """The ``known`` ids that are ``wanted`` (all when ``wanted`` is empty); an unknown wanted id is a
    :class:`MalformedFile` naming ``where`` and the known ids."""
    if not wanted:
        return known
    unknown = [c for c in wanted if c not in known]
    if unknown:
        raise MalformedFile(f"{where}: unknown {what} id(s): {', '.join(unknown)} (known: {', '.join(known)})")
    return [c for c in known if c in wanted]


def load_suite(
    suite: str | Path = DEFAULT_SUITE, cases: list[str] | None = None, levels: list[int] | None = None
) -> list[Case]:
    """Load every case of a suite directory, or those listed in ``cases`` and (if given) of a level
    in ``levels`` (both: the cases in both selections)."""
    loaded = [load_case(Path(suite) / i) for i in select_ids(case_ids(suite), cases, suite)]
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
    """The score of one case.  ``columns`` is empty when the output is not comparable row by row (no
    output, or a wrong number of events); ``first_row`` is the 0-based data row of the first failure
    (-1 when the case passes; for a wrong number of events the first event whose kind or wall differs,
    or the length of the shorter sequence), ``level`` the case's level, ``no_output`` true when the
    output file is missing."""

    case: str
    passed: bool
    columns: dict
    message: str = ""
    level: int | None = None
    first_row: int = -1
    no_output: bool = False
    #: Where the first failing value is in the output file, ``{"line": L, "column": C}`` (the file's own line,
    #: blank lines counted), or None (the case passes, or its rows are not comparable one by one).
    first_failing: dict | None = None

    @property
    def digits(self) -> float:
        if not self.columns:  # not comparable row by row (wrong number of events)
            return 0.0
        return min((c.digits for k, c in self.columns.items() if k in TOLERANCE_COLUMNS), default=DIGITS_CAP)

    @property
    def column_digits(self) -> dict:
        """Digits of accuracy per tolerance column (``{}`` when not comparable row by row)."""
        return {k: c.digits for k, c in self.columns.items() if k in TOLERANCE_COLUMNS}

    @property
    def worst_ratio(self) -> float | None:
        """The largest |error| / tolerance over the tolerance columns (``None`` when not comparable)."""
        ratios = [c.worst_ratio for k, c in self.columns.items() if k in TOLERANCE_COLUMNS]
        return max(ratios) if ratios else None


def no_output_score(case: Case, path) -> CaseScore:
    """The score of a case whose output file is missing: it fails ("no output"), the run goes on."""
    return CaseScore(case.id, False, {}, f"no output ({path} missing)", case.level, 0, True)


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


def score_sequence(case: Case, got: Sequence) -> CaseScore:
    """Score one output against a case: pass/fail per column and digits of accuracy."""
    exp = case.expected
    if len(got) != len(exp):
        # a well-formed file with a different event sequence (e.g. a missed impact or sticking
        # episode) is a wrong answer, not a malformed file: the case fails
        k = min(len(got), len(exp))
        diff = np.nonzero((got.kind[:k] != exp.kind[:k]) | (got.wall[:k] != exp.wall[:k]))[0]
        where = (
            f"first differing event at line {got.line(int(diff[0]))}"
            if diff.size
            else f"the first {k} events agree in kind and wall"
        )
        return CaseScore(
            case.id,
            False,
            {},
            f"wrong number of events: {len(got)} rows, expected {len(exp)} ({where} of {got.path})",
            case.level,
            int(diff[0]) if diff.size else k,
        )
    cols: dict[str, ColumnScore] = {}
    for c in EXACT_COLUMNS:
        a, e = getattr(got, c), getattr(exp, c)
        bad = np.nonzero(a != e)[0]
        first = int(bad[0]) if bad.size else -1
        cols[c] = ColumnScore(c, bad.size == 0, float(bad.size), first, DIGITS_CAP if bad.size == 0 else 0.0, first)
    for c in TOLERANCE_COLUMNS:
        cols[c] = _score_column(c, *case.row_tolerances(c), getattr(got, c), getattr(exp, c))
    passed = all(s.passed for s in cols.values())
    if passed:
        return CaseScore(case.id, True, cols, "", case.level, -1)
    failing = _first_failing(cols)
    return CaseScore(
        case.id,
        False,
        cols,
        _failure_note(cols, got, exp, case),
        case.level,
        failing.first_row,
        first_failing={"line": got.line(failing.first_row), "column": failing.column},
    )


def _first_failing(cols: dict) -> ColumnScore:
    """The first failing value: the smallest row, then the first column in file order."""
    return min((s for s in cols.values() if not s.passed), key=lambda s: (s.first_row, COLUMNS.index(s.column)))


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


def _row_note(column: str, row: int, got: Sequence, exp: Sequence, case: Case) -> str:
    """``column at line L (what is wrong there)``."""
    line = got.line(row)
    a, e = getattr(got, column)[row], getattr(exp, column)[row]
    if column in EXACT_COLUMNS:
        return f"{column} at line {line} ({a} instead of {e})"
    err = float(circular_distance(a, e)) if column == "tau_mod_2pi" else abs(float(a) - float(e))
    abs_tol, rel_tol = case.row_tolerances(column)
    allowed = float(abs_tol[row]) + rel_tol * abs(float(e))
    return f"{column} at line {line} (|error| {err:.3g}, {err / max(allowed, 1e-300):.3g} x tolerance)"


def _failure_note(cols: dict, got: Sequence, exp: Sequence, case: Case) -> str:
    """The first failing row (smallest line, first column in file order) and the worst one (largest
    |error| / tolerance; an exact-column mismatch if no tolerance column fails)."""
    bad = [s for s in cols.values() if not s.passed]
    first = _first_failing(cols)
    tol_bad = [s for s in bad if s.column in TOLERANCE_COLUMNS]
    worst = max(tol_bad, key=lambda s: s.worst_ratio) if tol_bad else first
    note = f"first failing: {_row_note(first.column, first.first_row, got, exp, case)}"
    if (worst.column, worst.worst_row) != (first.column, first.first_row):
        note += f"; worst: {_row_note(worst.column, worst.worst_row, got, exp, case)}"
    return f"{note} of {got.path}"


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
