"""Scipy reference track (Eq. 3 integrated with solve_ivp/DOP853): the event traps, sticking, dense
output invariants, the flow x saltation Jacobian, input validation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from scipy.integrate import solve_ivp

from gear_rattle.mapimpl.finder import GRAZE, HIT
from gear_rattle.mapimpl.orbit import map_orbit
from gear_rattle.mapimpl.params import Params
from gear_rattle.mapimpl.sticking import release_delay
from gear_rattle.reference import scipy_track as S
from refhelpers import N_ORBIT, map_first_impact, map_one, params_st, state_st, v0_for_apex

CI = settings(deadline=None, max_examples=12, derandomize=True)
LONG = settings(deadline=None, max_examples=2000)


def test_first_impact_matches_map_paper_parameters():
    p = Params(3.0, 0.1, 0.1, 0.9)
    seq = S.orbit(p, 0.0, 0.5, 3)
    assert seq.track == "scipy" and seq.status == "active"
    m, _ = map_one(p, 0.0, 0.5)
    assert seq.wall[1] == int(m.wall)
    assert abs(seq.tau[1] - float(m.tau)) < 1e-10
    assert abs(seq.sdot[1] - float(m.sdot)) < 1e-10


# ---------------------------------------------------------------- traps
def test_restart_on_wall_does_not_refire_and_returns_to_same_wall():
    # gamma presses into the upper wall: a slow bounce off s = 0 comes back to s = 0
    p = Params(0.5, 0.1, 0.9, 0.5)
    for v0 in (-0.1, -1e-3, -1e-6):
        fl = S.flight(0.3, 0.0, v0, p)
        st, t, wall, v = map_first_impact(0.3, 0.0, v0, p)
        assert fl.status == "hit" and fl.wall == 0 == wall
        assert fl.t > 0.5 * 2 * abs(v0) / 1.5  # not the start point: about 2|v0|/f later
        assert fl.segments == 2  # one reversal, then the start wall
        assert abs(fl.t - t) <= 1e-12 * max(1.0, t) + 1e-15
        assert abs(fl.v - v) <= 1e-11 * max(1.0, abs(v))


def test_release_from_wall_with_zero_velocity():
    # start exactly at the release point on the upper wall: sdot = 0 and s'' = 0 there
    p = Params(1.0, 0.1, 0.3, 0.5)
    th = float(release_delay(0.0, 0, p.alpha, p.beta, p.gamma))
    fl = S.flight(th, 0.0, 0.0, p, sigma=-1)
    st, t, wall, v = map_first_impact(th, 0.0, 0.0, p)
    assert fl.status == "hit" and st == HIT and fl.wall == wall
    assert fl.t > 0.1
    assert abs(fl.t - t) < 1e-10 and abs(fl.v - v) < 1e-10


@pytest.mark.parametrize("depth", [1e-4, 1e-6, 1e-8])
def test_double_crossing_inside_one_step_is_caught(depth):
    """scipy issue 9228: s pokes beyond s = 0 and comes back inside one solver step."""
    p = Params(0.0, 0.1, -0.5, 0.9)
    v0 = v0_for_apex(depth)

    def rhs(t, y):
        return [y[1], p.gamma - p.beta * y[1]]

    def top(t, y):
        return y[0]
    top.terminal, top.direction = True, 1.0
    plain = solve_ivp(rhs, (0.0, 50.0), [-1.0, v0], method="DOP853", rtol=1e-12, atol=1e-13, events=[top])
    assert len(plain.t_events[0]) == 0  # the plain event check misses the excursion (the trap is real)
    fl = S.flight(0.0, -1.0, v0, p)
    st, t, wall, v = map_first_impact(0.0, -1.0, v0, p)
    assert st == HIT and fl.status == "hit" and fl.wall == wall == 0
    vex = math.sqrt(2 * 0.5 * depth)  # impact speed of a parabolic apex
    assert abs(fl.v - v) <= 1e-12 / vex and abs(fl.v / vex - 1) < 0.05
    assert abs(fl.t - t) <= 1e-12 / vex**2 + 1e-12  # grazing: dt ~ ds / v, ds ~ v * dv / a


@pytest.mark.parametrize("depth", [-1e-8, -1e-5])
def test_near_miss_grazing_stays_inside(depth):
    p = Params(0.0, 0.1, -0.5, 0.9)
    v0 = v0_for_apex(depth)
    fl = S.flight(0.0, -1.0, v0, p)
    st, t, wall, v = map_first_impact(0.0, -1.0, v0, p)
    assert st == HIT and fl.status == "hit" and fl.wall == wall == -1  # turned back, fell to s = -1
    assert fl.segments == 2
    assert abs(fl.t - t) < 1e-10 and abs(fl.v - v) < 1e-10


def test_exact_tangency_is_hit_or_miss_consistently():
    # apex exactly at the wall to within rounding: the map calls it a graze or a miss; the reference
    # must report either a contact at the apex time or the fall to s = -1, never something else
    p = Params(0.0, 0.1, -0.5, 0.9)
    v0 = v0_for_apex(0.0)
    fl = S.flight(0.0, -1.0, v0, p)
    st, t, wall, v = map_first_impact(0.0, -1.0, v0, p)
    assert st in (HIT, GRAZE) and fl.status == "hit"
    if fl.wall == 0:
        assert abs(fl.t - t) < 1e-4 and abs(fl.v) < 1e-5
    else:
        t_apex = math.log((v0 + 5.0) / 5.0) / 0.1
        assert fl.t > t_apex


# ---------------------------------------------------------------- sticking
def test_chatter_sticks_forever_at_upper_wall_like_the_map():
    p = Params(0.5, 0.1, 0.9, 0.5)  # |gamma| > alpha sqrt(1 + beta^2): stuck forever once stuck
    m = map_orbit(p, 0.0, 0.5, N_ORBIT)
    s = S.orbit(p, 0.0, 0.5, N_ORBIT)
    assert s.status == m.status == "stuck_forever"
    assert list(s.kind) == list(m.kind) and s.kind[-1] == "stick"
    assert np.all(s.wall[-5:] == 0)
    assert np.max(np.abs(s.tau - m.tau)) < 1e-9


def test_stick_and_release_like_the_map():
    p = Params(1.0, 0.5, 0.2, 0.4)
    m = map_orbit(p, 0.0, 0.5, N_ORBIT)
    s = S.orbit(p, 0.0, 0.5, N_ORBIT)
    assert list(s.kind) == list(m.kind) and s.n_sticking == m.n_sticking >= 2
    assert np.max(np.abs(s.tau - m.tau)) < 1e-9
    i = s.impacts
    assert np.max(np.abs(s.sdot[i] - m.sdot[i])) < 1e-9


# ---------------------------------------------------------------- dense output invariants
def _check_invariants(p: Params, tau0: float, sdot0: float, n: int) -> None:
    seq, d = S.dense_orbit(p, tau0, sdot0, n, points_per_unit=20.0)
    if len(d.tau) == 0:
        return
    # -1 <= s <= 0 everywhere (to the integrator's accuracy, 1e-12)
    assert np.all(d.s <= 1e-12) and np.all(d.s >= -1.0 - 1e-12)
    # time non-decreasing overall, strictly increasing inside each flight
    assert np.all(np.diff(d.tau) >= 0.0)
    for g in np.unique(d.segment[d.segment >= 0]):
        tt = d.tau[d.segment == g]
        ok = np.diff(tt) > 0.0
        # segment joints repeat one point
        assert np.sum(~ok) <= 2 * len(tt) // 2 + 1 and np.all(np.diff(tt)[ok] > 0)
    tau, _, sd, wall = seq.impact_arrays()
    assert np.all(np.diff(seq.tau) >= 0.0) and np.all(np.diff(tau) > 0.0)
    # walls consistent with the velocity sign just before impact
    assert np.all(sd[wall == 0] >= 0.0) and np.all(sd[wall == -1] <= 0.0)
    # each flight starts on the wall of the impact with |sdot after| = r |sdot before| (Eq. 11)
    starts = {}
    for k, (t, s, v, g) in enumerate(zip(d.tau, d.s, d.sdot, d.segment)):
        if g >= 0 and g not in starts:
            starts[g] = (t, s, v)
    imp = np.flatnonzero(seq.impacts)
    for j, g in enumerate(sorted(starts)):
        t, s, v = starts[g]
        k = imp[j]
        if k + 1 < len(seq.kind) and seq.kind[k + 1] == "stick":
            assert v == 0.0 and s == seq.wall[k]
            continue
        assert s == float(seq.wall[k]) and abs(t - seq.tau[k]) <= 1e-12 * max(1.0, abs(t))
        assert abs(abs(v) - p.r * abs(seq.sdot[k])) <= 1e-15 * max(1.0, abs(v))


@CI
@given(params_st, state_st)
@example(Params(0.5, 0.1, 0.9, 0.5), (0.0, 0.5))
@example(Params(1.0, 0.5, 0.2, 0.4), (0.0, 0.5))
def test_dense_invariants(p, state):
    _check_invariants(p, state[0], state[1], 8)


@pytest.mark.slow
@LONG
@given(params_st, state_st)
def test_dense_invariants_long(p, state):
    _check_invariants(p, state[0], state[1], 20)


# ---------------------------------------------------------------- validation
@pytest.mark.parametrize("kw,name", [
    (dict(rtol=0.0), "rtol"), (dict(atol=-1.0), "atol"), (dict(max_step=0.0), "max_step"),
    (dict(t_max=float("inf")), "t_max"),
])
def test_bad_options_raise_naming_them(kw, name):
    with pytest.raises(ValueError, match=name):
        S.orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 2, **kw)


@pytest.mark.parametrize("args,name", [
    ((0.0, 0.0, 2), "sdot0"), ((float("nan"), 0.5, 2), "tau0"), ((0.0, 0.5, -1), "n_impacts"),
])
def test_bad_start_raises_naming_it(args, name):
    with pytest.raises(ValueError, match=name):
        S.orbit(Params(3.0, 0.1, 0.1, 0.9), *args)


def test_bad_s0_raises():
    with pytest.raises(ValueError, match="s0"):
        S.orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 2, s0=0.5)


def test_free_flight_start_matches_map():
    p = Params(3.0, 0.1, 0.1, 0.9)
    m = map_orbit(p, 1.0, 0.2, N_ORBIT, s0=-0.4)
    s = S.orbit(p, 1.0, 0.2, N_ORBIT, s0=-0.4)
    assert list(s.wall[:8]) == list(m.wall[:8])
    assert np.max(np.abs(s.tau[:8] - m.tau[:8])) < 1e-10  # chaotic beyond (see test_crossval)


def test_no_impact_status_like_the_map():
    # no forcing, weak damping loss: the tooth coasts to rest inside the gap
    p = Params(0.0, 1.0, 0.0, 0.5)
    s = S.orbit(p, 0.0, 0.5, N_ORBIT, t_max=200.0)
    m = map_orbit(p, 0.0, 0.5, N_ORBIT)
    assert s.status == m.status == "no_impact"
    assert len(s.kind) == len(m.kind) == 1
