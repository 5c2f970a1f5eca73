"""Chatter and sticking policy (shared by every track).

After an impact at a wall with post-impact speed ``u = r |sdot|``, while the forcing ``f`` of
Eq. (3) presses the tooth into that wall (``f > 0`` at ``s = 0``, ``f < 0`` at ``s = -1``; call the
pressing magnitude ``f_in > 0``), the following bounces have flight times close to ``2 u r^k / f_in``
and accumulate (complete chatter) after

    t_acc = 2 u / ((1 - r) f_in).

**Policy.**  When ``t_acc <= STICK_TIME`` (default 1e-6 in units of tau) and the forcing still presses
at the accumulation point, the infinitely many remaining bounces are replaced by their accumulation
point: the tooth *sticks* to the wall at ``tau + t_acc`` with ``s = wall``, ``sdot = 0``.  It stays
there until the contact acceleration ``f`` changes sign, found in closed form
(``f = gamma - R sin(tau - phi)``, ``R = alpha sqrt(1 + beta^2)``, ``phi = atan(beta)``), and then
leaves the wall with ``sdot = 0`` at the canonical release phase (:func:`release_phase`, a function of
the parameters alone, so every orbit that sticks continues on one post-release orbit).  The error of the jump is ``O(t_acc^2)`` in time
(below 1e-10 for the default).  When ``|gamma| >= R`` the forcing never changes sign and the tooth
stays stuck forever (a terminal state of the orbit).  With ``r = 1`` nothing accumulates and there
is no sticking.  An impact with ``u = 0`` while pressed (grazing into a pressing wall) sticks at once.

Every map step that sticks counts one sticking episode; the bounces between the last computed
impact and the accumulation point are not counted as impacts.
"""

from __future__ import annotations

from typing import NamedTuple

from ..core import jax_config  # noqa: F401
import jax.numpy as jnp

from .forcing import forcing_rate_sc, forcing_sc
from ..core.checks import check_real, check_tau0, check_wall, is_traced
from ..core.params import check_param
from ..core.phase import TWO_PI, reduce_phase

#: Predicted chatter accumulation time below which the tooth is stuck to the wall (units of tau).
STICK_TIME = 1e-6

#: Largest ``stick_time`` accepted (the jump's error grows as ``t_acc^2``: 1e-4 in time at this bound).
MAX_STICK_TIME = 1e-2


def check_stick_time(stick_time) -> float:
    """The policy's threshold as a float, ``0 <= stick_time <= MAX_STICK_TIME`` (1e-2); ``ValueError``
    (``TypeError`` for a non-number) naming ``stick_time`` and that range (:func:`core.checks.check_real`).
    Every entry point that takes ``stick_time`` checks it with this one function, once, before any work."""
    return check_real("stick_time", stick_time, 0.0, MAX_STICK_TIME)


def stick_time_meta(stick_time: float) -> dict:
    """``{"stick_time": stick_time}`` for an orbit's ``meta`` where it is not the default :data:`STICK_TIME`
    (an orbit under the default writes what it wrote before the threshold was a parameter), else ``{}``."""
    return {} if stick_time == STICK_TIME else {"stick_time": stick_time}


def wall_direction(wall):
    """+1 for the upper wall (``wall == 0``, ``s = 0``), -1 for the lower wall (``wall == -1``)."""
    return jnp.where(wall == 0, 1.0, -1.0)


def release_phase(wall, alpha, beta, gamma):
    """The canonical release phase at ``wall``: ``(phase, never)``.

    The contact force ``f = gamma - R sin(tau - phi)`` (``R = alpha sqrt(1 + beta^2)``,
    ``phi = atan(beta)``) stops pressing into the upper wall where it falls through zero,
    ``tau = phi + asin(gamma/R)``, and into the lower wall where it rises through zero,
    ``tau = phi + pi - asin(gamma/R)`` (mod 2 pi).  The phase is a function of the parameters
    alone, computed by this one float64 expression: every orbit that sticks to a wall is released
    at the same phase with ``sdot = 0``, so all of them continue on *one* post-release orbit (bit for
    bit, whatever their own sticking phase).  ``never``: the force never changes sign
    (``|gamma| >= R`` on the pressing side): stuck forever.

    Called with concrete values (not under ``jit``), ``wall`` must be 0 or -1 and ``alpha, beta, gamma``
    in the ranges of :class:`~gear_rattle.core.params.Params` (``ValueError``/``TypeError`` naming the
    argument); traced, its caller has checked them.
    """
    if not is_traced(wall, alpha, beta, gamma):
        check_wall("wall", wall)
        for name, value in (("alpha", alpha), ("beta", beta), ("gamma", gamma)):
            check_param(name, value)
    R = alpha * jnp.sqrt(1.0 + beta * beta)
    phi = jnp.arctan(beta)
    Rs = jnp.where(R > 0.0, R, 1.0)
    c = gamma / Rs
    never = (R <= 0.0) | (jnp.where(wall == 0, c, -c) >= 1.0)
    cc = jnp.clip(c, -1.0, 1.0)
    psi = jnp.where(wall == 0, jnp.arcsin(cc), jnp.pi - jnp.arcsin(cc))
    phase, _ = reduce_phase(phi + psi, jnp.zeros(jnp.shape(phi + psi), jnp.int32))
    return phase, never


