"""Property-based mutation test of `gear-rattle check` (issue 30 item 1: never fooled).

The correct outputs of every case (its `expected.csv`, with and without the radius columns) and of
every orbit record (the midpoints of its intervals) are mutated by Hypothesis -- digits, signs,
exponents and spellings of numbers, values just inside and just outside the tolerance (to the ulp),
swapped / duplicated / dropped / added / renamed columns, rows and points, odd characters, blanks,
line ends, blank lines, quotes, duplicate keys, deep nesting, huge fields and files -- and each mutant
is scored twice: by the real command line (`main(["check", ...])`) and by an independent reading of
docs/golden.md written here (its own CSV tokenizer, its own decimal reader with exact rationals,
Python's json module with hooks for the JSON limits, 2 pi from mpmath; nothing of the checker's
parsers is imported).  The verdicts must agree: malformed -> exit 1 with one line on stderr naming a
line and column (an error of its case), outside a tolerance or a different event sequence -> exit 1 and
nothing on stderr, right -> exit 0.  So no
mutant that is wrong or malformed passes, and the checker never crashes.

Default: 15 mutants per case and orbit record, a fixed seed per case (495 per run: 34 s on the shared
2-core machine at load 16, 12 s of CPU; each mutant costs one full `check` run).  Long profile:
`GEAR_RATTLE_CHECK_MUTANTS=N` (N per case, random seeds; 80 per case: 2640 mutants, 94 s) or
`pytest -m slow` (200 per case).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import tempfile
import zlib
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.paths import DEFAULT_ORBITS
from gear_rattle.validation.golden.paths import DEFAULT_SUITE

mpmath = pytest.importorskip("mpmath")

# ------------------------------------------------------------------------------------------------
# docs/reference/golden_formats.md, "What check reads", restated

MAX_BYTES, MAX_JSON_BYTES, MAX_LINES = 2 * 1024 * 1024, 256 * 1024, 20_000
MAX_FIELD, MAX_COLUMNS, MAX_INT_DIGITS = 1000, 100, 18
MAX_DEPTH, MAX_STRING, MAX_NUMBER = 32, 10_000, 100
COLUMNS = ["n", "tau", "tau_mod_2pi", "wall", "sdot", "kind"]
DIGITS = "0123456789"
with mpmath.workdps(420):
    TWO_PI = Fraction(mpmath.nstr(2 * mpmath.pi, 410, strip_zeros=False))


class Malformed(Exception):
    pass


def _text(data: bytes, limit: int) -> str:
    """The text layer: size, UTF-8, one leading BOM, line count, the characters allowed."""
    if len(data) > limit:
        raise Malformed("size")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise Malformed("utf-8") from None
    if text[:1] == "\ufeff":
        text = text[1:]
    if text.count("\n") + (0 if text.endswith("\n") else 1) > MAX_LINES:
        raise Malformed("lines")
    for i, c in enumerate(text):
        o = ord(c)
        if c == "\r":
            if text[i + 1 : i + 2] != "\n":
                raise Malformed("lone CR")
        elif c in "\t\n":
            continue
        elif o < 0x20 or 0x7F <= o <= 0x9F or c in "\u2028\u2029\ufeff":
            raise Malformed(f"U+{o:04X}")
    return text


def _float64(sign: int, digits: str, exp10: int) -> Fraction:
    """The float64 nearest to sign * int(digits) * 10^exp10, as an exact rational (Malformed: overflow)."""
    m = int(digits)
    if m == 0:
        return Fraction(0)
    mag = len(str(m)) + exp10  # 10^(mag-1) <= value < 10^mag
    if mag > 310:
        raise Malformed("overflow")
    if mag < -330:
        return Fraction(0)
    try:
        f = float(Fraction(m) * Fraction(10) ** exp10)  # int / int: correctly rounded
    except OverflowError:
        raise Malformed("overflow") from None
    if math.isinf(f):
        raise Malformed("overflow")
    return sign * Fraction(f)


def _decimal(s: str) -> Fraction:
    """``[+-]?(digits[.[digits]] | .digits)([eE][+-]?digits)?`` in ASCII, read as the nearest float64."""
    i, sign = 0, 1
    if s[:1] in ("+", "-"):
        sign, i = (-1 if s[0] == "-" else 1), 1
    j = i
    while i < len(s) and s[i] in DIGITS:
        i += 1
    intd, frac = s[j:i], ""
    if s[i : i + 1] == ".":
        i += 1
        j = i
        while i < len(s) and s[i] in DIGITS:
            i += 1
        frac = s[j:i]
    if not intd and not frac:
        raise Malformed("number")
    exp = 0
    if s[i : i + 1] in ("e", "E"):
        i += 1
        esign = 1
        if s[i : i + 1] in ("+", "-"):
            esign, i = (-1 if s[i] == "-" else 1), i + 1
        j = i
        while i < len(s) and s[i] in DIGITS:
            i += 1
        if i == j:
            raise Malformed("exponent")
        exp = esign * int(s[j:i])
    if i != len(s):
        raise Malformed("number")
    return _float64(sign, intd + frac, exp - len(frac))


def _integer(s: str) -> int:
    """``[+-]?digits{1,18}(.0*)?``."""
    body = s[1:] if s[:1] in ("+", "-") else s
    whole, dot, zeros = body.partition(".")
    if not (1 <= len(whole) <= MAX_INT_DIGITS and all(c in DIGITS for c in whole) and set(zeros) <= {"0"}):
        raise Malformed("integer")
    return -int(whole) if s[:1] == "-" else int(whole)


def _fields(line: str) -> list[str]:
    """The CSV fields of one line: blanks around, quoted fields with "" inside, no other quote."""
    out, i, n = [], 0, len(line)
    while True:
        start = i
        while i < n and line[i] in " \t":
            i += 1
        if i < n and line[i] == '"':
            i += 1
            buf = []
            while True:
                if i >= n:
                    raise Malformed("open quote")
                if line[i] == '"':
                    if line[i + 1 : i + 2] == '"':
                        buf.append('"')
                        i += 2
                        continue
                    i += 1
                    break
                buf.append(line[i])
                i += 1
            while i < n and line[i] in " \t":
                i += 1
            if i < n and line[i] != ",":
                raise Malformed("after quote")
            value = "".join(buf)
        else:
            j = i
            while i < n and line[i] not in ',"':
                i += 1
            if i < n and line[i] == '"':
                raise Malformed("stray quote")
            value = line[j:i]
        if i - start > MAX_FIELD:
            raise Malformed("long field")
        out.append(value.strip(" \t"))
        if i >= n:
            return out
        i += 1


def read_rows(data: bytes) -> list[tuple]:
    """An impact-sequence file as rows ``(n, tau, tau_mod_2pi, wall, sdot or None, kind)``."""
    header, rows = None, []
    for line in _text(data, MAX_BYTES).split("\n"):
        line = line[:-1] if line.endswith("\r") else line
        if all(c in " \t" for c in line):
            continue
        f = _fields(line)
        if header is None:
            if len(f) > MAX_COLUMNS or "" in f or len(set(f)) != len(f) or f[:6] != COLUMNS:
                raise Malformed("header")
            header = f
            continue
        if len(f) != len(header):
            raise Malformed("field count")
        wall = _integer(f[3])
        if wall not in (0, -1) or f[5] not in ("impact", "stick", "release"):
            raise Malformed("wall/kind")
        if f[5] == "impact":
            sdot = _decimal(f[4])
        elif f[4] == "" or f[4].lstrip("+-").lower() == "nan" and len(f[4]) - len(f[4].lstrip("+-")) <= 1:
            sdot = None
        else:
            raise Malformed("sdot")
        rows.append((_integer(f[0]), _decimal(f[1]), _decimal(f[2]), wall, sdot, f[5]))
    if header is None:
        raise Malformed("empty")
    return rows


#: settings.json's pointer to the per-row tolerances of expected.csv, and its columns (suite 2.0.0).
TOL_COLUMNS = {"tau": "tau_tol", "tau_mod_2pi": "tau_mod_2pi_tol", "sdot": "sdot_tol"}
POINTER = {"file": "expected.csv", "columns": TOL_COLUMNS}


def _absent(cell: str) -> bool:
    return cell == "" or cell.lstrip("+-").lower() == "nan" and len(cell) - len(cell.lstrip("+-")) <= 1


def read_tolerances(data: bytes, settings: dict) -> list[dict]:
    """The absolute tolerance of every row of an expected.csv per column: with ``row_tolerances`` in the
    settings (it must be the pointer above), the ``*_tol`` cells (a decimal literal, finite, >= 0; on a
    stick or release row ``sdot_tol`` is empty or nan); without it, settings' ``abs`` for every row."""
    rows = read_rows(data)
    if "row_tolerances" not in settings:
        return [{c: Fraction(settings["tolerances"][c]["abs"]) for c in TOL_COLUMNS}] * len(rows)
    if settings["row_tolerances"] != POINTER:
        raise Malformed("pointer")
    lines = [ln[:-1] if ln.endswith("\r") else ln for ln in _text(data, MAX_BYTES).split("\n")]
    lines = [ln for ln in lines if not all(c in " \t" for c in ln)]
    header = _fields(lines[0])
    if any(name not in header for name in TOL_COLUMNS.values()):
        raise Malformed("tolerance column")
    out = []
    for line in lines[1:]:
        f, tol = _fields(line), {}
        for c, name in TOL_COLUMNS.items():
            cell = f[header.index(name)]
            if c == "sdot" and f[5] != "impact":
                if not _absent(cell):
                    raise Malformed("sdot_tol on a stick/release row")
                continue
            if _absent(cell):
                raise Malformed("missing tolerance")
            tol[c] = _decimal(cell)
            if tol[c] < 0:
                raise Malformed("negative tolerance")
            if tol[c] >= Fraction(1e-4):  # every tolerance a suite states is below 1e-4 (docs/golden.md)
                raise Malformed("tolerance out of range")
        out.append(tol)
    return out


