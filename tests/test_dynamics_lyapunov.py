"""Lyapunov exponents (Figs. 4b, 8b): QR method, sum rule, agreement with Floquet multipliers."""

import numpy as np
import pytest

from gear_rattle.mapimpl.params import Params
from gear_rattle.mapimpl.periodic import find_periodic
from gear_rattle.validation.dynamics.crises import attractor_point
from gear_rattle.validation.dynamics.lyapunov import lyapunov, raw_product_overflow


def test_sum_equals_closed_form_mean_log_det():
    res = lyapunov(Params(3.0, 0.1, 0.1, 0.9), "r", [0.9, 0.86, 0.8, 0.75], n=4000, transient=500)
    assert np.all(res.n_stuck == 0) and np.all(res.active)
    assert np.all(res.sum_error < 1e-10)
    # Fig. 4b: chaotic at r = 0.9 (Fig. 3), periodic (negative lambda1) at r = 0.8
    assert res.lam[0, 0] > 0.1
    assert res.lam[2, 0] < 0


def test_periodic_lambda1_matches_floquet_multiplier():
    p = Params(3.0, 0.1, 0.1, 0.8)
    th, sd = attractor_point(p, 3000)
    o = find_periodic(p, th, sd, 6)
    res = lyapunov(p, "r", [0.8], n=6000, transient=3000)
    expect = np.sort(np.log(np.abs(o.multipliers)))[::-1] / 6
    assert res.lam[0] == pytest.approx(expect, abs=2e-3)


def test_paper_raw_product_overflows():
    # the paper's eigenvalues of the raw product J_1...J_n are not computable for long runs in float64
    k = raw_product_overflow(Params(3.0, 0.1, 0.1, 0.9), n=6000)
    assert k is not None and 500 < k < 6000


@pytest.mark.parametrize("kw", [dict(n=0), dict(transient=-1), dict(sdot0=0.0)])
def test_bad_inputs(kw):
    with pytest.raises(ValueError):
        lyapunov(Params(3.0, 0.1, 0.1, 0.9), "r", [0.9], **kw)


def test_bad_parameter_value_names_parameter():
    with pytest.raises(ValueError, match="r="):
        lyapunov(Params(3.0, 0.1, 0.1, 0.9), "r", [1.2], n=10)
