"""The event specification of the hybrid ODE, shared by both reference tracks.

Eq. (3), ``s'' = -alpha sin(tau) + alpha beta cos(tau) + gamma - beta s'``, holds while the tooth is
inside the backlash, ``-1 <= s <= 0``; the impact law Eqs. (9)-(11) resets ``sdot -> -r sdot`` at
``s = 0`` reached upward and at ``s = -1`` reached downward.  Both tracks (:mod:`reference.scipy_track`
with numpy floats, :mod:`reference.diffrax_track` with JAX arrays under jit, vmap and jacfwd)
integrate every flight as a chain of **monotone segments** defined here:

* a segment has a direction ``sigma = +-1`` (the sign of ``sdot`` on it) and watches two
  **terminal** event functions, both ``<= 0`` at its start and both located as **upcrossings**
  (:data:`DIRECTION`): the wall ahead, :func:`wall_condition` (``s`` for ``sigma = +1``,
  ``-1 - s`` for ``sigma = -1``), and the velocity reversal, :func:`reversal_condition`
  (``-sigma sdot``, an extremum of ``s``);
* a segment ends (:func:`segment_end`) at the wall (:data:`WALL_REACHED`: an impact), at a reversal
  inside the gap (:data:`REVERSAL`: the next segment starts there with ``-sigma``), at a reversal
  *beyond* the wall ahead (:data:`MISSED_CROSSING`: ``s`` crossed the wall and came back inside one
  solver step, scipy issue 9228 / diffrax issue 507; ``s`` is monotone from the segment start to
  the extremum, so the tracks solve again on exactly that interval watching the wall only, where
  the crossing is a sign change; if that solve finds no crossing the extremum is a reversal), or
  without an event (:data:`OPEN_END`: the flight horizon :data:`~gear_rattle.core.horizons.T_MAX` or a solver failure);
* a flight starts (:func:`initial_direction`) in the direction of ``sdot``; at rest on a wall,
  away from it; at rest inside, in the direction of the acceleration.  After an impact or a release
  the flight restarts on the wall (:func:`restart_direction`) moving away from it, so the wall it
  starts on is watched again only after a reversal (a restart never re-fires the impact);
* caps: at most :data:`MAX_SEGMENTS` segments per flight (else ``"step_cap"``) and a flight of at
  most :data:`~gear_rattle.core.horizons.T_MAX` (else ``"no_impact"``, as in every track);
* event accuracy: an event time found on the interpolant is refined by one Newton step
  (:func:`newton_step`) on the event function, whose rate along the vector field ``f = (sdot,
  sddot)`` is :func:`condition_rate`.

Every function here serves both tracks: a branch is a :func:`select`, a Python conditional on a
Python or numpy bool and ``jnp.where`` on a JAX array (so the diffrax track stays traceable and the
two tracks evaluate exactly the same expressions).
"""

from __future__ import annotations

import math

import numpy as np

from ..core import jax_config  # noqa: F401  (float64)
from ..core.horizons import T_MAX  # (a flight longer than it ends the orbit with "no_impact")
import jax.numpy as jnp

#: Most monotone segments (velocity reversals + 1) integrated in one flight before ``"step_cap"``.
MAX_SEGMENTS = 4000
#: Speed a segment that starts at rest is solved from (:func:`start_velocity`): far below every error of
#: the tracks, yet it makes the reversal condition start strictly negative.
START_SPEED = 1e-300

#: The walls: ``s = 0`` (reached with ``sdot > 0``) and ``s = -1`` (reached with ``sdot < 0``).
UPPER_WALL, LOWER_WALL = 0, -1
#: Both event functions are located where they cross zero upward (scipy ``direction=+1``, diffrax
#: ``direction=True``) and both end the segment (scipy ``terminal=True``).
DIRECTION = 1
TERMINAL = True

#: How a monotone segment ends (:func:`segment_end`).
WALL_REACHED, REVERSAL, MISSED_CROSSING, OPEN_END = 0, 1, 2, 3


def select(cond, a, b):
    """``a if cond else b``: a Python conditional for a Python/numpy bool, elementwise otherwise
    (``np.where`` on a numpy array, ``jnp.where`` on a JAX array or tracer)."""
    if isinstance(cond, (bool, np.bool_)):
        return a if cond else b
    if isinstance(cond, np.ndarray):
        return np.where(cond, a, b)
    return jnp.where(cond, a, b)


def wall_ahead(sigma):
    """The wall a segment of direction ``sigma`` moves toward: 0 for ``sigma > 0``, -1 otherwise."""
    return select(sigma > 0, UPPER_WALL, LOWER_WALL)


def wall_condition(s, sigma):
    """Event function of the wall ahead: ``s`` (``sigma > 0``) or ``-1 - s``; ``<= 0`` inside the
    gap, positive beyond the wall."""
    return select(sigma > 0, s, -1.0 - s)


