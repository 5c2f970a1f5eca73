"""The impact map, Eqs. (12)-(13): pre-impact state n -> pre-impact state n+1.

Map state just before impact n: phase ``theta_n = tau_n mod 2 pi``, whole turns ``cycles`` (so the
elapsed time is ``2 pi cycles + theta`` without losing the phase's digits), velocity ``sdot_n`` and
the wall being hit (0: ``s = 0``, reached with ``sdot > 0``; -1: ``s = -1``, reached with
``sdot < 0``).  One step

1. resets ``sdot -> -r sdot`` (Eq. 11) or, under the sticking policy of :mod:`mapimpl.sticking`,
   jumps to the chatter accumulation point, sticks and releases with ``sdot = 0``;
2. finds the *first* later wall contact with :func:`mapimpl.finder.first_impact` (Eqs. 7-8);
3. returns the new pre-impact state, which satisfies Eqs. (12)-(13).

It also returns the analytic Jacobian of ``(tau_n, sdot_n) -> (tau_{n+1}, sdot_{n+1})`` obtained by
implicit differentiation of the impact condition ``s(tau_{n+1}) = wall_{n+1}``:

    d tau1/d tau  = (sdot0 + E1 a0) / v1,          d tau1/d sdot  = r E1 / v1,
    d v1/d tau    = a1 d tau1/d tau - E a0,          d v1/d sdot    = a1 d tau1/d sdot - r E,

with ``sdot0 = -r sdot_n``, ``E = exp(-beta dt)``, ``E1 = (1 - E)/beta``, ``a0 = f(tau_n) - beta sdot0``
and ``a1 = f(tau_{n+1}) - beta v1`` the accelerations after and before the impacts.  Its determinant
is ``det J = r^2 exp(-beta dt) sdot_n / sdot_{n+1}`` (proof in ``docs/model.md``).  A step that
sticks forgets its input: ``J = 0``.

All kernels take scalars; :mod:`mapimpl.batch` vmaps them.
"""

from __future__ import annotations

from ..core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from .finder import T_MAX, first_impact
from .flight import phi12
from .forcing import forcing_sc
from ..core.phase import reduce_phase
from ..core.params import ParamArrays
from ..core.state import MapState, StepInfo, Trajectory
from ..core.status import FlightOutcome, Status
from .sticking import STICK_TIME, decide_stick, released_turns


def jacobian_sc(sin0, cos0, v0, dt, sin1, cos1, v1, alpha, beta, gamma, r):
    """The analytic Jacobian ``d(tau_{n+1}, sdot_{n+1}) / d(tau_n, sdot_n)`` of a free step (module
    docstring; implicit differentiation of the impact condition of Eqs. 12-13): the flight leaves the
    wall at a phase with sine/cosine ``sin0, cos0`` and velocity ``v0 = -r sdot_n`` (Eq. 11) and hits
    after ``dt`` at a phase with ``sin1, cos1`` with velocity ``v1``.  The one implementation of the
    formula: :func:`step` and the engine's arrival pass (:mod:`mapimpl.engine.kernel`) call it."""
    e = jnp.exp(-beta * dt)
    e1 = dt * phi12(beta * dt, e)[0]
    a0 = forcing_sc(sin0, cos0, alpha, beta, gamma) - beta * v0
    a1 = forcing_sc(sin1, cos1, alpha, beta, gamma) - beta * v1
    dt1_dtau = (v0 + e1 * a0) / v1
    dt1_dsd = r * e1 / v1
    return jnp.array([[dt1_dtau, dt1_dsd], [a1 * dt1_dtau - e * a0, a1 * dt1_dsd - r * e]])


def jacobian(theta0, v0, dt, theta1, v1, p: ParamArrays):
    """:func:`jacobian_sc` at the phases ``theta0`` (start) and ``theta1`` (impact)."""
    alpha, beta, gamma, r = p
    return jacobian_sc(
        jnp.sin(theta0), jnp.cos(theta0), v0, dt, jnp.sin(theta1), jnp.cos(theta1), v1, alpha, beta, gamma, r
    )


