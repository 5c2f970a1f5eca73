"""Diffrax reference track (Eq. 3, diffeqsolve + Event in a while_loop): traps, sticking, jit/vmap."""

from __future__ import annotations

import numpy as np
import pytest

import gear_rattle  # noqa: F401  (float64: importing the package switches JAX to it)
import jax

from gear_rattle.core.status import FlightOutcome
from gear_rattle.mapimpl.orbit import map_orbit
from gear_rattle.core.params import Params
from gear_rattle.reference import diffrax_track as D
from refhelpers import GRAZE_DS, N_ORBIT, SLOW_DEPARTURES, map_first_impact, v0_for_apex
from mpref import first_root

_flight = jax.jit(D.flight)


def _fl(theta, s0, v0, sigma, p):
    return jax.tree.map(np.asarray, _flight(theta, s0, v0, sigma, p.alpha, p.beta, p.gamma))


@pytest.mark.parametrize("depth", [1e-4, 1e-8, -1e-8])
def test_double_crossing_and_near_miss(depth):
    """diffrax issue 507: an excursion beyond s = 0 inside one step is still an impact of Eq. (3).
    Grazing model as in test_reference_scipy (GRAZE_DS = 4e-15): dt <= ds / v + a few ulp of t ~ 2-4,
    dv <= |a| ds / v; measured ds = dt v <= 8.6e-17 (grazes), 1.7e-15 (the near miss, v = 0.93)."""
    p = Params(0.0, 0.1, -0.5, 0.9)
    v0 = v0_for_apex(depth)
    fl = _fl(0.0, -1.0, v0, 1.0, p)
    st, t, wall, v = map_first_impact(0.0, -1.0, v0, p)
    assert (
        st == FlightOutcome.HIT
        and int(fl.status) == FlightOutcome.HIT
        and int(fl.wall) == wall == (0 if depth > 0 else -1)
    )
    vex = abs(v)
    assert abs(float(fl.t) - t) <= GRAZE_DS / vex + 1e-14 and abs(float(fl.v) - v) <= 0.5 * GRAZE_DS / vex


@pytest.mark.parametrize("v0", [-0.1, -1e-4])
def test_restart_on_wall_returns_to_same_wall(v0):
    """A slow bounce off s = 0 into a pressing force returns to s = 0 (Eq. 3) after ~2.5 |v0|; resolved
    relative to its size: measured 4.3e-16 t (time), 5.4e-16 |v| (velocity); bound 4e-15 relative."""
    p = Params(0.5, 0.1, 0.9, 0.5)
    fl = _fl(0.3, 0.0, v0, -1.0, p)
    st, t, wall, v = map_first_impact(0.3, 0.0, v0, p)
    assert int(fl.status) == FlightOutcome.HIT and int(fl.wall) == wall == 0 and int(fl.segments) == 2
    assert abs(float(fl.t) - t) <= 4e-15 * t and float(fl.t) > abs(v0)
    assert abs(float(fl.v) - v) <= 4e-15 * abs(v)


@pytest.mark.parametrize("case", range(len(SLOW_DEPARTURES)))
def test_slow_departure_returns_to_start_wall(case):
    """The slow departures that the scipy track gets wrong (refhelpers.SLOW_DEPARTURES): the
    flight of Eq. (3) returns to its start wall after 0.03-0.07, as the map and a 50-digit bisection of
    Eqs. (7)-(8) find; diffrax agrees with the map in the gap, ``|dt| |v|`` (the time of a contact of speed
    ``v`` is conditioned by ``1 / |v|``: an ulp of the position is 3.3e-13 in time at ``v = 6.8e-4``): measured
    0.0003 ... 0.44 ulp of a position (2^-52) with the tracks' tolerances (rtol 1e-13, the slow departure's
    bounded first interval); bound 2 ulps, the golden suite's gap error of a correct implementation
    (conditioning.GAP_ULPS)."""
    p, theta, s0, v0 = SLOW_DEPARTURES[case]
    fl = _fl(theta, s0, v0, 1.0 if v0 > 0 else -1.0, p)
    st, t, wall, v = map_first_impact(theta, s0, v0, p)
    ref = first_root(theta, s0, v0, p.alpha, p.beta, p.gamma, t_lo=1e-6, t_hi=0.2, n=400)
    assert st == FlightOutcome.HIT and wall == ref[1] == int(s0) and abs(t - float(ref[0])) < 1e-14
    assert int(fl.status) == FlightOutcome.HIT and int(fl.wall) == wall
    assert abs(float(fl.t) - t) * abs(v) <= 2 * 2.0**-52