def circ(d: Fraction) -> Fraction:
    """Distance of d to the nearest multiple of 2 pi."""
    k = math.floor(d / TWO_PI + Fraction(1, 2))
    return min(abs(d - j * TWO_PI) for j in (k - 1, k, k + 1))


def case_verdict(cid: str, data: bytes, suite: Path = DEFAULT_SUITE) -> str:
    """The verdict on an output ``data`` of case ``cid`` of ``suite``: the suite is read first (a malformed
    expected.csv is a malformed run), each row against its own tolerance."""
    settings = json.loads((suite / cid / "settings.json").read_text())
    try:
        exp_data = (suite / cid / "expected.csv").read_bytes()
        exp, tols = read_rows(exp_data), read_tolerances(exp_data, settings)
    except Malformed:
        return "malformed-suite"
    try:
        got = read_rows(data)
    except Malformed:
        return "malformed"
    rel = settings["tolerances"]
    if len(got) != len(exp):
        return "wrong"
    for g, e, tol in zip(got, exp, tols):
        if (g[0], g[3], g[5]) != (e[0], e[3], e[5]):
            return "wrong"
        for k, col in ((1, "tau"), (2, "tau_mod_2pi"), (4, "sdot")):
            if e[k] is None:
                continue
            d = g[k] - e[k]
            err = circ(d) if col == "tau_mod_2pi" else abs(d)
            if err > tol[col] + Fraction(rel[col]["rel"]) * abs(e[k]):
                return "wrong"
    return "right"