def step(state: MapState, p: ParamArrays, stick_time=STICK_TIME, t_max=T_MAX):
    """One application of the impact map (Eqs. 11-13 with the sticking policy). Scalar state.

    Returns ``(new_state, StepInfo)``.  Terminal states are returned unchanged.
    """
    alpha, beta, gamma, r = p
    th, wall, sd = state.theta, state.wall, state.sdot
    dec = decide_stick(th, wall, sd, alpha, beta, gamma, r, stick_time)
    never = dec.stick & ~jnp.isfinite(dec.delay)
    released = dec.stick & ~never
    delay = jnp.where(released, dec.delay, 0.0)
    # a released tooth leaves the wall at the canonical release phase (a function of the parameters
    # alone), not at th + delay rounded: every orbit that sticks continues on the same orbit
    th0 = jnp.where(released, dec.phase, th)
    cyc0 = state.cycles + jnp.where(released, released_turns(th, delay, dec.phase), 0).astype(state.cycles.dtype)
    v0 = jnp.where(dec.stick, 0.0, -r * sd)
    s0 = wall.astype(jnp.float64)
    hit = first_impact(th0, s0, v0, alpha, beta, gamma, t_max=t_max)
    th1, cyc1 = reduce_phase(th0 + hit.t, cyc0)
    ok = (hit.status == FlightOutcome.HIT) | (hit.status == FlightOutcome.GRAZE)
    status = jnp.where(
        state.status != Status.ACTIVE,
        state.status,
        jnp.where(never, Status.STUCK_FOREVER, jnp.where(ok, Status.ACTIVE, hit.status)),
    ).astype(jnp.int32)
    advance = status == Status.ACTIVE
    new = MapState(
        theta=jnp.where(advance, th1, th),
        cycles=jnp.where(advance, cyc1, state.cycles),
        sdot=jnp.where(advance, hit.v, sd),
        wall=jnp.where(advance, hit.wall, wall),
        status=status,
    )
    tau_n = state.tau
    jac = jacobian(th, v0, hit.t, th1, hit.v, p)
    jac = jnp.where(dec.stick, jnp.zeros((2, 2)), jac)
    nan = jnp.nan
    info = StepInfo(
        stuck=dec.stick & (state.status == Status.ACTIVE),
        stick_tau=jnp.where(dec.stick, tau_n + dec.t_acc, nan),
        release_tau=jnp.where(dec.stick & ~never, tau_n + delay, nan),
        dt=jnp.where(advance, delay + hit.t, nan),
        graze=(hit.status == FlightOutcome.GRAZE) & advance,
        steps=hit.steps,
        jac=jnp.where(advance, jac, nan),
    )
    return new, info


def free_flight_start(tau0, s0, sdot0, p: ParamArrays, t_max=T_MAX) -> MapState:
    """First pre-impact state of the flight leaving a free state ``(tau0, s0, sdot0)``, ``-1 < s0 < 0``
    (or on a wall, moving away from it).  Scalar inputs."""
    alpha, beta, gamma, _ = p
    th0, cyc0 = reduce_phase(jnp.asarray(tau0, jnp.float64), jnp.asarray(0, jnp.int64))
    hit = first_impact(
        th0, jnp.asarray(s0, jnp.float64), jnp.asarray(sdot0, jnp.float64), alpha, beta, gamma, t_max=t_max
    )
    th1, cyc1 = reduce_phase(th0 + hit.t, cyc0)
    ok = (hit.status == FlightOutcome.HIT) | (hit.status == FlightOutcome.GRAZE)
    status = jnp.where(ok, Status.ACTIVE, hit.status).astype(jnp.int32)
    return MapState(
        jnp.where(ok, th1, th0),
        jnp.where(ok, cyc1, cyc0),
        jnp.where(ok, hit.v, sdot0),
        jnp.where(ok, hit.wall, 0).astype(jnp.int32),
        status,
    )


def iterate(state: MapState, p: ParamArrays, n: int, stick_time=STICK_TIME, t_max=T_MAX) -> Trajectory:
    """Apply the map ``n`` times (``lax.scan``), recording every pre-impact state and step info."""

    def body(s, _):
        s1, info = step(s, p, stick_time, t_max)
        return s1, (s1, info)

    _, (states, infos) = jax.lax.scan(body, state, None, length=n)
    return Trajectory(states, infos)


__all__ = [
    "step",
    "iterate",
    "free_flight_start",
]