def reversal_condition(sdot, sigma):
    """Event function of the velocity reversal: ``-sigma sdot`` (``< 0`` while ``s`` moves in the
    direction ``sigma``, zero at an extremum of ``s``)."""
    return -sigma * sdot


def dip_condition(sddot, sigma):
    """Event function of a **speed minimum** inside a segment: ``sigma sddot`` crosses zero upward where
    ``sigma sdot`` stops decreasing.  Watched without ending the segment: if ``sigma sdot < 0`` there, the
    velocity reversed and reversed back inside one solver step (both step ends have the same sign of
    ``sdot``, so the reversal event missed it), and the segment is solved again up to that minimum,
    where the reversal is a sign change (:func:`hidden_reversal`)."""
    return sigma * sddot


def hidden_reversal(sdot_at_dip, sigma, tol=0.0):
    """At a speed minimum (:func:`dip_condition`): the velocity points against ``sigma`` there by more
    than ``tol``, so the segment reversed (twice) unseen before it.

    ``tol`` is the velocity the integrator cannot tell from zero (its absolute tolerance): a dip whose
    backward velocity is below it has no resolvable sign.  Such a dip follows many releases from
    sticking: the forcing of Eq. (3) vanishes at the release phase only to rounding (``|s''| ~ 1e-16``),
    and with the wrong sign of that rounding ``sdot`` dips to about ``-s''^2 / (2 s''') ~ -1e-31`` just
    after the start.  Counted as a reversal it split the flight into segments ~1e-16 long at its start
    (repeated joints in the dense output) and, while the reversal condition started at zero (before
    :func:`start_velocity`), into zero-length segments up to :data:`MAX_SEGMENTS` (``"step_cap"``)."""
    return sigma * sdot_at_dip < -tol


def wall_rate(f, sigma):
    """Rate of :func:`wall_condition` along the vector field ``f = (sdot, sddot)``."""
    return select(sigma > 0, f[0], -f[0])


def reversal_rate(f, sigma):
    """Rate of :func:`reversal_condition` along the vector field ``f = (sdot, sddot)``."""
    return -sigma * f[1]


def condition(y, sigma, wall):
    """The event function of the wall ahead (``wall`` true) or of the reversal at ``y = (s, sdot)``."""
    return select(wall, wall_condition(y[0], sigma), reversal_condition(y[1], sigma))


def condition_rate(f, sigma, wall):
    """The rate of :func:`condition` along the vector field ``f``."""
    return select(wall, wall_rate(f, sigma), reversal_rate(f, sigma))


def newton_step(g, dg):
    """One Newton step ``-g / dg`` on an event function of value ``g`` and rate ``dg``; 0 if ``dg = 0``."""
    nz = dg != 0.0
    return select(nz, -g / select(nz, dg, 1.0), 0.0)


def beyond_wall(s, sigma):
    """``s`` lies beyond the wall ahead (``s > 0`` for ``sigma > 0``, ``s < -1`` otherwise).  At a
    velocity reversal this is a missed crossing (see the module docstring)."""
    return select(sigma > 0, s > 0.0, s < -1.0)


def moving_along(sdot, sigma):
    """``sdot`` points along the segment's direction ``sigma`` (strictly)."""
    return sigma * sdot > 0.0


def _sqrt(x):
    """Square root of a Python float, a numpy array or a JAX array (each with its own library)."""
    if isinstance(x, (int, float, np.floating)):
        return math.sqrt(x)
    if isinstance(x, np.ndarray):
        return np.sqrt(x)
    return jnp.sqrt(x)


def wall_step(s, sdot, sddot, sigma):
    """The wall ahead on the **quadratic** model of the flight at a located event state ``(s, sdot)``
    with acceleration ``sddot``: ``(reached, h)``, whether ``s + sdot h + sddot h^2 / 2`` reaches the wall
    while moving along ``sigma``, and the step ``h`` to its first root (0 where not reached).

    On the wall condition ``g = g0 + g1 h + g2 h^2 / 2`` (:func:`wall_condition`, ``g1 = sigma sdot``,
    ``g2 = sigma sddot``): reached iff ``g1 > 0`` and ``g1^2 - 2 g0 g2 >= 0`` (or ``g0 >= 0``: the state is
    already beyond the wall); ``h = -2 g0 / (g1 + sqrt(.))`` (the cancellation-free root; it is the Newton
    step ``-g0 / g1`` to first order).  A near miss turns
    back within ``h ~ sdot / |sddot|`` of such a state, where the cubic term is far below rounding.

    Why not one Newton step: the diffrax track locates its events on the solver's dense interpolant
    (good to ~1e-11 in ``s``, its nodes to ~1e-15).  A reversal 2e-11 short of ``s = 0`` (alpha = 0,
    beta = 1, gamma = -1.12, r = 1, issue 31) put the interpolant's ``s`` on the wall 2.5e-6 before the
    turning point; the linear step from the node state there, ``-g0 / g1``, jumped past the turning point
    and reported an impact (with ``sdot < 0``; at other depths with ``sdot > 0`` and a graze that is not
    there).  On the quadratic model the node state shows the turning point inside the gap."""
    g0, g1, g2 = wall_condition(s, sigma), sigma * sdot, sigma * sddot
    disc = g1 * g1 - 2.0 * g0 * g2
    real = disc >= 0.0
    # a state already beyond the wall (g0 >= 0) crossed it before: reached (the root lies behind it)
    reached = select(g1 > 0.0, select(real, True, g0 >= 0.0), False)
    den = select(reached, g1 + _sqrt(select(real, disc, 0.0)), 1.0)
    h = select(real, -2.0 * g0 / den, -g0 / den)  # no real root behind a state beyond: the Newton step
    return reached, select(reached, h, 0.0)