# --- JSON: Python's json module, with the format's limits as hooks


class Num:
    def __init__(self, lit: str):
        if len(lit) > MAX_NUMBER:
            raise Malformed("long number")
        self.value = _decimal(lit)


def _pairs(pairs):
    keys = [k for k, _ in pairs]
    if len(set(keys)) != len(keys):
        raise Malformed("duplicate key")
    return dict(pairs)


def _constant(name):
    raise Malformed(name)


def _depth(text: str) -> int:
    depth = best = 0
    in_str = esc = False
    for c in text:
        if in_str:
            if esc:
                esc = False
            elif c == "\\":
                esc = True
            elif c == '"':
                in_str = False
        elif c == '"':
            in_str = True
        elif c in "[{":
            depth += 1
            best = max(best, depth)
        elif c in "]}":
            depth -= 1
    return best


def _strings_ok(v) -> None:
    if isinstance(v, str):
        if len(v) > MAX_STRING or any("\ud800" <= c <= "\udfff" for c in v):
            raise Malformed("string")
    elif isinstance(v, dict):
        for k, x in v.items():
            _strings_ok(k)
            _strings_ok(x)
    elif isinstance(v, list):
        for x in v:
            _strings_ok(x)


def read_json(data: bytes) -> dict:
    text = _text(data, MAX_JSON_BYTES)
    if _depth(text) > MAX_DEPTH:
        raise Malformed("depth")
    try:
        v = json.loads(text, object_pairs_hook=_pairs, parse_constant=_constant, parse_float=Num, parse_int=Num)
    except (json.JSONDecodeError, RecursionError):
        raise Malformed("json") from None
    if not isinstance(v, dict):
        raise Malformed("not an object")
    _strings_ok(v)
    return v


def _num(x) -> Fraction:
    if not isinstance(x, Num):
        raise Malformed("not a number")
    return x.value


def _objects(d, key) -> list:
    v = d[key]
    if not (isinstance(v, list) and v and all(isinstance(p, dict) for p in v)):
        raise Malformed(key)
    return v


def _interval_dist(x: Fraction, lo: Fraction, hi: Fraction, circular=False) -> Fraction:
    if circular:
        return max(circ(x - (lo + hi) / 2) - (hi - lo) / 2, Fraction(0))
    return max(lo - x, x - hi, Fraction(0))


def _record(rid: str) -> dict:
    def num(lit):
        return Fraction(float(lit))

    return json.loads((DEFAULT_ORBITS / f"{rid}.json").read_text(), parse_float=num)


