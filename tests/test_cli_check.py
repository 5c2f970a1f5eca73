"""`gear-rattle check` (docs/golden.md): the circular comparison of `tau_mod_2pi` for any value.

The output of a perfect implementation is stood in for by the certified `expected.csv` itself (extra
trailing columns are ignored), so these tests run no track and no JAX."""

import csv
import math
import shutil

import numpy as np
import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.suite import DEFAULT_SUITE, case_ids, circular_distance

TWO_PI = 2 * math.pi


def test_circular_distance_any_real():
    """In [0, pi] for any finite inputs; exact for small differences; never negative (the old
    min(d, 2 pi - d) was -987 for 1000 vs 6.28 and so passed any tolerance)."""
    assert circular_distance(1000.0, 1.0) == pytest.approx(abs(1000.0 - 1.0 - 159 * TWO_PI), abs=1e-12)
    assert circular_distance(1.0 + 3 * TWO_PI, 1.0) == pytest.approx(0.0, abs=1e-14)
    assert circular_distance(-1e-3, TWO_PI - 2e-3) == pytest.approx(1e-3, abs=1e-15)
    assert circular_distance(TWO_PI, 0.0) == 0.0
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
    assert main(["check", str(d), "--quiet"]) == 0
    assert capsys.readouterr().out.startswith(f"{len(ids)}/{len(ids)} cases pass")
    for cid in ids:
        _set_column(d / f"{cid}.csv", "tau_mod_2pi", lambda x: 1000.0)
    assert main(["check", str(d)]) == 1
    out = capsys.readouterr().out
    assert out.splitlines()[-1].startswith(f"0/{len(ids)} cases pass")
    assert "tau_mod_2pi differs" in out


def test_check_reduces_out_of_range_phases(tmp_path, capsys):
    """Documented choice (docs/golden.md): a phase outside [0, 2 pi) is reduced, then compared
    circularly; the right phase plus 2 pi k passes, a wrong one by 2 pi k + 1e-6 fails."""
    cid = case_ids()[0]
    d = tmp_path / "out"
    _copy_expected(d, [cid])
    _set_column(d / f"{cid}.csv", "tau_mod_2pi", lambda x: x + 4 * TWO_PI)
    assert main(["check", str(d), "--cases", cid, "--quiet"]) == 0
    shutil.rmtree(d)
    _copy_expected(d, [cid])
    _set_column(d / f"{cid}.csv", "tau_mod_2pi", lambda x: x - 4 * TWO_PI + 1e-6)
    assert main(["check", str(d), "--cases", cid, "--quiet"]) == 1
    capsys.readouterr()
