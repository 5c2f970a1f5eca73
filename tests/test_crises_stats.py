"""Statistics of the crisis analyses (validation/dynamics/crises/stats.py) on synthetic data with known
answers: censored exponential lifetimes, exact Poisson intervals, the crisis-law fit T = C |mu - mu_c|^-g
(the law behind r1 of Figs. 4/7 and alpha1 of Fig. 8), and brackets by direct observation."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gear_rattle.validation.dynamics.crises.stats import (
    Bracket,
    bracket,
    locate,
    censored_lifetimes,
    fit_crisis,
    lifetime_lower_bound,
    mean_time,
    next_probes,
    range_systematic,
    WHY_BRACKET_NARROWER,
    WHY_FIT_NARROWER,
    WHY_FIT_OUTSIDE,
    WHY_NO_BRACKET,
)


def test_censored_lifetimes_recover_the_mean_with_heavy_censoring_and_left_truncation():
    rng = np.random.default_rng(7)
    T_true, cap, n0 = 1000.0, 1500, 200
    life = rng.exponential(T_true, 4000)
    esc = np.where(life < cap, np.floor(life).astype(int), -1)  # escaped within the run, else censored
    n_run = np.full(life.size, cap)
    rate, dropped = censored_lifetimes(esc, n_run, n0=n0)
    assert dropped == int(np.sum((esc >= 0) & (esc <= n0)))
    # the naive mean of the escaped orbits is biased low by the censoring; the MLE is not
    assert np.mean(life[life < cap]) < 0.75 * T_true
    assert abs(rate.T - T_true) < 4 * rate.rel_err * T_true
    assert rate.lo < T_true < rate.hi


def test_exact_interval_covers_at_its_level():
    rng = np.random.default_rng(11)
    T_true, E = 500.0, 5000.0  # ten events expected
    hits = 0
    trials = 400
    for _ in range(trials):
        k = rng.poisson(E / T_true)
        m = mean_time(np.array([k]), np.array([E]))
        hits += m.lo <= T_true <= m.hi
    # exact (Garwood) intervals are conservative: coverage >= 95 % up to the binomial noise of 400 trials
    assert hits / trials >= 0.95 - 3 * math.sqrt(0.95 * 0.05 / trials)


def test_no_event_gives_the_one_sided_bound():
    m = mean_time(np.zeros(4, int), np.full(4, 1e5))
    assert math.isinf(m.T) and math.isinf(m.hi)
    assert m.bound == pytest.approx(4e5 / -math.log(0.05))
    assert lifetime_lower_bound(4e5) == pytest.approx(4e5 / -math.log(0.05))


def _synthetic(mu_c, g, C, x, side, rng, exposure_factor=2000.0):
    mu = mu_c + x if side == "above" else mu_c - x
    T = C * x ** (-g)
    E = exposure_factor * T
    k = rng.poisson(E / T)
    return mu, k, E


@pytest.mark.parametrize("side", ["above", "below"])
def test_fit_crisis_recovers_the_crisis_point(side):
    rng = np.random.default_rng(3 if side == "above" else 4)
    mu_c, g, C = 1.2437, 1.0, 0.5
    x = np.geomspace(2e-5, 2e-3, 7)
    mu, k, E = _synthetic(mu_c, g, C, x, side, rng)
    fixed = fit_crisis(mu, k, E, side, g=g)
    assert abs(fixed.mu_c - mu_c) < 4 * fixed.err
    assert fixed.err < 2e-6  # 2000 events per point pin mu_c well below the nearest offset
    free = fit_crisis(mu, k, E, side)
    assert abs(free.g - g) < 4 * free.g_err
    assert abs(free.mu_c - mu_c) < 4 * max(free.err_lo, free.err_hi)
    syst, subs = range_systematic(mu, k, E, side, g=g)
    assert len(subs) == 3 and syst >= 0


def test_fit_crisis_with_the_wrong_side_cannot_fit_the_data():
    rng = np.random.default_rng(5)
    mu, k, E = _synthetic(0.74144, 0.87, 1e-3, np.geomspace(1e-6, 1e-4, 6), "below", rng)
    right = fit_crisis(mu, k, E, "below", g=0.87)
    wrong = fit_crisis(mu, k, E, "above", g=0.87)
    assert wrong.deviance > 100 * max(right.deviance, 1.0)


def test_bracket_and_probes():
    mu = np.array([1.2430, 1.2433, 1.2436, 1.2440])
    k = np.array([0, 0, 3, 40])
    E = np.array([2e6, 5e5, 1e6, 1e6])
    b = bracket(mu, k, E, "above", min_exposure=1e6)
    assert b.seen == 1.2436
    assert b.clear == 1.2430  # 1.2433 has no event but was not observed long enough
    assert b.clear_bound == pytest.approx(2e6 / -math.log(0.05))
    # bracket wider than 2 x target: bisect it
    assert next_probes(mu, k, E, "above", 1.2434, 1e-4, 1e-5, 1e6) == [pytest.approx(1.2433)]
    # no clear value yet: probe beyond the fit
    b2 = bracket(mu[2:], k[2:], E[2:], "above", min_exposure=1e6)
    assert math.isnan(b2.clear)
    assert next_probes(mu[2:], k[2:], E[2:], "above", 1.2435, 1e-4, 1e-5, 1e6) == [pytest.approx(1.2434)]
    with pytest.raises(ValueError, match="side"):
        bracket(mu, k, E, "left")


def test_locate_reports_the_fit_inside_the_bracket_and_the_bracket_when_the_fit_contradicts_it():
    """r1 at paper scale: the GOY fit (from the far points) lay above the r at which no hop was seen in
    5e7 impacts; then the direct observations decide."""
    b = Bracket("below", seen=0.7414329, clear=0.7414365, clear_exposure=5.1e7, clear_bound=1.7e7, level=0.95)
    inside = locate(0.7414340, 1e-6, b)
    assert inside.method == "fit" and inside.value == 0.7414340 and inside.outside == 0.0
    assert inside.why == WHY_FIT_NARROWER
    out = locate(0.7414435, 2.4e-6, b, margin=1.7e-9)
    assert out.method == "bracket" and out.why == WHY_FIT_OUTSIDE
    assert out.value == pytest.approx(0.5 * (0.7414329 + 0.7414365 + 1.7e-9))
    assert out.err == pytest.approx(0.5 * (0.7414365 + 1.7e-9 - 0.7414329))
    assert out.outside == pytest.approx((0.7414435 - 0.7414365 - 1.7e-9) / 2.4e-6)
    above = Bracket("above", seen=1.2433, clear=1.2431, clear_exposure=5e7, clear_bound=1.7e7, level=0.95)
    assert locate(1.2436, 1e-5, above).method == "bracket"
    assert locate(1.24325, 1e-5, above).method == "fit"
    no = locate(1.0, 1.0, Bracket("above", 1.2, math.nan, 0.0, 0.0, 0.95))
    assert no.method == "fit" and no.why == WHY_NO_BRACKET


def test_locate_states_the_bracket_when_it_is_narrower_than_a_consistent_fit():
    """The published r1 run (docs/report, paper profile): GOY fit 0.7414394 +- 7.2e-6 (dominated by the
    fit-range systematic), 1.0e-6 above the bracket [0.7414354, 0.7414384 + 1.7e-9] but within its
    error; the bracket's half-width 1.5e-6 is the narrower statement, so it is reported."""
    b = Bracket("below", seen=0.741435351, clear=0.7414383709, clear_exposure=5.07e7, clear_bound=1.69e7, level=0.95)
    loc = locate(0.7414393709, 7.2e-6, b, margin=1.7e-9)
    assert loc.method == "bracket" and loc.why == WHY_BRACKET_NARROWER
    assert 0 < loc.outside < 1
    assert loc.value == pytest.approx(0.5 * (0.741435351 + 0.7414383709 + 1.7e-9), abs=1e-13)
    assert loc.err == pytest.approx(0.5 * (0.7414383709 + 1.7e-9 - 0.741435351), rel=1e-9)
    assert loc.err < 2e-6
    # the same bracket with a fit narrower than it and inside it: the fit
    tight = locate(0.7414370, 1e-6, b, margin=1.7e-9)
    assert tight.method == "fit" and tight.value == 0.7414370 and tight.why == WHY_FIT_NARROWER