def test_chatter_sticks_forever_like_the_map():
    """Chatter into sticking forever (|gamma| > alpha sqrt(1 + beta^2)) like the map: event times
    (tau < 1.4) within 1.1e-16 (measured); bound 2e-14."""
    p = Params(0.5, 0.1, 0.9, 0.5)
    m = map_orbit(p, 0.0, 0.5, N_ORBIT)
    d = D.orbit(p, 0.0, 0.5, N_ORBIT)
    assert d.track == "diffrax" and d.status == m.status == "stuck_forever"
    assert list(d.kind) == list(m.kind)
    assert np.max(np.abs(d.tau - m.tau)) < 2e-14


def test_batch_equals_single_orbits():
    """vmapped and single diffrax orbits (separately compiled, so not bitwise equal): impact times
    (tau < 12) within 1.4e-14 (measured); bound 1e-13."""
    p = Params(1.0, 0.5, 0.2, 0.4)
    tau0 = np.array([0.0, 1.0, 2.5])
    sd0 = np.array([0.5, -0.3, 1.2])
    tr = D.batch_orbit(p, tau0, sd0, 4)
    for i in range(3):
        one = D.iterate(jax.tree.map(lambda x: x[i], D.make_state(tau0, sd0)), p.arrays(), 4)
        np.testing.assert_array_equal(np.asarray(tr.states.wall[i]), np.asarray(one.states.wall))
        np.testing.assert_allclose(np.asarray(tr.states.tau[i]), np.asarray(one.states.tau), rtol=0, atol=1e-13)


@pytest.mark.parametrize(
    "kw,name", [(dict(rtol=0.0), "rtol"), (dict(dtmax=-1.0), "dtmax"), (dict(max_steps=0), "max_steps")]
)
def test_bad_options_raise(kw, name):
    with pytest.raises(ValueError, match=name):
        D.orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 2, **kw)


def test_bad_start_raises():
    with pytest.raises(ValueError, match="sdot0"):
        D.orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.0, 2)


@pytest.mark.parametrize("sdot0", [1e-10, 1e-7, 1e-6])
def test_a_slow_bounce_into_a_weak_force_is_found(sdot0):
    """Found by ``gear-rattle fuzz`` (stick-threshold scenario, seed 44, shrunk): alpha = 0.5, beta = 0.003,
    gamma = 0, r = 0.3 from the pre-impact state (0, sdot0).  The flight leaves s = 0 at 0.3 sdot0 against
    f = 0.0015 (which changes sign 0.003 later), turns back at most 3e-11 below the wall and lands on it
    again after ~400 sdot0 time units.  Diffrax's first step (0.01) hid both reversals and the track
    reported the lower wall at t = 2.56 (on the old code, for every sdot0 here); the first segment of a
    departure against the force is now solved on ``[0, 2 |v0 / a0|]`` first (``departure_bound``).  As the
    map: measured relative differences 1.3e-16 ... 3.4e-16 (time), 2.2e-16 ... 8.9e-16 (velocity); bound 1e-13."""
    p = Params(0.5, 0.003, 0.0, 0.3)
    v0 = -p.r * sdot0
    fl = _fl(0.0, 0.0, v0, -1.0, p)
    st, t, wall, v = map_first_impact(0.0, 0.0, v0, p)
    assert st == FlightOutcome.HIT and wall == 0 and t < 1e-3
    assert int(fl.status) == FlightOutcome.HIT and int(fl.wall) == 0
    assert abs(float(fl.t) - t) <= 1e-13 * t and abs(float(fl.v) - v) <= 1e-13 * abs(v)
