"""`gear-rattle check` (docs/golden.md): the circular comparison of `tau_mod_2pi` for any value.

The output of a perfect implementation is stood in for by the certified `expected.csv` itself (extra
trailing columns are ignored), so these tests run no track and no JAX."""

import csv
import math
import shutil

import numpy as np
import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.formats.cases import case_ids, load_case
from gear_rattle.validation.golden.scoring.cases import circular_distance

TWO_PI = 2 * math.pi


def test_circular_distance_any_real():
    """In [0, pi] for any finite inputs; exact for small differences; never negative (the old
    min(d, 2 pi - d) was -987 for 1000 vs 6.28 and so passed any tolerance)."""
    assert circular_distance(1000.0, 1.0) == pytest.approx(abs(1000.0 - 1.0 - 159 * TWO_PI), abs=1e-12)
    assert circular_distance(1.0 + 3 * TWO_PI, 1.0) == pytest.approx(0.0, abs=1e-14)
    assert circular_distance(-1e-3, TWO_PI - 2e-3) == pytest.approx(1e-3, abs=1e-15)
    # the double nearest 2 pi lies 2.449e-16 below it: that is its exact distance to phase 0
    assert circular_distance(TWO_PI, 0.0) == pytest.approx(2.4492935982947064e-16, rel=1e-15)
    assert circular_distance(0.5 + 1e-17, 0.5) == abs((0.5 + 1e-17) - 0.5)
    rng = np.random.default_rng(0)
    a, b = rng.uniform(-1e4, 1e4, 1000), rng.uniform(0, TWO_PI, 1000)
    d = circular_distance(a, b)
    assert np.all((d >= 0) & (d <= math.pi + 1e-9))
    assert np.isnan(circular_distance(np.nan, 1.0))


def _copy_expected(dst, ids):
    dst.mkdir()
    for cid in ids:
        shutil.copy(DEFAULT_SUITE / cid / "expected.csv", dst / f"{cid}.csv")


