"""The event specification of the hybrid ODE (Eq. 3 with the impact law Eqs. 9-11) shared by the
scipy and diffrax tracks: each condition's sign and direction at hand-made states, the segment
outcomes, the flight directions, and the same answers on numpy floats and on JAX arrays."""

from __future__ import annotations

import math

import numpy as np
import pytest

import gear_rattle  # noqa: F401  (float64: importing the package switches JAX to it)
import jax
import jax.numpy as jnp

from gear_rattle.core.horizons import T_MAX as MAP_T_MAX
from gear_rattle.reference import events as ev

UP, DOWN = 1.0, -1.0


# ---------------------------------------------------------------- conditions: sign
@pytest.mark.parametrize(
    "sigma, s, sign",
    [
        (UP, -0.5, -1),
        (UP, -1.0, -1),
        (UP, 0.0, 0),
        (UP, 1e-9, 1),  # toward s = 0
        (DOWN, -0.5, -1),
        (DOWN, 0.0, -1),
        (DOWN, -1.0, 0),
        (DOWN, -1.0 - 1e-9, 1),  # toward s = -1
    ],
)
def test_wall_condition_is_negative_inside_zero_on_the_wall_ahead_positive_beyond(sigma, s, sign):
    assert np.sign(ev.wall_condition(s, sigma)) == sign


def test_the_wall_behind_a_segment_does_not_count():
    # a segment leaving s = 0 downward starts on that wall: its condition is -1 there, a full gap away
    assert ev.wall_condition(0.0, DOWN) == -1.0
    assert ev.wall_condition(-1.0, UP) == -1.0
    assert ev.wall_ahead(UP) == ev.UPPER_WALL == 0 and ev.wall_ahead(DOWN) == ev.LOWER_WALL == -1


@pytest.mark.parametrize(
    "sigma, sdot, sign",
    [
        (UP, 0.3, -1),
        (UP, 0.0, 0),
        (UP, -0.1, 1),
        (DOWN, -0.3, -1),
        (DOWN, 0.0, 0),
        (DOWN, 0.1, 1),
    ],
)
def test_reversal_condition_is_negative_while_moving_in_the_segment_direction(sigma, sdot, sign):
    assert np.sign(ev.reversal_condition(sdot, sigma)) == sign


# ---------------------------------------------------------------- conditions: direction
def test_both_events_are_terminal_upcrossings():
    assert ev.DIRECTION == 1 and ev.TERMINAL is True


@pytest.mark.parametrize("sigma", [UP, DOWN])
def test_the_wall_is_reached_as_an_upcrossing(sigma):
    # moving toward the wall ahead (sdot has the sign of sigma): the condition rises through zero
    f = (0.7 * sigma, -2.0)  # (sdot, sddot), any acceleration
    assert ev.wall_rate(f, sigma) > 0.0
    assert ev.condition_rate(f, sigma, True) == ev.wall_rate(f, sigma)


@pytest.mark.parametrize("sigma", [UP, DOWN])
def test_a_velocity_reversal_is_an_upcrossing(sigma):
    # at an extremum of s in a segment of direction sigma, the acceleration points against sigma
    f = (0.0, -1.5 * sigma)
    assert ev.reversal_rate(f, sigma) > 0.0
    assert ev.condition_rate(f, sigma, False) == ev.reversal_rate(f, sigma)


@pytest.mark.parametrize("sigma", [UP, DOWN])
@pytest.mark.parametrize("wall", [True, False])
def test_rates_are_the_derivatives_of_the_conditions_along_the_vector_field(sigma, wall):
    y, f, h = np.array([-0.4, 0.3]), np.array([0.3, -0.8]), 1e-6
    fd = (ev.condition(y + h * f, sigma, wall) - ev.condition(y, sigma, wall)) / h
    assert fd == pytest.approx(ev.condition_rate(f, sigma, wall), rel=1e-8)


def test_newton_step_lands_on_the_root_of_a_linear_condition():
    assert ev.newton_step(-0.2, 0.4) == pytest.approx(0.5)
    assert ev.newton_step(0.3, 0.6) == pytest.approx(-0.5)
    assert ev.newton_step(0.3, 0.0) == 0.0  # no rate: no step, no division by zero