def orbit_verdict(rid: str, data: bytes) -> str:
    rec = _record(rid)
    try:
        d = read_json(data)
        need = ("points", "multipliers") if rec["kind"] == "periodic-orbit" else ("value",)
        if any(k not in d for k in need):
            raise Malformed("missing key")
        pts = mult = value = None
        if "points" in d:
            pts = []
            for p in _objects(d, "points"):
                w = _num(p.get("wall"))
                if w not in (0, -1):
                    raise Malformed("wall")
                pts.append((_num(p.get("tau_mod_2pi")), _num(p.get("sdot")), int(w)))
        if "multipliers" in d:
            mult = [
                (_num(m.get("re")), _num(m["im"]) if "im" in m else Fraction(0)) for m in _objects(d, "multipliers")
            ]
        if "value" in d:
            value = _num(d["value"])
    except Malformed:
        return "malformed"
    tol = rec["tolerances"]
    ok = True
    if pts is not None:
        n = len(rec["points"])
        good = False
        for k in range(n) if len(pts) == n else []:
            rot = pts[k:] + pts[:k]
            if [p[2] for p in rot] != [q["wall"] for q in rec["points"]]:
                continue
            good = good or all(
                _interval_dist(p[0], *q["tau_mod_2pi"], circular=True) <= Fraction(tol["tau_mod_2pi"])
                and _interval_dist(p[1], *q["sdot"]) <= Fraction(tol["sdot"])
                for p, q in zip(rot, rec["points"])
            )
        ok = ok and good
    if mult is not None:
        m = rec["multipliers"]
        perms = ([0, 1], [1, 0]) if len(m) == 2 else [list(range(len(m)))]
        ok = (
            ok
            and len(mult) == len(m)
            and any(
                all(
                    max(_interval_dist(mult[i][0], *q["re"]), _interval_dist(mult[i][1], *q["im"]))
                    <= Fraction(tol["multipliers"])
                    for i, q in zip(perm, m)
                )
                for perm in perms
            )
        )
    if rec["kind"] != "periodic-orbit":
        ok = ok and _interval_dist(value, *rec["value"]) <= Fraction(tol["value"])
    return "right" if ok else "wrong"


# ------------------------------------------------------------------------------------------------
# the checker


def run_check(folder: Path, cid: str, orbits: bool, suite: Path | None = None) -> tuple[int, list[str]]:
    out, err = io.StringIO(), io.StringIO()
    argv = ["check", *(["--orbits"] if orbits else []), str(folder), "--cases", cid, "--summary"]
    argv += ["--suite", str(suite)] if suite is not None else []
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, err.getvalue().splitlines()


# a malformed output is an error of its case (exit 1); a malformed suite is a usage error (exit 2)
EXIT = {"right": 0, "wrong": 1, "malformed": 1, "malformed-suite": 2}


def _agree(verdict: str, rc: int, err: list[str], data: bytes) -> None:
    assert rc in (0, 1, 2)
    assert rc == EXIT[verdict], (verdict, rc, err, data[:300])
    if verdict.startswith("malformed"):  # told apart from a wrong answer by its one line on stderr
        assert len(err) == 1 and "line " in err[0] and ", column " in err[0], err
    else:
        assert err == [], (verdict, err, data[:300])


# ------------------------------------------------------------------------------------------------
# mutations

ODD = [
    "\x00",
    "\x01",
    "\t",
    "\x0b",
    "\x0c",
    "\r",
    "\x1c",
    "\x1e",
    "\x7f",
    "\x85",
    "\xa0",
    "\u2028",
    "\u2029",
    "\ufeff",
    "\u0662",
    "\uff11",
    "\u200b",
    "é",
    " ",
    ",",
    '"',
    "\n",
    "\r\n",
    "'",
    "\\",
    "{",
    "}",
    "[",
    "]",
    ":",
    "e",
    "E",
    "-",
    "+",
    ".",
    "0",
    "9",
    "_",
    "x",
]
#: The characters the format refuses (the checker must find them even where the content is ignored).
REFUSED = ["\x00", "\x0b", "\x1f", "\x7f", "\x85", "\x9f", "\u2028", "\u2029", "\ufeff", "\r"]
SPELLINGS = [
    "nan",
    "NaN",
    "-nan",
    "+NAN",
    "inf",
    "-inf",
    "Infinity",
    "-Infinity",
    "1e999",
    "-1e400",
    "1e-400",
    "0x1p-2",
    "1_0",
    "",
    " ",
    "١",
    "1.5.2",
    "--1",
    "+-1",
    ".",
    "e5",
    "1e",
    "1e+",
    ".5",
    "5.",
    "00012",
    "1E+00",
    "1e0000000000000000001",
    "-0",
    "+0.0",
    "0e99999",
    "1" * 30,
    "0." + "0" * 400 + "1",
    "9" * 400,
    "null",
    "true",
    '"1.5"',
    "[]",
    "{}",
]


def _num_text(x: float, style: int) -> str:
    return [repr(x), f"{x:.17e}", f"{x:.25g}", f"{x:.17E}", f"{x:+.20f}", f"{x:.16g}", f"{x:.3g}"][style % 7]


@st.composite
def near_values(draw, golden: float, tol: float, circular: bool = False):
    """A value at a multiple of the tolerance from the golden one (exact boundary, a few ulps off),
    or another mutation of it (sign, digits, 2 pi turns for a phase)."""
    if not isinstance(golden, float):  # already replaced by another spelling
        return golden
    kind = draw(st.integers(0, 5))
    if kind == 0:
        m = draw(st.sampled_from([0.0, 0.5, 0.999, 1.0, 1.001, 2.0, 1e3, 1e9]))
        x = golden + draw(st.sampled_from([1.0, -1.0])) * m * tol
        for _ in range(draw(st.integers(0, 3))):
            x = math.nextafter(x, draw(st.sampled_from([math.inf, -math.inf])))
        return x
    if kind == 1:
        return -golden
    if kind == 2 and circular:
        return golden + draw(st.integers(-(10**6), 10**6)) * 2 * math.pi + draw(st.sampled_from([0, tol, -2 * tol]))
    if kind == 3:
        return golden * (1 + draw(st.sampled_from([1e-17, 1e-15, 1e-12, 1e-9, 1e-6, 0.1])))
    if kind == 4:
        return draw(st.floats(allow_nan=False, allow_infinity=False))
    return golden


