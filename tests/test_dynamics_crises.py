"""Paper-scale location of r2, r1, alpha1 (Section 3, Figs. 4-8; opt-in: pytest -m slow).

Each test checks the result against its own error bar and bracket and states where the paper's value
lies; the tolerances are the computed errors, not widened ones."""

import numpy as np
import pytest

from gear_rattle.validation.dynamics.crises import (
    PAPER_ALPHA1,
    PAPER_R1_FIG7,
    PAPER_R2_FIG5,
    locate_alpha1,
    locate_r1,
    locate_r2,
)


@pytest.mark.slow
def test_r2_fold_and_type1_intermittency_slope():
    """Figs. 4-6: the fold r2 of the 6-impact orbit; the paper's r = 0.82144 of Fig. 5 (">~ r2") is r2
    rounded to 5 decimals; the laminar-length exponent is compared with type-I theory (-1/2) within 4
    of its own errors (the report prints the local slopes)."""
    res = locate_r2("paper")
    assert abs(res.r2 - PAPER_R2_FIG5) < 5e-6
    assert res.fold.residual < 1e-10
    assert abs(res.slope + 0.5) < 4 * res.slope_err + 0.05


@pytest.mark.slow
def test_r1_interior_crisis_bracketed_by_direct_observation():
    """Figs. 4 and 7: r1 from band hops, bracketed (hops seen at r_a < r1, none in >= 5e7 impacts at r_b,
    where the band orbits are chaotic, lambda1 > 0: not a periodic window) to the +-2e-6 issue 10 asks;
    the paper's r = 0.74001 of Fig. 7 ("<~ r1") is below it."""
    res = locate_r1("paper")
    b = res.bracket
    assert np.isfinite(b.clear) and b.clear_exposure >= 5e7
    assert res.clear_lyapunov["chaotic"] and res.clear_lyapunov["r"] == b.clear
    assert b.seen - res.err <= res.value <= b.clear + res.err
    assert res.err <= 2e-6
    assert res.value > PAPER_R1_FIG7


@pytest.mark.slow
def test_alpha1_boundary_crisis_from_escape_times():
    """Fig. 8: alpha1 from escape times of the pre-crisis chaotic set (GOY fit) within its bracket; the
    node is the stable 4-impact period-1 orbit; where the paper's 1.24370 lies is reported, not assumed."""
    res = locate_alpha1("paper")
    # issue 10: >= 200 orbits per value, mean lifetimes measured down to >= 1e6 impacts, +-1e-5
    assert res.ics["n"] >= 200 and res.T_max_measured >= 1e6
    assert res.err <= 1e-5
    b = res.bracket
    assert b.clear - res.bracket_margin - res.err <= res.value <= b.seen + res.err
    assert res.node.stable and res.node.impacts == 4
    # where the paper's value lies: if it is above our alpha1 (beyond the error), escapes must have been
    # observed there (a finite measured mean lifetime): the chaotic set is already transient at 1.24370
    assert res.paper["measured_at"] == PAPER_ALPHA1
    if PAPER_ALPHA1 > res.value + 3 * res.err:
        assert np.isfinite(res.paper["T"]) and res.paper["T"] > 0