# ---------------------------------------------------------------- segment outcomes
@pytest.mark.parametrize(
    "sigma, s, beyond",
    [
        (UP, 1e-12, True),
        (UP, 0.0, False),
        (UP, -0.5, False),
        (DOWN, -1.0 - 1e-12, True),
        (DOWN, -1.0, False),
        (DOWN, -0.5, False),
        (DOWN, 0.2, False),
    ],
)
def test_beyond_wall(sigma, s, beyond):
    assert bool(ev.beyond_wall(s, sigma)) is beyond
    assert bool(ev.beyond_wall(s, sigma)) is bool(ev.wall_condition(s, sigma) > 0.0)


@pytest.mark.parametrize(
    "hit, reversal, s_end, sigma, end",
    [
        (True, False, 0.0, UP, ev.WALL_REACHED),
        (False, True, -0.3, UP, ev.REVERSAL),
        (False, True, 1e-9, UP, ev.MISSED_CROSSING),  # extremum above s = 0: crossed and came back
        (False, True, -0.3, DOWN, ev.REVERSAL),
        (False, True, -1.0 - 1e-9, DOWN, ev.MISSED_CROSSING),
        (False, False, -0.3, UP, ev.OPEN_END),
    ],
)
def test_segment_end(hit, reversal, s_end, sigma, end):
    assert ev.segment_end(hit, reversal, s_end, sigma) == end


# ---------------------------------------------------------------- flight directions and starts
@pytest.mark.parametrize(
    "s0, v0, a0, sigma",
    [
        (-0.5, 0.2, -9.0, UP),
        (-0.5, -0.2, 9.0, DOWN),  # moving: the sign of sdot
        (0.0, 0.0, 9.0, DOWN),
        (-1.0, 0.0, -9.0, UP),  # at rest on a wall: away from it
        (-0.5, 0.0, 0.3, UP),
        (-0.5, 0.0, -0.3, DOWN),
        (-0.5, 0.0, 0.0, UP),  # at rest inside: acceleration
    ],
)
def test_initial_direction(s0, v0, a0, sigma):
    assert ev.initial_direction(s0, v0, a0) == sigma


@pytest.mark.parametrize(
    "wall, v0, sigma",
    [
        (0, -0.45, DOWN),
        (0, 0.0, DOWN),  # after an impact on s = 0 (v0 = -r sdot < 0) or a release there
        (-1, 0.45, UP),
        (-1, 0.0, UP),
    ],
)
def test_restart_moves_away_from_the_wall(wall, v0, sigma):
    assert ev.restart_direction(wall, v0) == sigma
    # so the wall it starts on is not the wall ahead: a restart never re-fires the impact
    assert ev.wall_condition(float(wall), sigma) == -1.0


@pytest.mark.parametrize(
    "s0, sdot0, a0, wall",
    [
        (0.0, 0.3, -1.0, 0),
        (0.0, 0.0, 1.0, 0),
        (0.0, 0.0, -1.0, None),
        (0.0, -0.3, 1.0, None),
        (-1.0, -0.3, 1.0, -1),
        (-1.0, 0.0, -1.0, -1),
        (-1.0, 0.0, 1.0, None),
        (-1.0, 0.3, -1.0, None),
        (-0.5, 1.0, 1.0, None),
    ],
)
def test_pre_impact_wall(s0, sdot0, a0, wall):
    assert ev.pre_impact_wall(s0, sdot0, a0) == wall


def test_start_wall():
    from gear_rattle.core.checks import start_wall

    assert start_wall(None, 0.4) == 0 and start_wall(None, -0.4) == -1 and start_wall(-1, 0.4) == -1
    for bad in (1, -2, True, 0.5):
        with pytest.raises(ValueError, match="wall=.* is (out of range|a bool): allowed 0"):
            start_wall(bad, 0.4)


@pytest.mark.parametrize("sigma", [UP, DOWN])
def test_hidden_reversal_needs_a_backward_velocity_above_the_tolerance(sigma):
    # a speed minimum with sdot against sigma is a hidden double reversal; one below the integrator's
    # absolute tolerance has no resolvable sign (the rounding-level dip right after a release)
    assert ev.hidden_reversal(-sigma * 1e-3, sigma) and ev.hidden_reversal(-sigma * 1e-3, sigma, 1e-13)
    assert ev.hidden_reversal(-sigma * 1e-31, sigma) and not ev.hidden_reversal(-sigma * 1e-31, sigma, 1e-13)
    assert not ev.hidden_reversal(sigma * 1e-3, sigma, 1e-13) and not ev.hidden_reversal(0.0, sigma)


