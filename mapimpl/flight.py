"""Closed-form free flight between impacts, Eqs. (7)-(8) of the paper, in a cancellation-free form.

Eq. (3) reads ``s'' + beta s' = f(tau)`` with the forcing (right-hand side at rest)::

    f(tau) = -alpha sin(tau) + alpha beta cos(tau) + gamma,          s'' = f(tau) - beta s'.

From a state ``(tau0, s0, sdot0)`` and elapsed flight time ``t = tau - tau0 >= 0``, Eq. (7) is
rewritten exactly as::

    s(tau) - s0   = t sdot0 phi1(beta t) + t^2 Q(t),
    Q(t)          = -(alpha/2) sin(tau0) sinc^2(t/2)
                    + alpha cos(tau0) (beta phi2(beta t) - t sigma(t)) + gamma phi2(beta t),
    sdot(tau)     = sdot0 exp(-beta t)
                    + t [ -alpha sin(tau0 + t/2) sinc(t/2) + (alpha beta cos(tau0) + gamma) phi1(beta t) ]   (Eq. 8)

with ``phi1(x) = (1 - e^-x)/x``, ``phi2(x) = (x - 1 + e^-x)/x^2``, ``sigma(t) = (t - sin t)/t^3``,
``sinc(x) = sin(x)/x``.  Every term is a product of small quantities, so

* the gap to the wall the flight starts from is computed with *relative* accuracy, however small
  the bounce (a flight that starts on a wall has gap exactly 0 at t = 0, no 0/0 and no re-detection);
* ``beta`` down to 1e-8 (and below) loses no digits: the ``gamma/beta`` terms of Eq. (7) cancel
  analytically inside ``phi2``.

The phase ``tau0`` is passed reduced mod 2*pi; only the flight time ``t`` is added to it.
All functions are pure ``jax.numpy`` and work elementwise on arrays (float64).
"""

from __future__ import annotations

from typing import NamedTuple

from ..core import jax_config  # noqa: F401
import jax.numpy as jnp


#: Below this argument phi1 / phi2 use their Taylor series (direct form: < 2 ulp).
SERIES_X = 1.0
_SIGMA_T = 1.5  # below this |t| sigma uses its Taylor series


def horner(x, coeffs):
    """The polynomial ``sum_k coeffs[k] x^k`` by Horner's rule (the Taylor series of Eqs. 7-8's functions)."""
    acc = jnp.zeros_like(x) + coeffs[-1]
    for c in coeffs[-2::-1]:
        acc = acc * x + c
    return acc


def _inv_factorials(start: int, n: int) -> list[float]:
    out, f = [], 1.0
    for k in range(1, start + n):
        f *= k
        if k >= start:
            out.append(1.0 / f)
    return out


# phi2(x) = sum_k (-x)^k / (k+2)!, 18 terms for x < 1 (the next, x^18/20!, is below 0.01 ulp of phi2 >= 1/e);
# sigma(t) = sum_k (-t^2)^k / (2k+3)!
_PHI2_COEFFS = [((-1.0) ** k) * c for k, c in enumerate(_inv_factorials(2, 18))]
#: Taylor coefficients of ``sigma(t) = (t - sin t)/t^3`` in ``t^2``.
SIGMA_COEFFS = [((-1.0) ** k) * c for k, c in enumerate(_inv_factorials(3, 30)[::2][:14])]


def phi12(x, e):
    """``(phi1(x), phi2(x))`` for ``x >= 0`` given ``e = exp(-x)``: ``phi1 = (1 - e)/x`` (limit 1 at 0) and
    ``phi2 = (x - 1 + e)/x^2`` (limit 1/2).

    Below ``x = 1``: one Taylor series for ``phi2`` and ``phi1 = 1 - x phi2`` (an identity; ``x phi2 <=
    1/e``, so no cancellation).  Above: the direct forms with ``expm1(-x) = e - 1`` (exact to rounding:
    ``e <= 1/e``).  Both within 2 ulp (tested against 50-digit values)."""
    big = x >= SERIES_X
    xb = jnp.where(big, x, 1.0)
    em1 = e - 1.0
    p2 = horner(jnp.where(big, 0.0, x), _PHI2_COEFFS)
    return (jnp.where(big, -em1 / xb, 1.0 - x * p2), jnp.where(big, ((xb - 1.0) + e) / (xb * xb), p2))


def phi1(x):
    """(1 - exp(-x)) / x, limit 1 at x = 0 (:func:`phi12`)."""
    return phi12(x, jnp.exp(-x))[0]


