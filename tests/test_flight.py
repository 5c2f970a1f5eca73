"""Closed-form flight, Eqs. (7)-(8): agreement with the printed formulas, Eq. (3) residual,
small-beta stability and relative accuracy of slow bounces."""

import jax
import jax.numpy as jnp
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, strategies as st

from gear_rattle.mapimpl.flight import flight, flight_textbook, forcing, phi1, phi2, reduce_phase, sigma, TWO_PI
from tests.mpref import s_and_v

finite = dict(allow_nan=False, allow_infinity=False)


@given(t=st.floats(0, 30, **finite), tau0=st.floats(0, 6.28, **finite), v0=st.floats(-3, 3, **finite),
       alpha=st.floats(0, 5, **finite), beta=st.floats(1e-3, 1, **finite), gamma=st.floats(-0.5, 0.5, **finite))
def test_matches_eq7_eq8_as_printed(t, tau0, v0, alpha, beta, gamma):
    fp = flight(t, tau0, v0, alpha, beta, gamma)
    s_ref, v_ref = s_and_v(t, tau0, 0, v0, alpha, beta, gamma)
    scale = 1 + abs(v0) * t + (alpha + abs(gamma)) * (1 + t * t)
    assert abs(float(fp.ds) - float(s_ref)) <= 1e-14 * scale
    assert abs(float(fp.v) - float(v_ref)) <= 1e-14 * (1 + abs(v0) + alpha + abs(gamma) * (1 + t))


@given(t=st.floats(0, 20, **finite), tau0=st.floats(0, 6.28, **finite), v0=st.floats(-3, 3, **finite),
       alpha=st.floats(0, 5, **finite), beta=st.floats(1e-8, 1, **finite), gamma=st.floats(-0.5, 0.5, **finite))
def test_eq3_residual(t, tau0, v0, alpha, beta, gamma):
    """s'' + beta s' = f(tau) along the closed form (derivatives by autodiff); a = s'' too."""
    ds = lambda x: flight(x, tau0, v0, alpha, beta, gamma).ds  # noqa: E731
    d1 = jax.grad(ds)(t)
    d2 = jax.grad(jax.grad(ds))(t)
    fp = flight(t, tau0, v0, alpha, beta, gamma)
    f = forcing(tau0 + t, alpha, beta, gamma)
    tol = 1e-12 * (1 + alpha + abs(gamma) + abs(v0))
    assert abs(float(d2 + beta * d1 - f)) <= tol
    assert abs(float(d1 - fp.v)) <= tol
    assert abs(float(d2 - fp.a)) <= tol


@pytest.mark.parametrize("beta", [1e-8, 1e-5, 1e-2, 1.0])
@pytest.mark.parametrize("t", [1e-9, 1e-3, 0.4, 3.0, 25.0])
def test_small_beta_no_cancellation(beta, t):
    """Relative accuracy ~1e-15 for beta down to 1e-8 (the printed formula loses ~8 digits there)."""
    tau0, v0, a, g = 1.3, 0.4, 3.0, 0.1
    fp = flight(t, tau0, v0, a, beta, g)
    s_ref, v_ref = s_and_v(t, tau0, 0, v0, a, beta, g)
    assert abs(float(fp.ds) - float(s_ref)) <= 4e-15 * abs(float(s_ref)) + 1e-300
    assert abs(float(fp.v) - float(v_ref)) <= 4e-16 * (1 + a + abs(v0))


def test_textbook_formula_cancels_for_small_beta():
    """Documents why the rewritten form exists: Eq. (7) verbatim has error ~ eps * gamma/beta^2."""
    t, tau0, v0, a, b, g = 3.0, 1.3, 0.4, 3.0, 1e-8, 0.1
    s_tb, _ = flight_textbook(t, tau0, 0.0, v0, a, b, g)
    s_ref, _ = s_and_v(t, tau0, 0, v0, a, b, g)
    assert abs(float(s_tb) - float(s_ref)) > 1e-6


@pytest.mark.parametrize("v0", [-1e-4, -1e-8, -1e-12])
@pytest.mark.parametrize("t", [1e-5, 1e-9, 1e-13])
def test_slow_bounce_relative_accuracy(v0, t):
    """A bounce lower than any absolute tolerance is still resolved: ds has relative error ~1e-15."""
    tau0, a, b, g = 2.0, 3.0, 0.1, 0.1
    fp = flight(t, tau0, v0, a, b, g)
    s_ref, _ = s_and_v(t, tau0, 0, v0, a, b, g)
    assert abs(float(fp.ds) - float(s_ref)) <= 1e-14 * abs(float(s_ref))


def test_phi_functions_series_and_direct_agree():
    for x in [1e-12, 1e-4, 0.1, 0.5, 0.99999, 1.0, 1.00001, 1.49999, 1.5, 2.0, 50.0]:
        xm = mp.mpf(x)
        assert abs(float(phi1(x)) - float((1 - mp.exp(-xm)) / xm)) < 2e-16
        assert abs(float(phi2(x)) - float((xm - 1 + mp.exp(-xm)) / xm**2)) < 2e-16
        assert abs(float(sigma(x)) - float((xm - mp.sin(xm)) / xm**3)) < 3e-16


def test_reduce_phase_keeps_turns_and_phase():
    theta, cycles = reduce_phase(jnp.asarray(1e6 + 0.25), jnp.asarray(0, jnp.int64))
    k = int(np.floor(1e6 / (2 * np.pi)))
    assert int(cycles) == k
    assert abs(float(theta) - float(mp.mpf(1e6 + 0.25) - k * 2 * mp.pi)) < 1e-9
    for x in [0.0, float(TWO_PI), -1e-18, 6.283185307179586, 12.566370614359172]:
        th, _ = reduce_phase(jnp.asarray(x), jnp.asarray(0, jnp.int64))
        assert 0.0 <= float(th) < 2 * np.pi