# --- cases

CASE_IDS = sorted(p.name for p in DEFAULT_SUITE.iterdir() if (p / "settings.json").is_file())


def _is_float(text: str) -> bool:
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


def _case_rows(cid: str, extra: bool) -> list[list[str]]:
    """The rows of the case's expected.csv, with its extra columns (radii, tolerances) or without."""
    rows = [r.split(",") for r in (DEFAULT_SUITE / cid / "expected.csv").read_text().splitlines()]
    return rows if extra else [r[:6] for r in rows]


def _row_tolerances(cid: str) -> list[dict]:
    settings = json.loads((DEFAULT_SUITE / cid / "settings.json").read_text())
    return read_tolerances((DEFAULT_SUITE / cid / "expected.csv").read_bytes(), settings)


@st.composite
def case_mutant(draw, cid: str) -> bytes:
    rows = _case_rows(cid, draw(st.booleans()))
    tols = _row_tolerances(cid)
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from([0, 0, 1, 2, 2, 3, 4, 4, 5, 5, 5, 6, 7, 8, 9, 9, 10]))
        r = draw(st.integers(1, len(rows) - 1)) if len(rows) > 1 else 0
        c = min(draw(st.integers(0, len(rows[0]) - 1)), len(rows[r]) - 1)
        if op in (0, 1) and r > 0 and c in (1, 2, 4) and _is_float(rows[r][c]):
            col = COLUMNS[c]
            scale = tols[(r - 1) % len(tols)].get(col, Fraction(1, 10**12))  # the row's tolerance (rows may move)
            x = draw(near_values(float(rows[r][c]), float(scale), col == "tau_mod_2pi"))
            rows[r][c] = _num_text(x, draw(st.integers(0, 6)))
        elif op == 2 and r > 0:  # a field spelled otherwise, or another value
            rows[r][c] = draw(
                st.sampled_from(
                    SPELLINGS
                    + [
                        rows[r][c].strip(),
                        f'"{rows[r][c]}"',
                        f' "{rows[r][c]}"\t',
                        f" {rows[r][c]} ",
                        f'"{rows[r][c]}""',
                        '"a""b"',
                    ]
                )
            )
        elif op == 3 and r > 0:  # exact columns
            rows[r][c] = draw(
                st.sampled_from(
                    [
                        "0",
                        "-1",
                        "1",
                        "-0",
                        "+0",
                        "0.0",
                        "-1.",
                        "1e0",
                        "2.5",
                        "impact",
                        "stick",
                        "release",
                        "Impact",
                        "3",
                        "-2",
                        "+2.00",
                    ]
                )
            )
        elif op == 4:  # rows: swap, duplicate, drop
            if len(rows) > 2:
                s = draw(st.integers(1, len(rows) - 1))
                how = draw(st.integers(0, 2))
                if how == 0:
                    rows[r], rows[s] = rows[s], rows[r]
                elif how == 1:
                    rows.insert(s, list(rows[r]))
                else:
                    del rows[r]
        elif op == 5:  # columns: swap, duplicate (same name, other values), drop, add, rename
            how = draw(st.integers(0, 4))
            d = draw(st.integers(0, len(rows[0]) - 1))
            for k, row in enumerate(rows):
                if max(c, d) >= len(row):
                    continue
                if how == 0:
                    row[c], row[d] = row[d], row[c]
                elif how == 1:
                    row.append(row[c] if k == 0 else draw(st.sampled_from([row[c], "0", "1.5", ""])))
                elif how == 2:
                    del row[c]
                elif how == 3:
                    row.append(draw(st.sampled_from(["extra", "", "n", "tau", "x y"])) if k == 0 else "1")
                elif k == 0:
                    row[c] = draw(st.sampled_from(["Tau", "tau ", "t", "kind", "tau_radius", ""]))
        elif op == 6:  # a huge field
            rows[r][c] = rows[r][c] + draw(st.sampled_from([" " * 1000, "0" * 990, "1" * 2000]))
        elif op == 7:  # trailing / missing field
            rows[r] = rows[r] + [""] if draw(st.booleans()) else rows[r][:-1]
        elif op == 8:  # an added row
            rows.append(list(rows[-1]) if draw(st.booleans()) else ["0", "0", "0", "0", "1", "impact"][: len(rows[0])])
        elif op == 9:  # an extra column whose text is ignored, but not its characters, quotes or length
            name = draw(st.sampled_from(["note", "tau", "kind", "", '"note"', "no\u2028te", "n o"]))
            odd = draw(st.sampled_from(REFUSED + ODD))
            cells = draw(st.sampled_from(["a", f"a{odd}b", f'"a{odd}b"', f'"{odd}"', "x" * 1001, '"x""y"']))
            for k, row in enumerate(rows):
                row.append(name if k == 0 else (cells if k == r else "a"))
        elif op == 10 and r > 0:  # the whole row quoted field by field
            rows[r] = [f'"{v}"' for v in rows[r]]
    eol = draw(st.sampled_from(["\n", "\r\n", "\n", "\n", "\r\n", "\n", "\n", "\r"]))
    text = eol.join(",".join(r) for r in rows) + draw(st.sampled_from([eol, "", eol + eol, "\n \t\n"]))
    for _ in range(draw(st.sampled_from([0, 0, 0, 1, 2]))):  # odd characters, blank lines, a BOM
        pos = draw(st.integers(0, len(text)))
        text = text[:pos] + draw(st.sampled_from(ODD + REFUSED + ["\n\n", "\n \t \n"])) + text[pos:]
    if draw(st.integers(0, 9)) == 0:
        text = "\ufeff" + text
    data = text.encode("utf-8")
    big = draw(st.integers(0, 40))
    if big == 0:  # beyond the line limit (blank lines) or just within it
        data += b"\n" * draw(st.sampled_from([MAX_LINES, MAX_LINES - len(rows) - 2]))
    elif big == 1:
        data += b"\xff" if draw(st.booleans()) else b"\xc3"
    return data


