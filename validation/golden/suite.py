"""The golden conformance suite: case layout, loading, validation of output files, and scoring.

Layout (one folder per case, as in the SBML test suite)::

    validation/golden/cases/<case-id>/settings.json    parameters, initial state, impacts, tolerances
    validation/golden/cases/<case-id>/expected.csv     certified impact sequence (+ radius columns)
    validation/golden/cases/<case-id>/provenance.json  how every number was obtained

An implementation under test writes one ``<case-id>.csv`` per case with the header
``n,tau,tau_mod_2pi,wall,sdot,kind`` (the :class:`core.results.ImpactSequence` layout; extra
trailing columns are ignored).  :func:`score_case` compares it with ``expected.csv`` column by column.
This module needs only numpy (no interval library), so ``gear-rattle check`` runs anywhere.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: Where the committed cases live.
DEFAULT_SUITE = Path(__file__).resolve().parent / "cases"
#: Columns of an impact-sequence CSV, in order (``core.results.COLUMNS``, restated: numpy only here).
COLUMNS = ("n", "tau", "tau_mod_2pi", "wall", "sdot", "kind")
#: Extra columns of ``expected.csv``: a proven bound on |printed value - true value|.
RADIUS_COLUMNS = ("tau_radius", "tau_mod_2pi_radius", "sdot_radius")
#: Columns compared with tolerances; the others must match exactly.
TOLERANCE_COLUMNS = ("tau", "tau_mod_2pi", "sdot")
EXACT_COLUMNS = ("n", "wall", "kind")
KINDS = ("impact", "stick", "release")
#: Digits of accuracy are capped here (a float64 carries ~16-17).
DIGITS_CAP = 17.0
TWO_PI = 2.0 * math.pi


class MalformedFile(Exception):
    """An input file cannot be read as the documented layout (one-line message naming file and line)."""


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

    def __len__(self) -> int:
        return int(self.n.size)


@dataclass
class Case:
    """One golden case: its folder, settings and expected sequence."""

    id: str
    folder: Path
    settings: dict
    expected: Sequence

    @property
    def tolerances(self) -> dict:
        return self.settings["tolerances"]


def _num(text: str, path, line: int, col: str, *, integer: bool = False, allow_empty: bool = False) -> float:
    t = text.strip()
    if t == "" and allow_empty:
        return math.nan
    try:
        v = int(t) if integer else float(t)
    except ValueError:
        what = "an integer" if integer else "a number"
        raise MalformedFile(f"{path}: line {line}: column {col!r}: {text!r} is not {what}") from None
    if not integer and not math.isfinite(v) and not (allow_empty and math.isnan(v)):
        raise MalformedFile(f"{path}: line {line}: column {col!r}: {text!r} is not finite")
    return v


def read_sequence(path: str | Path, *, expected_rows: int | None = None, required_extra=()) -> Sequence:
    """Parse an impact-sequence CSV strictly; raise :class:`MalformedFile` with a one-line message."""
    path = Path(path)
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise MalformedFile(f"{path}: missing file") from None
    except (OSError, UnicodeDecodeError) as e:
        raise MalformedFile(f"{path}: cannot read: {e}") from None
    rows = list(csv.reader(text.splitlines()))
    if not rows:
        raise MalformedFile(f"{path}: line 1: empty file (expected header {','.join(COLUMNS)})")
    header = [h.strip() for h in rows[0]]
    for k, col in enumerate(COLUMNS):
        if col not in header:
            raise MalformedFile(f"{path}: line 1: missing column {col!r} (header must start with {','.join(COLUMNS)})")
        if k >= len(header) or header[k] != col:
            raise MalformedFile(f"{path}: line 1: wrong header {','.join(header)!r}: must start with {','.join(COLUMNS)}")
    for col in required_extra:
        if col not in header:
            raise MalformedFile(f"{path}: line 1: missing column {col!r}")
    idx = {h: i for i, h in enumerate(header)}
    data = [(i + 2, r) for i, r in enumerate(rows[1:]) if any(c.strip() for c in r)]
    if expected_rows is not None and len(data) != expected_rows:
        last = data[-1][0] if data else 1
        raise MalformedFile(f"{path}: line {last}: wrong row count: {len(data)} data rows, expected {expected_rows}")
    cols: dict[str, list] = {c: [] for c in header}
    for line, r in data:
        if len(r) < len(header):
            raise MalformedFile(f"{path}: line {line}: {len(r)} fields, expected {len(header)}")
        kind = r[idx["kind"]].strip()
        if kind not in KINDS:
            raise MalformedFile(f"{path}: line {line}: column 'kind': {kind!r} is not one of {', '.join(KINDS)}")
        cols["kind"].append(kind)
        cols["n"].append(_num(r[idx["n"]], path, line, "n", integer=True))
        w = _num(r[idx["wall"]], path, line, "wall", integer=True)
        if w not in (0, -1):
            raise MalformedFile(f"{path}: line {line}: column 'wall': {w} is not 0 or -1")
        cols["wall"].append(w)
        for c in ("tau", "tau_mod_2pi"):
            cols[c].append(_num(r[idx[c]], path, line, c))
        sd = _num(r[idx["sdot"]], path, line, "sdot", allow_empty=(kind != "impact"))
        cols["sdot"].append(sd)
        for c in required_extra:
            cols[c].append(_num(r[idx[c]], path, line, c, allow_empty=True))
    extra = {c: np.asarray(cols[c], dtype=float) for c in required_extra}
    return Sequence(str(path), np.asarray(cols["n"], dtype=np.int64), np.asarray(cols["tau"], dtype=float),
                    np.asarray(cols["tau_mod_2pi"], dtype=float), np.asarray(cols["wall"], dtype=np.int64),
                    np.asarray(cols["sdot"], dtype=float), np.asarray(cols["kind"], dtype=object), extra)


def _read_json(path: Path) -> dict:
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        raise MalformedFile(f"{path}: missing file") from None
    except json.JSONDecodeError as e:
        raise MalformedFile(f"{path}: line {e.lineno}: invalid JSON: {e.msg}") from None


SETTINGS_KEYS = ("id", "description", "params", "initial_state", "n_impacts", "stick_time", "expected_rows",
                 "expected_status", "tolerances")


def load_case(folder: str | Path) -> Case:
    """Load and validate one case folder."""
    folder = Path(folder)
    settings = _read_json(folder / "settings.json")
    for k in SETTINGS_KEYS:
        if k not in settings:
            raise MalformedFile(f"{folder / 'settings.json'}: missing key {k!r}")
    for c in TOLERANCE_COLUMNS:
        tol = settings["tolerances"].get(c)
        if not (isinstance(tol, dict) and {"abs", "rel"} <= set(tol) and tol["abs"] >= 0 and tol["rel"] >= 0):
            raise MalformedFile(f"{folder / 'settings.json'}: tolerances[{c!r}] must be {{'abs': >= 0, 'rel': >= 0}}")
    exp = read_sequence(folder / "expected.csv", expected_rows=settings["expected_rows"], required_extra=RADIUS_COLUMNS)
    return Case(settings["id"], folder, settings, exp)


def case_ids(suite: str | Path = DEFAULT_SUITE) -> list[str]:
    """Sorted case ids (folder names that contain a settings.json)."""
    suite = Path(suite)
    if not suite.is_dir():
        raise MalformedFile(f"{suite}: suite directory not found")
    return sorted(p.name for p in suite.iterdir() if (p / "settings.json").is_file())


def load_suite(suite: str | Path = DEFAULT_SUITE, cases: list[str] | None = None) -> list[Case]:
    """Load every case (or the listed ids) of a suite directory."""
    ids = case_ids(suite)
    if cases:
        unknown = [c for c in cases if c not in ids]
        if unknown:
            raise MalformedFile(f"{suite}: unknown case id(s): {', '.join(unknown)} (known: {', '.join(ids)})")
        ids = [c for c in ids if c in cases]
    return [load_case(Path(suite) / i) for i in ids]


# ---------------------------------------------------------------------------------------------
# scoring


@dataclass
class ColumnScore:
    column: str
    passed: bool
    max_error: float          # largest |x - e| (circular_distance for tau_mod_2pi; mismatch count for exact columns)
    worst_row: int            # 0-based data row of the largest violation ratio (or first mismatch), -1 if none
    digits: float             # min over rows of -log10(relative error), capped at DIGITS_CAP


@dataclass
class CaseScore:
    case: str
    passed: bool
    columns: dict
    message: str = ""

    @property
    def digits(self) -> float:
        if not self.columns:  # not comparable row by row (wrong number of events)
            return 0.0
        return min((c.digits for k, c in self.columns.items() if k in TOLERANCE_COLUMNS), default=DIGITS_CAP)


def _digits(err: np.ndarray, scale: np.ndarray) -> float:
    if err.size == 0:
        return DIGITS_CAP
    rel = err / np.maximum(np.abs(scale), 1e-300)
    worst = float(np.max(rel))
    if worst <= 0.0:
        return DIGITS_CAP
    return float(min(DIGITS_CAP, -math.log10(worst)))


def circular_distance(a, b) -> np.ndarray:
    """Distance between phases on the circle of length 2 pi, in [0, pi], for any real inputs.

    Values outside [0, 2 pi) are reduced first (a phase printed as 2 pi, -0.0 or unreduced denotes
    the phase it is congruent to), so a wrong value can never come out closer than it is: the naive
    ``min(|a - b|, 2 pi - |a - b|)`` goes negative, and passes, once ``|a - b| > 2 pi``.  Exact for
    ``|a - b| < pi``; NaN stays NaN.
    """
    raw = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    return np.abs(raw - TWO_PI * np.round(raw / TWO_PI))


def score_sequence(case: Case, got: Sequence) -> CaseScore:
    """Score one output against a case: pass/fail per column and digits of accuracy."""
    exp = case.expected
    if len(got) != len(exp):
        # a well-formed file with a different event sequence (e.g. a missed impact or sticking
        # episode) is a wrong answer, not a malformed file: the case fails
        k = min(len(got), len(exp))
        diff = np.nonzero((got.kind[:k] != exp.kind[:k]) | (got.wall[:k] != exp.wall[:k]))[0]
        where = (f"first differing event at line {int(diff[0]) + 2}" if diff.size
                 else f"the first {k} events agree in kind and wall")
        return CaseScore(case.id, False, {}, f"wrong number of events: {len(got)} rows, expected {len(exp)} "
                                             f"({where} of {got.path})")
    cols: dict[str, ColumnScore] = {}
    for c in EXACT_COLUMNS:
        a, e = getattr(got, c), getattr(exp, c)
        bad = np.nonzero(a != e)[0]
        cols[c] = ColumnScore(c, bad.size == 0, float(bad.size), int(bad[0]) if bad.size else -1,
                              DIGITS_CAP if bad.size == 0 else 0.0)
    for c in TOLERANCE_COLUMNS:
        tol = case.tolerances[c]
        a, e = getattr(got, c), getattr(exp, c)
        if c == "sdot":
            e_nan, a_nan = np.isnan(e), np.isnan(a)
            mask = ~e_nan
            # a value where the golden has none (stick/release rows) is ignored; a missing one fails
            missing = np.nonzero(mask & a_nan)[0]
        else:
            mask = np.ones(e.shape, dtype=bool)
            missing = np.empty(0, dtype=np.int64)
        diff = circular_distance(a, e) if c == "tau_mod_2pi" else np.abs(a - e)
        diff = np.where(mask, diff, 0.0)
        diff = np.where(np.isnan(diff), np.inf, diff)
        allowed = tol["abs"] + tol["rel"] * np.abs(np.where(mask, e, 0.0))
        ratio = np.where(mask, diff / np.maximum(allowed, 1e-300), 0.0)
        ok = bool(np.all(diff[mask] <= allowed[mask])) and missing.size == 0
        worst = int(missing[0]) if missing.size else (int(np.argmax(ratio)) if ratio.size and not ok else -1)
        # relative error; the scale is 2 pi for the phase and at least 1 for the elapsed time
        scale = np.full(e.shape, TWO_PI) if c == "tau_mod_2pi" else (np.maximum(np.abs(e), 1.0) if c == "tau" else e)
        cols[c] = ColumnScore(c, ok, float(np.max(diff[mask])) if mask.any() else 0.0, worst,
                              _digits(diff[mask], scale[mask]))
    passed = all(s.passed for s in cols.values())
    msg = ""
    if not passed:
        bad = [s for s in cols.values() if not s.passed]
        s = bad[0]
        line = s.worst_row + 2  # header is line 1
        msg = f"{s.column} differs at line {line} of {got.path}"
        if s.column in TOLERANCE_COLUMNS:
            msg += f" (|error| {s.max_error:.3g} > tolerance)"
    return CaseScore(case.id, passed, cols, msg)


def score_file(case: Case, path: str | Path) -> CaseScore:
    """Read ``path`` strictly and score it (a different number of events fails the case)."""
    got = read_sequence(path)
    return score_sequence(case, got)


def summary_table(scores: list[CaseScore]) -> str:
    """Plain-text table: case, verdict, digits per tolerance column, exact-column check, message."""
    head = f"{'case':<30} {'result':<6} {'tau':>6} {'tau%2pi':>7} {'sdot':>6}  n/wall/kind  note"
    lines = [head, "-" * len(head)]
    for s in scores:
        d = [s.columns[c].digits if c in s.columns else 0.0 for c in TOLERANCE_COLUMNS]
        ex = "ok" if all(c in s.columns and s.columns[c].passed for c in EXACT_COLUMNS) else "MISMATCH"
        lines.append(f"{s.case:<30} {'PASS' if s.passed else 'FAIL':<6} {d[0]:6.1f} {d[1]:7.1f} {d[2]:6.1f}  "
                     f"{ex:<11}  {s.message}")
    n_pass = sum(s.passed for s in scores)
    lines.append(f"{n_pass}/{len(scores)} cases pass (digits: min over rows of -log10 relative error, "
                 f"capped at {DIGITS_CAP:g})")
    return "\n".join(lines)


def sequence_from_impacts(seq, path: str = "<memory>") -> Sequence:
    """A :class:`Sequence` from a :class:`core.results.ImpactSequence` (any track)."""
    return Sequence(path, np.asarray(seq.n, dtype=np.int64), np.asarray(seq.tau, dtype=float),
                    np.asarray(seq.theta, dtype=float), np.asarray(seq.wall, dtype=np.int64),
                    np.asarray(seq.sdot, dtype=float), np.asarray(seq.kind, dtype=object))


def run_case(case: Case, track: str = "map"):
    """Run one of our tracks on a case's settings; returns the :class:`ImpactSequence`."""
    from ...core.params import Params
    from ...mapimpl.tracks import orbit

    s = case.settings
    p = Params(**s["params"])
    ini = s["initial_state"]
    return orbit(track, p, ini["tau0"], ini["sdot0"], int(s["n_impacts"]), s0=ini.get("s0"))