def segment_end(hit, reversal, s_end, sigma):
    """How a segment of direction ``sigma`` ended: :data:`WALL_REACHED` when the wall event fired,
    :data:`MISSED_CROSSING` when the reversal fired at ``s_end`` beyond the wall, :data:`REVERSAL`
    when it fired inside the gap, :data:`OPEN_END` when neither fired."""
    return select(
        hit, WALL_REACHED, select(reversal, select(beyond_wall(s_end, sigma), MISSED_CROSSING, REVERSAL), OPEN_END)
    )


def initial_direction(s0, v0, a0):
    """Direction ``sigma`` (+-1.0) of the first segment of a flight from ``(s0, v0)`` with acceleration
    ``a0``: the sign of ``v0``; at rest on a wall, away from it; at rest inside, the sign of ``a0``
    (``a0 = 0`` counts as upward)."""
    inside = select(a0 >= 0.0, 1.0, -1.0)
    at_rest = select(s0 == 0.0, -1.0, select(s0 == -1.0, 1.0, inside))
    return select(v0 > 0.0, 1.0, select(v0 < 0.0, -1.0, at_rest))


def restart_direction(wall, v0):
    """Direction of the flight that leaves ``wall`` with velocity ``v0`` after an impact (``v0 = -r
    sdot``, Eq. 11) or a release (``v0 = 0``): the sign of ``v0``, or away from the wall."""
    return initial_direction(as_float(wall), v0, 0.0)


def as_float(x):
    """``x`` (a wall index, say) as float64 of its own kind: a Python float, a numpy or a JAX array."""
    if isinstance(x, (int, float, np.integer, np.floating)):
        return float(x)
    if isinstance(x, np.ndarray):
        return x.astype(np.float64)
    return jnp.asarray(x, jnp.float64)


def start_velocity(sdot, sigma):
    """The velocity a segment of direction ``sigma`` is solved from: ``sdot`` if it points along
    ``sigma``, else ``sigma START_SPEED``.  A segment starts at rest after a release (``sdot = 0``) and
    at a landed reversal (``sdot = 0`` to rounding); there its reversal condition would start at zero
    (or above), and a solver that locates an event by a sign change at step ends takes the start
    itself for the root of any upcrossing inside the first step (scipy's ``brentq`` returns an end
    where the condition is 0): a zero-length segment, after which the next one, toward the wall it
    starts on, ends the same way, until :data:`MAX_SEGMENTS`.  Started strictly negative, a return
    inside the first step (a slow departure turning back within 0.03, alpha = 0.5, gamma = -0.5) is a
    proper bracket.  (The diffrax track restarts after every reversal with ``START_SPEED`` in the new
    direction.)"""
    return select(sigma * sdot > 0.0, sdot, sigma * START_SPEED)


def pre_impact_wall(s0: float, sdot0: float, a0: float) -> int | None:
    """The wall of a start ``(s0, sdot0)`` that is already a pre-impact state (on a wall, moving into
    it, or at rest there with the acceleration ``a0`` pointing into it); None for a free start."""
    if s0 == 0.0 and (sdot0 > 0.0 or (sdot0 == 0.0 and a0 > 0.0)):
        return UPPER_WALL
    if s0 == -1.0 and (sdot0 < 0.0 or (sdot0 == 0.0 and a0 < 0.0)):
        return LOWER_WALL
    return None


__all__ = [
    "T_MAX",
    "MAX_SEGMENTS",
    "START_SPEED",
    "UPPER_WALL",
    "LOWER_WALL",
    "DIRECTION",
    "TERMINAL",
    "WALL_REACHED",
    "REVERSAL",
    "MISSED_CROSSING",
    "OPEN_END",
    "select",
    "wall_ahead",
    "wall_condition",
    "reversal_condition",
    "wall_rate",
    "reversal_rate",
    "condition",
    "condition_rate",
    "newton_step",
    "beyond_wall",
    "segment_end",
    "moving_along",
    "wall_step",
    "initial_direction",
    "restart_direction",
    "start_velocity",
    "pre_impact_wall",
]