def test_crisis_results_are_typed_and_write_as_strict_json(tmp_path):
    """The crisis analyses return typed results (issue 24 item 1); their ``as_dict`` is the data written to
    crises.json -- nested fits, brackets and the located point by their own ``as_dict``, periodic orbits
    and branches left out, an infinite mean time (no event) written as null by the strict writer."""
    import json

    from gear_rattle.validation.dynamics.crises import R1Result
    from gear_rattle.validation.dynamics.crises.stats import mean_time
    from gear_rattle.validation.io.crises import write_crises

    r = np.array([0.7410, 0.7412, 0.7413, 0.7414])
    k = np.array([400.0, 120.0, 40.0, 0.0])
    E = np.full(4, 4e6)
    goy = fit_crisis(r[:3], k[:3], E[:3], "below", g=1.0)
    brk = bracket(r, k, E, "below")
    loc = locate(goy.mu_c, goy.err, brk)
    none = mean_time([0, 0], [1e6, 1e6])
    res = R1Result(
        value=loc.value,
        err=loc.err,
        method=loc.method,
        located=loc,
        goy=goy.mu_c,
        goy_err=goy.err,
        stat=goy.err,
        syst=0.0,
        free=goy.mu_c,
        free_err=goy.err,
        g_free=1.0,
        g_free_err=0.0,
        fit_goy=goy,
        fit_free=goy,
        subranges_goy=[("all", goy.mu_c)],
        subranges_free=[],
        goy_exponent=1.0,
        saddle=object(),
        bracket=brk,
        bracket_margin=math.nan,
        lower_bound=brk.seen,
        upper_bound=brk.clear,
        consistent=True,
        clear_lyapunov=None,
        near={"r": brk.seen, **none.as_dict()},
        hops=[],
        paper_fig7={},
        ics={},
        cost={},
        profile="quick",
    )
    d = res.as_dict()
    assert "saddle" not in d and d["bracket"] == brk.as_dict() and d["located"] == loc.as_dict()
    # one crisis result type (issue 39): the fields r1 and alpha1 share have one name each, and the file keeps
    # its layout: the located values named after the crisis, in the order of before
    assert list(d)[:8] == ["r1", "r1_err", "method", "located", "r1_goy", "r1_goy_err", "r1_stat", "r1_syst"]
    assert list(d)[-4:] == ["paper_fig7", "ics", "cost", "profile"] and d["r1"] == res.value == loc.value
    with pytest.warns(DeprecationWarning, match=r"R1Result.r1_goy is deprecated: use .goy"):
        assert res.r1_goy == res.goy
    # the located values r1 and alpha1 build alike (one function): the shared fields, in their order
    from gear_rattle.validation.dynamics.crises.results import CrisisResult, located_fields

    shared = located_fields(loc, goy, goy, 0.0, 0.0)
    assert list(shared) == [f.name for f in dataclasses.fields(CrisisResult)][: len(shared)]
    assert shared["value"] == res.value and shared["goy_err"] == res.goy_err and shared["fit_free"] is goy
    assert d["fit_goy"]["mu_c"] == goy.mu_c and d["near"]["T"] == math.inf
    write_crises(tmp_path, "quick", types_ns(as_dict=lambda: {}), res, types_ns(as_dict=lambda: {"x": math.nan}))
    back = json.loads((tmp_path / "crises.json").read_text(), parse_constant=lambda c: pytest.fail(c))
    assert back["r1"]["near"]["T"] is None and back["r1"]["bracket"]["seen"] == brk.seen
    assert back["alpha1"] == {"x": None} and back["profile"] == "quick"


def types_ns(**kw):
    import types

    return types.SimpleNamespace(**kw)


def test_run_sizes_replace_the_profile_and_name_a_wrong_key():
    """``sizes`` (locate_r2/r1/alpha1, their doctests) replaces entries of the named profile; a key the
    analysis does not have is refused by name, and the result's profile says that sizes were replaced."""
    from gear_rattle.validation.profiles import PROFILES, get_profile, label

    pr = get_profile("quick", "r2", {"orbits": 2})
    assert pr["orbits"] == 2 and pr["cap"] == PROFILES["quick"]["r2"]["cap"]
    assert PROFILES["quick"]["r2"]["orbits"] == 8  # the table itself is unchanged
    assert get_profile("quick", "alpha1", {"probe_ics": 16})["probe_ics"] == 16
    with pytest.raises(ValueError, match=r"sizes=\['orbit'\] is out of range"):
        get_profile("quick", "r2", {"orbit": 2})
    with pytest.raises(ValueError, match="probe_ics"):
        get_profile("quick", "r1", {"probe_ics": 16})
    with pytest.raises(ValueError, match="profile='fast'"):
        get_profile("fast", "r2")
    assert label("quick", None) == "quick" and label("paper", {"cap": 10}) == "paper+sizes"