def release_delay(theta, wall, alpha, beta, gamma):
    """Time from phase ``theta`` until the contact force at ``wall`` stops pressing (``inf`` if never):
    the first downward zero crossing of ``dir * f`` after ``theta``, at :func:`release_phase`."""
    phase, never = release_phase(wall, alpha, beta, gamma)
    delay = jnp.mod(phase - theta, TWO_PI)
    return jnp.where(never, jnp.inf, delay)


def released_turns(theta, delay, phase):
    """Whole driving periods to add to the turn counter of an orbit stuck at phase ``theta``
    (``0 <= theta < 2 pi``) and released ``delay`` later at the canonical ``phase``: ``theta +
    delay = phase + 2 pi turns`` up to rounding (so ``turns`` is 0 or 1)."""
    return jnp.round((theta + delay - phase) / TWO_PI).astype(jnp.int32)


class StickDecision(NamedTuple):
    """``stick``: the tooth sticks; ``t_acc``: accumulation delay; ``delay``: release delay from
    the impact (``inf`` = stuck forever); ``phase``: the canonical release phase of the wall
    (:func:`release_phase`; the flight after a release starts there)."""

    stick: jnp.ndarray
    t_acc: jnp.ndarray
    delay: jnp.ndarray
    phase: jnp.ndarray


def check_stick(theta, wall, sdot, alpha, beta, gamma, r, stick_time=STICK_TIME) -> None:
    """The arguments of :func:`decide_stick` (:mod:`core.checks`): a phase ``|theta| <= 1e6``, ``wall``
    0 or -1, a finite ``sdot``, parameters in the ranges of :class:`~gear_rattle.core.params.Params` and
    ``0 <= stick_time <= MAX_STICK_TIME``."""
    check_tau0(theta, "theta")
    check_wall("wall", wall)
    check_real("sdot", sdot)
    for name, value in (("alpha", alpha), ("beta", beta), ("gamma", gamma), ("r", r)):
        check_param(name, value)
    check_stick_time(stick_time)


def decide_stick(theta, wall, sdot, alpha, beta, gamma, r, stick_time=STICK_TIME) -> StickDecision:
    """Apply the sticking policy to an impact at phase ``theta`` on ``wall`` with pre-impact ``sdot``.
    Called with concrete values it checks them first (:func:`check_stick`)."""
    if not is_traced(theta, wall, sdot, alpha, beta, gamma, r, stick_time):
        check_stick(theta, wall, sdot, alpha, beta, gamma, r, stick_time)
    return decide_stick_sc(theta, jnp.sin(theta), jnp.cos(theta), wall, sdot, alpha, beta, gamma, r, stick_time)


def decide_stick_sc(
    theta, sin_t, cos_t, wall, sdot, alpha, beta, gamma, r, stick_time=STICK_TIME, release=None
) -> StickDecision:
    """:func:`decide_stick` with ``sin(theta), cos(theta)`` given; ``release``: ``(phase, never)`` of
    :func:`release_phase` for ``wall`` when the caller has it already (the engine computes it once
    per orbit: it depends on the parameters alone)."""
    d = wall_direction(wall)
    u = r * jnp.abs(sdot)
    f_in = d * forcing_sc(sin_t, cos_t, alpha, beta, gamma)
    pressing = (f_in > 0.0) | ((f_in == 0.0) & (d * forcing_rate_sc(sin_t, cos_t, alpha, beta) > 0.0))
    denom = (1.0 - r) * f_in
    t_acc = jnp.where(u == 0.0, 0.0, jnp.where(denom > 0.0, 2.0 * u / jnp.where(denom > 0.0, denom, 1.0), jnp.inf))
    phase, never = release_phase(wall, alpha, beta, gamma) if release is None else release
    delay = jnp.where(never, jnp.inf, jnp.mod(phase - theta, TWO_PI))
    stick = pressing & (t_acc <= stick_time) & (delay > t_acc)
    return StickDecision(stick, t_acc, delay, phase)


__all__ = [
    "STICK_TIME",
    "MAX_STICK_TIME",
    "wall_direction",
    "release_phase",
    "release_delay",
    "released_turns",
    "StickDecision",
    "check_stick",
    "decide_stick",
    "decide_stick_sc",
]