@pytest.mark.parametrize("sigma", [UP, DOWN])
def test_a_segment_at_rest_is_solved_from_a_velocity_along_it(sigma):
    # its reversal condition then starts strictly negative (an upcrossing in the first step has a
    # bracket that does not end at the start); a velocity along sigma is kept as it is
    assert ev.start_velocity(sigma * 0.3, sigma) == sigma * 0.3
    for v in (0.0, -0.0, -sigma * 1e-29):
        v_s = ev.start_velocity(v, sigma)
        assert v_s == sigma * ev.START_SPEED and ev.reversal_condition(v_s, sigma) < 0.0
    assert 0.0 < ev.START_SPEED < 1e-290


def test_caps():
    assert ev.T_MAX is MAP_T_MAX  # the one orbit horizon (core.horizons), imported, not restated
    assert isinstance(ev.MAX_SEGMENTS, int) and ev.MAX_SEGMENTS >= 1000


# ---------------------------------------------------------------- one spec for numpy and JAX
_GRID = [(s, v, sig) for s in (-1.2, -1.0, -0.5, 0.0, 0.1) for v in (-0.3, 0.0, 0.3) for sig in (UP, DOWN)]


def test_select_dispatches_on_the_condition_type():
    a, b = object(), object()
    assert ev.select(True, a, b) is a and ev.select(np.bool_(False), a, b) is b
    assert isinstance(ev.select(np.array([True, False]), 1.0, 2.0), np.ndarray)
    assert isinstance(ev.select(jnp.asarray(True), 1.0, 2.0), jax.Array)


def test_same_values_on_floats_and_on_jax_arrays_under_jit_and_vmap():
    s, v, sig = (np.array(x) for x in zip(*_GRID))
    a0 = np.linspace(-1.0, 1.0, len(s))

    def spec(s, v, sig, a0):
        f = (v, a0 - 0.1 * v)
        return (
            ev.wall_condition(s, sig),
            ev.reversal_condition(v, sig),
            ev.condition_rate(f, sig, s > -0.7),
            ev.beyond_wall(s, sig),
            ev.segment_end(v > 0.0, v < 0.0, s, sig),
            ev.initial_direction(s, v, a0),
            ev.wall_ahead(sig),
            ev.newton_step(s, v),
            ev.start_velocity(v, sig),
        )

    on_jax = jax.jit(jax.vmap(spec))(s, v, sig, a0)
    for i in range(len(s)):
        on_host = spec(float(s[i]), float(v[i]), float(sig[i]), float(a0[i]))
        for h, j in zip(on_host, on_jax):
            assert h == j[i] or (math.isnan(h) and math.isnan(j[i]))


def test_conditions_are_differentiable_on_jax():
    # the diffrax track differentiates through the event conditions (jax.jacfwd of one step)
    y = jnp.array([-0.3, 0.4])
    assert jnp.array_equal(jax.jacfwd(lambda y: ev.wall_condition(y[0], jnp.asarray(DOWN)))(y), jnp.array([-1.0, 0]))
    assert jnp.array_equal(jax.jacfwd(lambda y: ev.reversal_condition(y[1], jnp.asarray(UP)))(y), jnp.array([0, -1.0]))


# ---------------------------------------------------------------- both tracks use the spec
def test_scipy_events_are_the_spec():
    from gear_rattle.reference import scipy_track as S

    y = np.array([-0.25, 0.6])
    for sigma in (UP, DOWN):
        wall_ev, rev_ev = S.segment_events(sigma)
        assert wall_ev(0.0, y) == ev.wall_condition(y[0], sigma)
        assert rev_ev(0.0, y) == ev.reversal_condition(y[1], sigma)
        assert wall_ev.direction == rev_ev.direction == ev.DIRECTION
        assert wall_ev.terminal is rev_ev.terminal is ev.TERMINAL
