"""Bifurcation diagrams (Figs. 4a, 8a), time series (Figs. 5-7), CLI."""

import numpy as np
import pytest

from gear_rattle.mapimpl.params import Params
from gear_rattle.validation.dynamics.bifurcation import bifurcation_diagram
from gear_rattle.validation.cli import main
from gear_rattle.validation.dynamics.timeseries import time_series


def test_fig2_parameters_give_a_single_point_set():
    # Fig. 2 (alpha = 0.5, r = 0.9): a regular periodic motion -> one finite set of points, the same
    # from a fixed initial condition and along a sweep
    base = Params(0.5, 0.1, 0.1, 0.9)
    d = bifurcation_diagram(base, "r", 0.89, 0.9, 3, transient=2000, keep=60, mode="fixed")
    s = bifurcation_diagram(base, "r", 0.89, 0.9, 3, transient=2000, keep=60, mode="sweep")
    nd = d.n_distinct(1e-7)
    assert np.all(nd <= 4) and np.all(nd >= 1)
    assert np.array_equal(nd, s.n_distinct(1e-7))
    assert np.allclose(np.sort(d.sdot[-1])[[0, -1]], np.sort(s.sdot[-1])[[0, -1]], atol=1e-7)


def test_fig8a_four_impact_orbit_after_crisis_and_chaos_before():
    base = Params(1.25, 0.1, 0.1, 0.9)
    d = bifurcation_diagram(base, "alpha", 1.235, 1.26, 2, transient=20000, keep=100)
    nd = d.n_distinct(1e-6)
    assert nd[0] > 50  # chaotic attractor below alpha1 (Fig. 8a)
    assert nd[1] == 4  # 4-impact period-1 orbit above alpha1


def test_stroboscopic_series_of_a_period1_orbit_is_constant():
    # r = 0.8 is below r2: the 6-impact period-1 orbit (Fig. 4a); sampled every 2 pi it is a fixed point
    ts = time_series(Params(3.0, 0.1, 0.1, 0.8), n_impacts=120, transient=3000)
    assert ts.k.size >= 18
    assert np.ptp(ts.sdot_strobe) < 1e-8
    assert np.ptp(ts.sdot_n) > 1.0  # but the 6 impact velocities differ


@pytest.mark.parametrize("argv", [
    ["bifurcation", "--r", "1.5"],
    ["bifurcation", "--mode", "fixed", "--lo", "0.9", "--hi", "0.8"],
    ["lyapunov", "--alpha", "-1"],
    ["orbit", "find", "--impacts", "0"],
    ["timeseries", "--beta", "0"],
])
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
