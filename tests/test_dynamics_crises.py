"""Paper-scale location of r2, r1, alpha1 (opt-in: pytest -m slow)."""

import numpy as np
import pytest

from gear_rattle.validation.dynamics.crises import locate_alpha1, locate_r1, locate_r2


@pytest.mark.slow
def test_r2_fold_and_type1_intermittency_slope():
    # Figs. 4-6: the paper puts r = 0.82144 just above r2
    res = locate_r2("paper")
    assert abs(res["r2"] - 0.82144) < 1e-5
    assert abs(res["slope"] + 0.5) < 0.1  # type-I intermittency, theory -1/2


@pytest.mark.slow
def test_r1_interior_crisis_above_fig7_value():
    res = locate_r1("paper")
    # Fig. 7: r = 0.74001 is just below r1
    assert res["r1"] > 0.74001
    assert res["r1"] > res["lower_bound"] - 3 * res["r1_err"]
    assert res["r1_err"] < 1e-4


@pytest.mark.slow
def test_alpha1_boundary_crisis_near_paper_value():
    res = locate_alpha1("paper")
    # Fig. 8: alpha1 ~ 1.24370
    assert abs(res["alpha1"] - 1.24370) < 5e-3
    assert res["node"].stable and res["node"].impacts == 4
