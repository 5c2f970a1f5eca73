"""Bifurcation diagrams (Figs. 4a, 8a), time series (Figs. 5-7), CLI."""

import numpy as np
import pytest

from gear_rattle.core.params import Params
from gear_rattle.validation.dynamics.bifurcation import bifurcation_diagram
from gear_rattle.validation.cli import main
from gear_rattle.validation.dynamics.timeseries import time_series


def test_fig2_parameters_give_a_single_point_set():
    """Paper Fig. 2 (alpha = 0.5, r = 0.9): a regular periodic motion with 3 impacts per driving
    period (Fig. 2b) -> 3 points in the bifurcation diagram near r = 0.9, the same from a fixed
    initial condition and along a sweep.  After 2000 impacts the orbit has converged to rounding: the
    3 values are distinct at any tolerance from 1e-14 to 1e-7 (1e-12 used), and the two modes agree
    to 1.1e-16 (measured; bound 4e-15, ~36 ulp of |sdot| < 1)."""
    base = Params(0.5, 0.1, 0.1, 0.9)
    d = bifurcation_diagram(base, "r", 0.89, 0.9, 3, transient=2000, keep=60, mode="fixed")
    s = bifurcation_diagram(base, "r", 0.89, 0.9, 3, transient=2000, keep=60, mode="sweep")
    nd = d.n_distinct(1e-12)
    assert np.all(nd == 3)
    assert np.array_equal(nd, s.n_distinct(1e-12))
    assert np.all(np.abs(np.sort(d.sdot[-1])[[0, -1]] - np.sort(s.sdot[-1])[[0, -1]]) <= 4e-15)


def test_fig8a_four_impact_orbit_after_crisis_and_chaos_before():
    """Paper Fig. 8a (r = 0.9): a chaotic attractor at alpha = 1.235 < alpha1 = 1.24370 (all 100 kept
    points distinct to 1e-6; measured: distinct to 1e-13) and the stable period-1 orbit with four
    impacts at alpha = 1.26 > alpha1 (its 4 points coincide to rounding after 20000 impacts: 4 distinct
    values at tolerances 1e-13 ... 1e-6; 1e-12 used)."""
    base = Params(1.25, 0.1, 0.1, 0.9)
    d = bifurcation_diagram(base, "alpha", 1.235, 1.26, 2, transient=20000, keep=100)
    assert d.n_distinct(1e-6)[0] == 100  # chaotic attractor below alpha1 (Fig. 8a)
    assert d.n_distinct(1e-12)[1] == 4  # 4-impact period-1 orbit above alpha1


def test_stroboscopic_series_of_a_period1_orbit_is_constant():
    """Fig. 4a / Figs. 5-7(b): r = 0.8 is below r2, on the 6-impact period-1 orbit; sampled every 2 pi
    (the paper's stroboscopic map) it is a fixed point.  The sampling times k 2 pi ~ 3.2e3 carry the
    rounding of the elapsed time (ulp 4.5e-13), which moves sdot by |s''| < 3.4 times that: ~1.5e-12;
    measured spread 5.2e-13, bound 5e-12.  The 6 impact velocities spread over 3.36 (bound 3)."""
    ts = time_series(Params(3.0, 0.1, 0.1, 0.8), n_impacts=120, transient=3000)
    assert ts.k.size >= 19  # 120 impacts span 20 driving periods (measured 20 samples)
    assert np.ptp(ts.sdot_strobe) < 5e-12
    assert np.ptp(ts.sdot_n) > 3.0  # but the 6 impact velocities differ


@pytest.mark.parametrize(
    "argv",
    [
        ["bifurcation", "--r", "1.5"],
        ["bifurcation", "--mode", "fixed", "--lo", "0.9", "--hi", "0.8"],
        ["lyapunov", "--alpha", "-1"],
        ["orbit", "find", "--impacts", "0"],
        ["timeseries", "--beta", "0"],
    ],
)
def test_cli_bad_input_exit_2(argv, capsys):
    with pytest.raises(SystemExit) as e:
        rc = main(argv)
        raise SystemExit(rc)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err


def test_bad_inputs():
    base = Params(3.0, 0.1, 0.1, 0.9)
    with pytest.raises(ValueError, match="mode"):
        bifurcation_diagram(base, "r", 0.8, 0.9, 3, mode="random")
    with pytest.raises(ValueError, match="gamma"):
        bifurcation_diagram(base, "gamma", 0.8, 0.9, 3)
    with pytest.raises(ValueError, match="n_values"):
        bifurcation_diagram(base, "r", 0.8, 0.9, 0)
    with pytest.raises(ValueError, match="n_impacts"):
        time_series(base, n_impacts=1)
