"""The forcing of Eq. (3): the acceleration ``s''`` of the tooth at rest, ``f(tau) = -alpha sin(tau) +
alpha beta cos(tau) + gamma``, and its rate.  On a wall it is the contact acceleration that the sticking
policy (:mod:`gear_rattle.mapimpl.sticking`) reads; the closed-form flight
(:mod:`gear_rattle.mapimpl.flight`) is built on it.  A module of its own so that the numerical tracks,
which share the sticking policy, import no part of the closed-form flight (the import contract in
pyproject.toml).
"""

from __future__ import annotations

from ..core import jax_config  # noqa: F401
import jax.numpy as jnp


def forcing(tau, alpha, beta, gamma):
    """f(tau) = -alpha sin(tau) + alpha beta cos(tau) + gamma: the acceleration s'' at rest (Eq. 3).

    On a wall with ``sdot = 0`` this is the contact acceleration: it presses into the upper wall
    ``s = 0`` when positive and into the lower wall ``s = -1`` when negative.
    """
    return forcing_sc(jnp.sin(tau), jnp.cos(tau), alpha, beta, gamma)


def forcing_sc(sin_t, cos_t, alpha, beta, gamma):
    """:func:`forcing` from ``sin(tau), cos(tau)``."""
    return -alpha * sin_t + alpha * beta * cos_t + gamma


def forcing_rate(tau, alpha, beta):
    """df/dtau = -alpha cos(tau) - alpha beta sin(tau)."""
    return forcing_rate_sc(jnp.sin(tau), jnp.cos(tau), alpha, beta)


def forcing_rate_sc(sin_t, cos_t, alpha, beta):
    """:func:`forcing_rate` from ``sin(tau), cos(tau)``."""
    return -alpha * cos_t - alpha * beta * sin_t


__all__ = [
    "forcing",
    "forcing_sc",
    "forcing_rate",
    "forcing_rate_sc",
]