def _set_column(path, column, fn):
    rows = list(csv.reader(path.read_text().splitlines()))
    j = rows[0].index(column)
    for r in rows[1:]:
        r[j] = repr(fn(float(r[j])))
    with open(path, "w", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerows(rows)


def test_check_fails_a_phase_more_than_2pi_off(tmp_path, capsys):
    """The reproduction of issue 11: every tau_mod_2pi set to 1000.0 gave 11/11 pass."""
    ids = case_ids()
    d = tmp_path / "out"
    _copy_expected(d, ids)
    assert main(["check", str(d), "--summary"]) == 0
    assert capsys.readouterr().out.startswith(f"{len(ids)}/{len(ids)} cases pass")
    for cid in ids:
        _set_column(d / f"{cid}.csv", "tau_mod_2pi", lambda x: 1000.0)
    assert main(["check", str(d)]) == 1
    out = capsys.readouterr().out
    assert out.splitlines()[-1].startswith(f"0/{len(ids)} cases pass")
    assert "first failing: tau_mod_2pi at line 2" in out


def test_check_reduces_out_of_range_phases(tmp_path, capsys):
    """Documented choice (docs/golden.md): a phase outside [0, 2 pi) is reduced, then compared
    circularly; the right phase plus 2 pi k passes, a wrong one by 2 pi k + 1e-6 fails."""
    cid = case_ids()[0]
    d = tmp_path / "out"
    _copy_expected(d, [cid])
    _set_column(d / f"{cid}.csv", "tau_mod_2pi", lambda x: x + 4 * TWO_PI)
    assert main(["check", str(d), "--cases", cid, "--summary"]) == 0
    shutil.rmtree(d)
    _copy_expected(d, [cid])
    _set_column(d / f"{cid}.csv", "tau_mod_2pi", lambda x: x - 4 * TWO_PI + 1e-6)
    assert main(["check", str(d), "--cases", cid, "--summary"]) == 1
    capsys.readouterr()


@pytest.mark.parametrize("value", [1e17, 1e300, 1.7976931348623157e308, -1e300])
def test_check_fails_a_huge_phase(tmp_path, capsys, value):
    """Issue 21: a tau_mod_2pi of 1e300, 1e17 or the largest double scored 17.0 digits (in float64
    the circular distance is 0 above ~1e16).  The exact reduction compares the phase it denotes."""
    ids = case_ids()
    d = tmp_path / "out"
    _copy_expected(d, ids)
    for cid in ids:
        _set_column(d / f"{cid}.csv", "tau_mod_2pi", lambda x: value)
    assert main(["check", str(d)]) == 1
    out = capsys.readouterr().out
    assert out.splitlines()[-1].startswith(f"0/{len(ids)} cases pass")
    # the phase digits (4th column of the table) are those of the phase the value denotes: ~0
    phase_digits = [float(line.split()[3]) for line in out.splitlines()[3 : 3 + len(ids)]]  # suite, header, rule
    assert len(phase_digits) == len(ids) and max(phase_digits) < 3, phase_digits


def test_circular_distance_is_exact_for_any_double():
    """The reduction agrees with 300-digit arithmetic (mpmath) to the last bit, from tiny to the
    largest doubles (the float64 formula is 0 above ~1e16 and wrong by ~k ulp(2 pi) below)."""
    mp = pytest.importorskip("mpmath")
    rng = np.random.default_rng(21)
    xs = list(10.0 ** rng.uniform(-300, 308, 200)) + [1e17, 1e300, 1.7976931348623157e308, TWO_PI, 5e-324, 1e16]
    gs = rng.uniform(0, TWO_PI, len(xs))
    got = circular_distance(np.array(xs), gs)
    # 400 digits for this test only: a global mp.dps = 400 leaked into every later mpmath reference
    # (tests/mpref.py works at 50), which made test_finder's near-grazing cases ~5x slower
    with mp.workdps(400):
        for x, g, c in zip(xs, gs, got):
            d = mp.mpf(x) - mp.mpf(g)
            ref = abs(d - 2 * mp.pi * mp.nint(d / (2 * mp.pi)))
            assert c == float(ref), (x, g)
    assert np.all((got >= 0) & (got <= math.pi))


def test_note_names_the_first_and_the_worst_failing_line(tmp_path, capsys):
    """docs/golden.md: the note names the first failing line; the worst one follows (each row against its
    own tolerance, the ``tau_tol`` column of expected.csv)."""
    cid = "0001-regular-fig2"
    d = tmp_path / "out"
    _copy_expected(d, [cid])
    f = d / f"{cid}.csv"
    tol = load_case(DEFAULT_SUITE / cid).row_tolerances("tau")[0]
    rows = list(csv.reader(f.read_text().splitlines()))
    j = rows[0].index("tau")
    e3, e8 = 3 * float(tol[2]), 500 * float(tol[7])
    rows[3][j] = repr(float(rows[3][j]) + e3)  # line 4: 3 x its tolerance
    rows[8][j] = repr(float(rows[8][j]) + e8)  # line 9: 500 x its tolerance
    rows[12][3] = "-1" if rows[12][3] == "0" else "0"  # line 13: wrong wall
    with open(f, "w", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerows(rows)
    assert main(["check", str(d), "--cases", cid]) == 1
    note = capsys.readouterr().out.splitlines()[3]  # after the suite line, the header and the rule
    assert f"first failing: tau at line 4 (|error| {e3:.3g}, 3 x tolerance)" in note
    assert f"worst: tau at line 9 (|error| {e8:.3g}, 500 x tolerance)" in note


def _one_field(tmp_path, cid, line, column, text):
    """A copy of the case's expected.csv with one field replaced (``line``: file line, header 1)."""
    d = tmp_path / "out"
    _copy_expected(d, [cid])
    f = d / f"{cid}.csv"
    rows = list(csv.reader(f.read_text().splitlines()))
    rows[line - 1][rows[0].index(column)] = text
    with open(f, "w", newline="", encoding="utf-8") as fh:
        csv.writer(fh, lineterminator="\n").writerows(rows)
    return d


#: Case 0007: line 4 is an impact on the lower wall, line 26 its stick row, line 27 its release row.
@pytest.mark.parametrize(
    "line,column,text,needle",
    [
        (4, "tau", "2_349.97", "not a number"),  # Python's underscores
        (4, "tau", "0x1.2cp+1", "not a number"),  # hexadecimal
        (4, "tau", "inf", "not a number"),
        (4, "tau", "1e999", "not finite"),
        (4, "tau", "2.3\u00a0", "not a number"),  # a non-ASCII blank
        (4, "sdot", "nan", "not a number"),  # no velocity on an impact row
        (4, "n", "2e0", "not an integer"),
        (4, "n", "2.5", "not an integer"),
        (4, "n", "\u0662", "not an integer"),  # ARABIC-INDIC DIGIT TWO: int() took it
        (4, "n", "1_0", "not an integer"),
        (4, "wall", "-1e0", "not an integer"),
        (26, "sdot", "0.0", "on a stick row"),  # a number where no velocity exists
        (27, "sdot", "1e-300", "on a release row"),
    ],
)
def test_strict_number_forms_are_malformed(tmp_path, capsys, line, column, text, needle):
    cid = "0007-chatter-sticking"
    d = _one_field(tmp_path, cid, line, column, text)
    assert main(["check", str(d), "--cases", cid]) == 1  # malformed: an error of its case
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"line {line}" in err[0] and column in err[0] and needle in err[0], err


@pytest.mark.parametrize(
    "line,column,text",
    [
        (4, "n", "2.0"),
        (4, "n", "+2"),
        (4, "n", " 2 "),
        (4, "wall", "-1.0"),
        (4, "wall", "-1."),
        (4, "tau", "2.3499716642375561e+00"),
        (4, "tau", "+2.3499716642375561"),
        (26, "sdot", "nan"),
        (26, "sdot", "NaN"),
        (27, "sdot", "-nan"),
        (27, "sdot", " "),
    ],
)
def test_documented_number_forms_are_accepted(tmp_path, capsys, line, column, text):
    cid = "0007-chatter-sticking"
    d = _one_field(tmp_path, cid, line, column, text)
    assert main(["check", str(d), "--cases", cid, "--summary"]) == 0, capsys.readouterr()


def test_utf8_byte_order_mark_is_accepted(tmp_path, capsys):
    cid = "0001-regular-fig2"
    d = tmp_path / "out"
    _copy_expected(d, [cid])
    f = d / f"{cid}.csv"
    f.write_bytes(b"\xef\xbb\xbf" + f.read_bytes())
    assert main(["check", str(d), "--cases", cid, "--summary"]) == 0, capsys.readouterr()


def test_digits_where_the_golden_value_is_zero():
    """docs/golden.md: where the golden value is 0 the digits are those of the absolute error."""
    from gear_rattle.validation.golden.scoring.cases import DIGITS_CAP, accuracy_digits

    assert accuracy_digits(np.array([1e-10]), np.array([0.0])) == pytest.approx(10.0)
    assert accuracy_digits(np.array([0.0]), np.array([0.0])) == DIGITS_CAP
    assert accuracy_digits(np.array([1e-10, 1e-12]), np.array([0.0, 1e-3])) == pytest.approx(9.0)