def phi2(x):
    """(x - 1 + exp(-x)) / x^2, limit 1/2 at x = 0 (:func:`phi12`)."""
    return phi12(x, jnp.exp(-x))[1]


def sigma(t):
    """``(t - sin t) / t^3``, limit 1/6 at ``t = 0``; Taylor series for ``|t| < 1.5``."""
    big = jnp.abs(t) >= _SIGMA_T
    tb = jnp.where(big, t, 1.0)
    direct = (tb - jnp.sin(tb)) / (tb * tb * tb)
    ts = jnp.where(big, 0.0, t)
    series = horner(ts * ts, SIGMA_COEFFS)
    return jnp.where(big, direct, series)


def sinc(x):
    """sin(x)/x with sinc(0) = 1."""
    small = jnp.abs(x) < 1e-8
    xs = jnp.where(small, 1.0, x)
    return jnp.where(small, 1.0 - x * x / 6.0, jnp.sin(xs) / xs)


class FlightPoint(NamedTuple):
    """Displacement from the start ``ds = s - s0``, velocity ``v = sdot`` and acceleration ``a = s''``."""

    ds: jnp.ndarray
    v: jnp.ndarray
    a: jnp.ndarray


def flight(t, tau0, sdot0, alpha, beta, gamma) -> FlightPoint:
    """Closed-form flight, Eqs. (7)-(8), ``t = tau - tau0 >= 0`` after leaving ``(tau0, s0, sdot0)``.

    Returns ``ds = s(tau) - s0`` (add ``s0`` yourself: the gap to the start wall is ``ds`` itself,
    exactly), ``v = sdot(tau)`` and ``a = s''(tau)``.
    """
    sh, ch = jnp.sin(0.5 * t), jnp.cos(0.5 * t)
    s0, c0 = jnp.sin(tau0), jnp.cos(tau0)
    bt = beta * t
    e = jnp.exp(-bt)
    p1, p2 = phi12(bt, e)
    sc = sinc(0.5 * t)
    q = -0.5 * alpha * s0 * sc * sc + alpha * c0 * (beta * p2 - t * sigma(t)) + gamma * p2
    ds = t * sdot0 * p1 + t * t * q
    sin_mid = s0 * ch + c0 * sh  # sin(tau0 + t/2)
    v = sdot0 * e + t * (-alpha * sin_mid * sc + (alpha * beta * c0 + gamma) * p1)
    # sin/cos(tau0 + t) by the double-angle of t/2 (no further transcendental calls)
    st, ct = 2.0 * sh * ch, 1.0 - 2.0 * sh * sh
    sin_t = s0 * ct + c0 * st
    cos_t = c0 * ct - s0 * st
    a = -alpha * sin_t + alpha * beta * cos_t + gamma - beta * v
    return FlightPoint(ds, v, a)


def flight_textbook(t, tau0, s0, sdot0, alpha, beta, gamma):
    """Eqs. (7)-(8) exactly as printed in the paper (for tests; cancels badly for small beta).

    Returns ``(s, sdot)``.
    """
    tau = tau0 + t
    c = sdot0 - alpha * jnp.cos(tau0) - gamma / beta
    e = jnp.exp(-beta * t)
    s = s0 + alpha * (jnp.sin(tau) - jnp.sin(tau0)) + gamma / beta * t + (1.0 - e) / beta * c
    v = alpha * jnp.cos(tau) + c * e + gamma / beta
    return s, v


def derivative_bounds(t, tau0, sdot0, alpha, beta, gamma):
    """Bounds on ``|s''|``, ``|s'''|``, ``|s''''|`` valid for all flight times ``>= t`` (Eq. 3 differentiated).

    With ``B = beta (sdot0 - alpha cos tau0) - gamma`` one has
    ``s'' = -alpha sin(tau) - B e^{-beta t}``, ``s''' = -alpha cos(tau) + beta B e^{-beta t}``,
    ``s'''' = alpha sin(tau) - beta^2 B e^{-beta t}``, and ``e^{-beta t}`` decreases.
    """
    b = jnp.abs(beta * (sdot0 - alpha * jnp.cos(tau0)) - gamma) * jnp.exp(-beta * t)
    return alpha + b, alpha + beta * b, alpha + beta * beta * b


__all__ = [
    "SERIES_X",
    "horner",
    "SIGMA_COEFFS",
    "phi12",
    "phi1",
    "phi2",
    "sigma",
    "sinc",
    "FlightPoint",
    "flight",
    "flight_textbook",
    "derivative_bounds",
]