def _n_mutants() -> int:
    return int(os.environ.get("GEAR_RATTLE_CHECK_MUTANTS", "15"))


def _settings(n: int, key: str):
    """``n`` examples; the default run is reproducible and each case or record has its own seed (one
    seed for all would give each the same mutation recipes), the long profile is random."""

    def deco(f):
        f = settings(max_examples=n, deadline=None, database=None, suppress_health_check=list(HealthCheck))(f)
        return f if "GEAR_RATTLE_CHECK_MUTANTS" in os.environ else seed(zlib.crc32(key.encode()))(f)

    return deco


def _check_case(cid: str, n: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)

        @_settings(n, cid)
        @given(data=case_mutant(cid))
        def prop(data):
            (folder / f"{cid}.csv").write_bytes(data)
            rc, err = run_check(folder, cid, False)
            _agree(case_verdict(cid, data), rc, err, data)

        prop()


@pytest.mark.parametrize("cid", CASE_IDS)
def test_case_mutants(cid):
    _check_case(cid, _n_mutants())


@pytest.mark.slow
@pytest.mark.parametrize("cid", CASE_IDS)
def test_case_mutants_long(cid):
    _check_case(cid, 200)


# --- the suite's per-row tolerance cells (suite 2.0.0: expected.csv's *_tol columns)

TOL_SPELLINGS = [
    "",
    " ",
    "nan",
    "-nan",
    "inf",
    "-1e-15",
    "-0",
    "-0.0",
    "0",
    "0e0",
    "1e-400",
    "1e999",
    "1e300",
    "0x1p-40",
    "1_0e-13",
    "abc",
    "\u0661e-12",
    '"1e-12"',
    ' "1e-12" ',
    '"1e-12',
    "1e-12 1",
]


@st.composite
def tolerance_mutant(draw, cid: str) -> tuple[bytes, bytes]:
    """``(expected.csv, output)``: the case's expected.csv with tolerance cells (and their header) mutated,
    and the correct output with values moved near the row's tolerance (the mutated one where it is a number)."""
    rows = _case_rows(cid, True)
    out = [r[:6] for r in rows]
    header = rows[0]
    tcols = {header.index(name): c for c, name in TOL_COLUMNS.items()}
    for _ in range(draw(st.integers(1, 4))):
        r = draw(st.integers(1, len(rows) - 1))
        k = draw(st.sampled_from(sorted(tcols)))
        col = tcols[k]
        op = draw(st.integers(0, 5))
        if op == 0:  # the cell spelled otherwise (or another value)
            rows[r][k] = draw(st.sampled_from(TOL_SPELLINGS + [rows[r][k], f'"{rows[r][k]}"', f" {rows[r][k]}\t"]))
        elif op == 1 and _is_float(rows[r][k]):  # the tolerance scaled
            x = float(rows[r][k]) * draw(st.sampled_from([0.0, 0.5, 0.999, 1.001, 2.0, 1e6]))
            rows[r][k] = _num_text(x, draw(st.integers(0, 6)))
        elif op == 2 and draw(st.integers(0, 3)) == 0:  # the column's name changed, or the column dropped
            if draw(st.booleans()):
                rows[0][k] = draw(st.sampled_from(["tau_tol ", "Tau_tol", "tol", "tau_radius", "sdot_tol", ""]))
            else:
                for row in rows:
                    del row[k]
                break
        else:  # the output's value of this row near its tolerance
            c = COLUMNS.index(col)
            if _is_float(rows[r][k]) and _is_float(out[r][c]):
                x = draw(near_values(float(out[r][c]), float(rows[r][k]), col == "tau_mod_2pi"))
                out[r][c] = _num_text(x, draw(st.integers(0, 6)))
    return ("\n".join(",".join(r) for r in rows) + "\n").encode(), ("\n".join(",".join(r) for r in out) + "\n").encode()


