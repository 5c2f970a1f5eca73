"""Diffrax reference track (Eq. 3, diffeqsolve + Event in a while_loop): traps, sticking, jit/vmap."""

from __future__ import annotations

import numpy as np
import pytest

from gear_rattle.mapimpl import _jax  # noqa: F401
import jax

from gear_rattle.mapimpl.finder import HIT
from gear_rattle.mapimpl.orbit import map_orbit
from gear_rattle.mapimpl.params import Params
from gear_rattle.reference import diffrax_track as D
from refhelpers import N_ORBIT, map_first_impact, v0_for_apex

_flight = jax.jit(D.flight)


def _fl(theta, s0, v0, sigma, p):
    return jax.tree.map(np.asarray, _flight(theta, s0, v0, sigma, p.alpha, p.beta, p.gamma))


@pytest.mark.parametrize("depth", [1e-4, 1e-8, -1e-8])
def test_double_crossing_and_near_miss(depth):
    """diffrax issue 507: an excursion beyond s = 0 inside one step is still an impact."""
    p = Params(0.0, 0.1, -0.5, 0.9)
    v0 = v0_for_apex(depth)
    fl = _fl(0.0, -1.0, v0, 1.0, p)
    st, t, wall, v = map_first_impact(0.0, -1.0, v0, p)
    assert st == HIT and int(fl.status) == D.HIT and int(fl.wall) == wall == (0 if depth > 0 else -1)
    vex = max(abs(v), 1e-12)
    assert abs(float(fl.t) - t) <= 1e-12 / vex**2 + 1e-12 and abs(float(fl.v) - v) <= 1e-12 / vex


@pytest.mark.parametrize("v0", [-0.1, -1e-4])
def test_restart_on_wall_returns_to_same_wall(v0):
    p = Params(0.5, 0.1, 0.9, 0.5)
    fl = _fl(0.3, 0.0, v0, -1.0, p)
    st, t, wall, v = map_first_impact(0.3, 0.0, v0, p)
    assert int(fl.status) == D.HIT and int(fl.wall) == wall == 0 and int(fl.segments) == 2
    assert abs(float(fl.t) - t) <= 1e-12 * max(1.0, t) + 1e-15 and float(fl.t) > abs(v0)


def test_chatter_sticks_forever_like_the_map():
    p = Params(0.5, 0.1, 0.9, 0.5)
    m = map_orbit(p, 0.0, 0.5, N_ORBIT)
    d = D.orbit(p, 0.0, 0.5, N_ORBIT)
    assert d.track == "diffrax" and d.status == m.status == "stuck_forever"
    assert list(d.kind) == list(m.kind)
    assert np.max(np.abs(d.tau - m.tau)) < 1e-9


def test_batch_equals_single_orbits():
    p = Params(1.0, 0.5, 0.2, 0.4)
    tau0 = np.array([0.0, 1.0, 2.5])
    sd0 = np.array([0.5, -0.3, 1.2])
    tr = D.batch_orbit(p, tau0, sd0, 4)
    for i in range(3):
        one = D.iterate(jax.tree.map(lambda x: x[i], D.make_state(tau0, sd0)), p.arrays(), 4)
        np.testing.assert_array_equal(np.asarray(tr.states.wall[i]), np.asarray(one.states.wall))
        np.testing.assert_allclose(np.asarray(tr.states.tau[i]), np.asarray(one.states.tau), rtol=0, atol=1e-13)


@pytest.mark.parametrize("kw,name", [(dict(rtol=0.0), "rtol"), (dict(dtmax=-1.0), "dtmax"),
                                     (dict(max_steps=0), "max_steps")])
def test_bad_options_raise(kw, name):
    with pytest.raises(ValueError, match=name):
        D.orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 2, **kw)


def test_bad_start_raises():
    with pytest.raises(ValueError, match="sdot0"):
        D.orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.0, 2)