def _check_tolerances(cid: str, n: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        suite, folder = Path(tmp) / "suite", Path(tmp) / "out"
        folder.mkdir()
        (suite / cid).mkdir(parents=True)
        for name in ("settings.json", "provenance.json"):
            (suite / cid / name).write_bytes((DEFAULT_SUITE / cid / name).read_bytes())

        @_settings(n, "tol" + cid)
        @given(data=tolerance_mutant(cid))
        def prop(data):
            expected, output = data
            (suite / cid / "expected.csv").write_bytes(expected)
            (folder / f"{cid}.csv").write_bytes(output)
            rc, err = run_check(folder, cid, False, suite)
            _agree(case_verdict(cid, output, suite), rc, err, expected)

        prop()


@pytest.mark.parametrize("cid", CASE_IDS)
def test_tolerance_cell_mutants(cid):
    """Mutated per-row tolerance cells of a suite: the checker reads them as docs/golden.md says (each row
    against its own; a cell outside the forms, a missing or renamed column: a malformed suite, exit 2)."""
    _check_tolerances(cid, _n_mutants())


@pytest.mark.slow
@pytest.mark.parametrize("cid", CASE_IDS)
def test_tolerance_cell_mutants_long(cid):
    _check_tolerances(cid, 200)


# --- orbit records

RECORD_IDS = sorted(p.stem for p in DEFAULT_ORBITS.glob("*.json"))


def _mid(iv) -> float:
    return (iv[0] + iv[1]) / 2


@st.composite
def orbit_mutant(draw, rid: str) -> bytes:
    rec = json.loads((DEFAULT_ORBITS / f"{rid}.json").read_text())
    tol = rec["tolerances"]
    pts = [
        [["tau_mod_2pi", _mid(p["tau_mod_2pi"])], ["sdot", _mid(p["sdot"])], ["wall", p["wall"]]] for p in rec["points"]
    ]
    mult = [[["re", _mid(m["re"])], ["im", _mid(m["im"])]] for m in rec["multipliers"]]
    top = [["points", pts], ["multipliers", mult]]
    if "value" in rec:
        top.append(["value", _mid(rec["value"])])
    if rec["kind"] != "periodic-orbit" and draw(st.booleans()):
        top = [kv for kv in top if kv[0] == "value" or draw(st.booleans())]
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.integers(0, 10))
        if op == 10:  # an ignored key whose string holds a character the format refuses (or one it allows)
            odd = draw(st.sampled_from(REFUSED + ["\t", "é", "\\u2028", "\\u0000", "\\ud800", "\\ud83d\\ude00", "\\x"]))
            top.insert(draw(st.integers(0, len(top))), ["note", "\x00" + '"a' + odd + 'b"'])
        elif op in (0, 1, 2):  # a value near its tolerance (or otherwise changed)
            which = draw(st.integers(0, 2))
            if which == 0 and pts:
                p = draw(st.sampled_from(pts))
                k = draw(st.integers(0, 1))
                col = p[k][0]
                if col in tol:
                    p[k][1] = draw(near_values(p[k][1], tol[col], col == "tau_mod_2pi"))
            elif which == 1 and mult:
                m = draw(st.sampled_from(mult))
                k = draw(st.integers(0, len(m) - 1))
                m[k][1] = draw(near_values(m[k][1], tol["multipliers"]))
            elif "value" in rec:
                for kv in top:
                    if kv[0] == "value":
                        kv[1] = draw(near_values(kv[1], tol["value"]))
        elif op == 3 and pts:  # rotate (right), reverse, drop, duplicate
            how = draw(st.integers(0, 3))
            k = draw(st.integers(0, len(pts) - 1))
            if how == 0:
                pts[:] = pts[k:] + pts[:k]
            elif how == 1:
                pts.reverse()
            elif how == 2:
                del pts[k]
            else:
                pts.insert(k, pts[k])
        elif op == 4 and pts:  # walls
            p = draw(st.sampled_from(pts))
            p[2][1] = draw(
                st.sampled_from(
                    [
                        0,
                        -1,
                        -1.0,
                        0.0,
                        -0.0,
                        "\x001e-400",
                        True,
                        None,
                        "0",
                        2,
                        -2,
                        "\x00-1e0",
                        "\x00-10e-1",
                        "\x00-1.0000000000000000001",
                    ]
                )
            )
        elif op == 5:  # multipliers: swap (right), drop im (right when 0), conjugate
            how = draw(st.integers(0, 2))
            if how == 0:
                mult.reverse()
            elif how == 1 and mult:
                del mult[0][1:]
            elif mult and len(mult[0]) > 1 and isinstance(mult[0][1][1], float):
                mult[0][1][1] = -mult[0][1][1]
        elif op == 6:  # a number's value replaced by another spelling or type
            target = draw(st.sampled_from(["point", "mult", "top"]))
            spelled = "\x00" + draw(
                st.sampled_from(SPELLINGS + ["1" * 100, "1" * 101, "-" + "1" * 99, "1." + "0" * 98, "1e-99999"])
            )
            if target == "point" and pts:
                draw(st.sampled_from(pts))[draw(st.integers(0, 1))][1] = spelled
            elif target == "mult" and mult and mult[0]:
                mult[0][0][1] = spelled
            elif top:
                top[-1][1] = spelled
        elif op == 7:  # keys: duplicate (after escapes too), delete, unknown, misspelt
            how = draw(st.integers(0, 3))
            if how == 0 and top:
                kv = draw(st.sampled_from(top))
                top.append([draw(st.sampled_from([kv[0], "\x01\\u00" + hex(ord(kv[0][0]))[2:] + kv[0][1:]])), kv[1]])
            elif how == 1 and top:
                del top[draw(st.integers(0, len(top) - 1))]
            elif how == 2:
                top.insert(
                    0,
                    [
                        draw(
                            st.sampled_from(
                                ["note", "Points", "values", "\x01\\ud800", "\x01\\u2028", "x" * 10_001, "x" * 10_000]
                            )
                        ),
                        draw(st.sampled_from([1, "s", None])),
                    ],
                )
            elif pts:
                p = draw(st.sampled_from(pts))
                p.append([draw(st.sampled_from(["wall", "sdot", "extra"])), 0])
        elif op == 8:  # deep nesting (at, just beyond the limit)
            depth = draw(st.sampled_from([30, 31, 32, 33, 1000]))
            top.append(["deep", "\x00" + "[" * depth + "]" * depth])
        elif op == 9 and pts:  # swap two columns' keys
            p = draw(st.sampled_from(pts))
            p[0][0], p[1][0] = p[1][0], p[0][0]  # (each point has its 3 pairs first)
    style = draw(st.integers(0, 6))
    ws = draw(st.sampled_from(["", " ", "\n", "\t", "\r\n", "\r", "\n  "]))

    def ser(v) -> str:
        if isinstance(v, bool) or v is None:
            return json.dumps(v)
        if isinstance(v, float):
            return _num_text(v, style) if math.isfinite(v) else "NaN"
        if isinstance(v, int):
            return str(v)
        if isinstance(v, str):
            if v.startswith("\x00"):
                return v[1:]  # raw text
            return '"' + (v[1:] if v.startswith("\x01") else v) + '"'
        if v and isinstance(v[0], list) and len(v[0]) == 2 and isinstance(v[0][0], str):  # pairs: an object
            return "{" + ("," + ws).join(f"{ser(k)}{ws}:{ws}{ser(x)}" for k, x in v) + "}"
        return "[" + ("," + ws).join(ser(x) for x in v) + "]"

    text = ws + ser(top) + draw(st.sampled_from(["", "\n", " ", "\n\n", ",", "}"]))
    for _ in range(draw(st.integers(0, 1))):
        pos = draw(st.integers(0, len(text)))
        text = text[:pos] + draw(st.sampled_from(ODD + REFUSED)) + text[pos:]
    if draw(st.integers(0, 9)) == 0:
        text = "\ufeff" + text
    return text.encode("utf-8")


def _check_orbit(rid: str, n: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)

        @_settings(n, rid)
        @given(data=orbit_mutant(rid))
        def prop(data):
            (folder / f"{rid}.json").write_bytes(data)
            rc, err = run_check(folder, rid, True)
            _agree(orbit_verdict(rid, data), rc, err, data)

        prop()


@pytest.mark.parametrize("rid", RECORD_IDS)
def test_orbit_mutants(rid):
    _check_orbit(rid, _n_mutants())


@pytest.mark.slow
@pytest.mark.parametrize("rid", RECORD_IDS)
def test_orbit_mutants_long(rid):
    _check_orbit(rid, 200)


def test_the_independent_reading_accepts_the_correct_outputs():
    """The reading above is not vacuous: every expected.csv is right, and a value 2 tolerances off is wrong."""
    for cid in CASE_IDS:
        data = (DEFAULT_SUITE / cid / "expected.csv").read_bytes()
        assert case_verdict(cid, data) == "right", cid
    rows = _case_rows(CASE_IDS[0], False)
    tol = float(_row_tolerances(CASE_IDS[0])[2]["tau"])
    rows[3][1] = repr(float(rows[3][1]) + 2 * tol)  # 2 times the row's own tolerance
    assert case_verdict(CASE_IDS[0], "\n".join(",".join(r) for r in rows).encode()) == "wrong"
    rows[3][1] = repr(float(_case_rows(CASE_IDS[0], False)[3][1]) + 0.5 * tol)
    assert case_verdict(CASE_IDS[0], "\n".join(",".join(r) for r in rows).encode()) == "right"
    # a suite without the pointer: settings' abs for every row (the 1.0.0 reading)
    old = json.loads((DEFAULT_SUITE / CASE_IDS[0] / "settings.json").read_text())
    del old["row_tolerances"]
    tols = read_tolerances((DEFAULT_SUITE / CASE_IDS[0] / "expected.csv").read_bytes(), old)
    assert all(t["tau"] == Fraction(old["tolerances"]["tau"]["abs"]) for t in tols)
