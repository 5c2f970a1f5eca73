"""Reference track 2: Eq. (3) integrated with ``diffrax.diffeqsolve`` (Dopri8) and ``diffrax.Event``.

Same hybrid-ODE formulation as :mod:`reference.scipy_track` (right-hand side of Eq. 3 only, impact
law Eqs. 9-11, shared sticking policy :func:`mapimpl.sticking.decide_stick`) and the same event
specification, :mod:`reference.events`, evaluated on JAX arrays:

* each flight is a chain of **monotone segments** (:mod:`reference.events`): one ``diffeqsolve``
  per segment with a ``diffrax.Event`` on the upcrossing (``direction=True``) of
  ``max(wall ahead, velocity reversal)``, whose first upcrossing is the earlier of the two events
  (diffrax would otherwise give priority to the first triggered leaf of a condition pytree, not to
  the earliest root); the root is located by an ``optimistix.Bisection`` on the step's dense
  interpolant, then refined to node accuracy (``_segment``), and :func:`reference.events.segment_end`
  says which event it was.  The guard for diffrax issue 507 (two crossings in one step are missed
  by the sign check at step ends) is the spec's missed-crossing rule: beyond-and-back needs a
  velocity reversal, which ends the segment; if the extremum lies *beyond* the wall, the segment is
  solved again on exactly [start, extremum] with the wall condition only, where ``s`` is monotone and
  ends beyond the wall, so the crossing is a sign change at a step end.  ``dtmax`` (default 0.25)
  bounds the steps so that two reversals in one step stay a non-generic degeneracy;
* the restart loop over segments is a ``jax.lax.while_loop`` (bounded by ``MAX_SEGMENTS`` and the
  longest flight ``T_MAX``), and the loop over impacts a ``jax.lax.scan``; everything is jit-compiled
  and vmappable over initial conditions (:func:`batch_orbit`);
* ``adjoint=diffrax.ForwardMode()`` makes the solve forward-differentiable, so
  :func:`step_jacobian` is ``jax.jacfwd`` of one impact-to-impact step through the event solve
  (implicit differentiation of the root find) plus the reset (third route to the Jacobian of
  Eqs. 12-13).

Float64 throughout (importing :mod:`mapimpl` enables ``jax_enable_x64``).
"""

from __future__ import annotations

import math
from functools import partial
from typing import NamedTuple

import numpy as np

from ..core import jax_config  # noqa: F401
import diffrax
import jax
import jax.numpy as jnp
import optimistix as optx

from ..core.phase import reduce_phase
from ..core.state import MapState, make_state
from ..core.state import run_in_chunks, sequence_from_states
from ..core.checks import TAU0_MAX, check_array, check_int, start_wall
from ..core.params import ParamArrays, Params
from ..core.results import ImpactSequence, StepJacobian, TrackFunctions
from ..core.status import FlightOutcome, Status
from ..mapimpl.sticking import STICK_TIME, check_stick_time, decide_stick, released_turns, stick_time_meta
from . import events as ev
from .common import StepInfo, Trajectory, check_option, forcing_rhs, validate_start
from .events import MAX_SEGMENTS, T_MAX

#: Default tolerances, step bound and per-segment step cap of this track.
RTOL, ATOL, DTMAX = 1e-13, 1e-16, 0.25
MAX_STEPS = 16384
#: Tolerances of the bisection root find locating an event on the step's dense interpolant (a bracket
#: is always available; Newton started at the step end fails when that end is an extremum of s).
ROOT_RTOL, ROOT_ATOL = 1e-14, 1e-13

#: Impacts per XLA call of :func:`orbit` (:func:`core.state.run_in_chunks`, the map track's mechanism):
#: Ctrl-C acts between chunks.  An integrated step costs 0.02-0.3 ms on a CPU core, so a chunk takes
#: 0.005-0.08 s (docs/reference_track.md).
CHUNK = 256


class Options(NamedTuple):
    """Static solver options (hashable, validated by :func:`options`)."""

    rtol: float = RTOL
    atol: float = ATOL
    dtmax: float = DTMAX
    t_max: float = T_MAX
    max_steps: int = MAX_STEPS


def options(
    rtol: float = RTOL, atol: float = ATOL, dtmax: float = DTMAX, t_max: float = T_MAX, max_steps: int = MAX_STEPS
) -> Options:
    """Validated :class:`Options`; ``ValueError`` names a bad option and its range."""
    ms = check_int("max_steps", max_steps, 1, 10_000_000)
    return Options(
        check_option("rtol", rtol, 1e-15, 1e-3),
        check_option("atol", atol, 0.0, 1e-3),
        check_option("dtmax", dtmax, 0.0, 10.0),
        check_option("t_max", t_max, 0.0, 1e6),
        ms,
    )


def _vector_field(t, y, args):
    theta0, alpha, beta, gamma = args[:4]
    tau = theta0 + t
    # Eq. (3): s'' = -alpha sin(tau) + alpha beta cos(tau) + gamma - beta s'
    return jnp.stack([y[1], -alpha * jnp.sin(tau) + alpha * beta * jnp.cos(tau) + gamma - beta * y[1]])


def _wall_cond(t, y, args, **kwargs):
    return ev.wall_condition(y[0], args[4])


def _reversal_cond(t, y, args, **kwargs):
    """The reversal condition, or -1 (never fires) while it is not watched (the missed-crossing re-solve)."""
    sigma, watch = args[4], args[5]
    return jnp.where(watch, ev.reversal_condition(y[1], sigma), -1.0)


def _cond(t, y, args, **kwargs):
    """max(wall ahead, reversal): its first upcrossing is the earlier of the two events."""
    return jnp.maximum(_wall_cond(t, y, args), _reversal_cond(t, y, args))


_TERM = diffrax.ODETerm(_vector_field)
_SOLVER = diffrax.Dopri8()


def _segment(t0, y0, theta0, sigma, alpha, beta, gamma, opts: Options, t_end=None, watch=True):
    """One monotone segment: event solve, then an exact landing on the event time and a Newton polish.

    Diffrax's Dopri8 dense interpolant is only good to ~1e-11 here (its nodes are good to ~1e-15),
    so the event time found on the interpolant is refined: a second solve from the segment start
    ends *exactly* at that time (a node, no interpolation), and one Newton step on the event
    condition, ``dt = -g(y) / g'(y)``, with the vector field gives the event time and state to
    node accuracy.  Differentiating this composition (``jax.jacfwd``) gives the implicit-function
    derivative of the event time, as the map's Jacobian does.

    Which event fired is read off the interpolant (the first upcrossing of the max), so a wall event is
    judged again on the node state (:func:`reference.events.wall_step`, whose quadratic root is also the
    step onto the wall): refuted while ``s`` still moves toward the wall, the segment resumes from the node
    state (``resume``, the last value returned); refuted after the turn, it is a reversal.
    """
    args = (theta0, alpha, beta, gamma, sigma, jnp.asarray(watch))
    t_end = opts.t_max if t_end is None else t_end
    controller = diffrax.PIDController(rtol=opts.rtol, atol=opts.atol, dtmax=opts.dtmax)
    # (mypy reads optimistix's ClassVar `norm` as a field without a default)
    bisection: optx.Bisection = optx.Bisection(rtol=ROOT_RTOL, atol=ROOT_ATOL, flip=False)  # type: ignore[call-arg]
    event = diffrax.Event(_cond, root_finder=bisection, direction=ev.DIRECTION > 0)
    sol = diffrax.diffeqsolve(
        _TERM,
        _SOLVER,
        t0=t0,
        t1=t_end,
        dt0=None,
        y0=y0,
        args=args,
        stepsize_controller=controller,
        event=event,
        saveat=diffrax.SaveAt(t1=True),
        max_steps=opts.max_steps,
        throw=False,
        adjoint=diffrax.ForwardMode(),
    )
    # Under vmap diffrax runs the root find for every lane once any lane has an event; lanes without
    # an event then get a meaningless bisection result and a nonlinear-solver result code.  So the
    # event flag is taken from the event mask, and a lane without event has reached t_end (or failed).
    nonlin = (sol.result == diffrax.RESULTS.nonlinear_max_steps_reached) | (
        sol.result == diffrax.RESULTS.nonlinear_divergence
    )
    evt = sol.event_mask & ((sol.result == diffrax.RESULTS.event_occurred) | nonlin)
    ok = ~sol.event_mask & ((sol.result == diffrax.RESULTS.successful) | nonlin)
    y_i = sol.ys[-1]
    wall_first = _wall_cond(0.0, y_i, args) >= _reversal_cond(0.0, y_i, args)
    wall_hit, reversal = evt & wall_first, evt & ~wall_first
    t_e = jnp.where(evt, sol.ts[-1], t_end)
    # land exactly on t_e (no event, node value); without an event, on t_end when the state there is
    # needed (the bounded re-solve of a missed crossing, a departure's first bounded segment: t_end before
    # the horizon), else a short dummy solve
    bounded = (t_end < opts.t_max) | ~jnp.asarray(watch)
    t_land = jnp.where(evt & (t_e > t0), t_e, jnp.where(bounded, t_end, t0 + opts.dtmax))
    sol2 = diffrax.diffeqsolve(
        _TERM,
        _SOLVER,
        t0=t0,
        t1=t_land,
        dt0=None,
        y0=y0,
        args=args,
        stepsize_controller=controller,
        saveat=diffrax.SaveAt(t1=True),
        max_steps=opts.max_steps,
        throw=False,
        adjoint=diffrax.ForwardMode(),
    )
    y_n = sol2.ys[-1]
    landed = evt & (t_e > t0) & (sol2.result == diffrax.RESULTS.successful)
    f = _vector_field(t_e, y_n, args)
    # the wall event is judged again on the node state, on its quadratic model (ev.wall_step): a near miss
    # shallower than the interpolant's error (~1e-11) can put the interpolant's s on the wall
    reached, h_wall = ev.wall_step(y_n[0], y_n[1], f[1], sigma)
    refuted = wall_hit & landed & ~reached
    # refuted and still moving along sigma: the turning point is ahead; the segment resumes from the
    # node state.  Refuted and turned already: a reversal (beyond the wall: a missed crossing)
    resume = refuted & ev.moving_along(y_n[1], sigma)
    wall_hit = wall_hit & ~refuted
    reversal = reversal | (refuted & ~resume)
    dt_rev = ev.newton_step(_reversal_cond(t_e, y_n, args), ev.reversal_rate(f, sigma))
    dt = jnp.where(landed & ~resume, jnp.where(wall_hit, h_wall, dt_rev), 0.0)
    # second-order step in s (on the wall for a hit), first order in sdot
    y_p = jnp.stack([y_n[0] + (y_n[1] + 0.5 * f[1] * dt) * dt, y_n[1] + f[1] * dt])
    t_out = jnp.where(landed, t_e + dt, t_e)
    y_out = jnp.where(landed, y_p, jnp.where(evt, y_i, y_n))
    return t_out, y_out, wall_hit, reversal, ok, resume


class FlightResult(NamedTuple):
    """``status`` (HIT/NO_IMPACT/STEP_CAP), flight time ``t``, ``wall`` (0/-1), velocity ``v`` just
    before the impact, number of monotone ``segments``."""

    status: jnp.ndarray
    t: jnp.ndarray
    wall: jnp.ndarray
    v: jnp.ndarray
    segments: jnp.ndarray


def departure_bound(theta0, v0, sigma, alpha, beta, gamma, opts: Options):
    """End of the first segment's solve of a flight that leaves with ``v0`` along ``sigma`` against its
    acceleration ``a0``: twice the time to the reversal, ``2 |v0 / a0|``, where that is shorter than
    ``opts.dtmax``; else ``opts.t_max`` (no bound).

    Why: the solver's first step is chosen from the state's scales, not from the reversal ahead.  After a
    slow impact into a weak pressing force (alpha = 0.5, beta = 0.003, gamma = 0, r = 0.3 from the
    pre-impact state (0, 1e-7): the flight leaves at 3e-8 against f = 0.0015, which changes sign 0.003
    later) it was 0.01 long, and inside it ``s`` reversed at 2e-5, came back to the wall at 4e-5 (a bounce
    3e-13 deep), left it and reversed again at 0.006: both step ends moving down, no event; the track
    reported an impact on the other wall at t = 2.56 instead of the bounce (found by ``gear-rattle fuzz``,
    stick-threshold scenario).  Solved on ``[0, 2 |v0 / a0|]`` first, the reversal is a sign change at
    the end of that interval (the force stays nearly constant over it); without one the segment goes on
    from its end (:func:`flight`)."""
    a0 = _vector_field(0.0, jnp.stack([jnp.zeros_like(v0), v0]), (theta0, alpha, beta, gamma))[1]
    opposed = (sigma * v0 > 0.0) & (sigma * a0 < 0.0)
    t_rev = jnp.abs(v0) / jnp.where(opposed, jnp.abs(a0), 1.0)
    return jnp.where(opposed & (2.0 * t_rev < opts.dtmax), 2.0 * t_rev, opts.t_max)


def flight(theta0, s0, v0, sigma, alpha, beta, gamma, opts: Options = Options(), active=True) -> FlightResult:
    """First wall contact of the flight leaving ``(theta0, s0, v0)`` (local time 0), first segment
    direction ``sigma`` (+-1).  Scalar, jit/vmap/jacfwd-able.  ``active=False`` returns at once.  A
    departure against the force is solved on a bounded interval first (:func:`departure_bound`)."""
    dtype = jnp.float64
    t_max = jnp.asarray(opts.t_max, dtype)
    t_first = departure_bound(theta0, jnp.asarray(v0, dtype), sigma, alpha, beta, gamma, opts)
    init = dict(
        t=jnp.asarray(0.0, dtype),
        y=jnp.stack([jnp.asarray(s0, dtype), jnp.asarray(v0, dtype)]),
        sigma=jnp.asarray(sigma, dtype),
        seg=jnp.asarray(0, jnp.int32),
        done=~jnp.asarray(active),
        status=jnp.asarray(FlightOutcome.STEP_CAP, jnp.int32),
        t_end=t_first,
        watch=jnp.asarray(True),
    )

    def cond(c):
        return (~c["done"]) & (c["seg"] < MAX_SEGMENTS)

    def body(c):
        sig, watch = c["sigma"], c["watch"]
        t1, y1, hit, rev, reached, resume = _segment(
            c["t"], c["y"], theta0, sig, alpha, beta, gamma, opts, c["t_end"], watch
        )
        end = ev.segment_end(hit, rev, y1[0], sig)
        # MISSED_CROSSING: the extremum lies beyond the wall ahead, the crossing happened inside one
        # step (diffrax issue 507).  s is monotone on [t, t1]: solve again on exactly that interval,
        # wall only; if that finds no crossing (it reaches t1), the extremum is a reversal.
        retry = watch & (end == ev.MISSED_CROSSING)
        turn = (watch & (end == ev.REVERSAL)) | (~watch & ~hit & reached)
        # the bounded first segment of a departure ended without an event: go on from its end
        bounded_on = watch & ~hit & ~rev & reached & (c["t_end"] < t_max)
        # resume: the wall event was the interpolant's (ev.false_wall_hit); the segment goes on from the
        # landed node state, still moving along sig, with the same watch and end
        done = hit | (~retry & ~turn & ~resume & ~bounded_on)
        status = jnp.where(
            hit, FlightOutcome.HIT, jnp.where(watch & reached, FlightOutcome.NO_IMPACT, FlightOutcome.STEP_CAP)
        ).astype(jnp.int32)
        advance = ~retry
        # restart at an extremum with sdot = -sigma * START_SPEED (it is 0 there to rounding, and its
        # derivative along the extremum is 0): the combined condition then starts strictly negative,
        # so a short return to a wall inside the first step is an upcrossing with a valid bracket
        y1 = jnp.where(turn, y1.at[1].set(-sig * ev.START_SPEED), y1)
        return dict(
            t=jnp.where(advance, t1, c["t"]),
            y=jnp.where(advance, y1, c["y"]),
            sigma=jnp.where(turn, -sig, sig),
            seg=c["seg"] + 1,
            done=done,
            status=jnp.where(done, status, c["status"]),
            t_end=jnp.where(retry, t1, jnp.where(resume, c["t_end"], t_max)),
            watch=jnp.where(resume, watch, ~retry),
        )

    c = jax.lax.while_loop(cond, body, init)
    hit = c["status"] == FlightOutcome.HIT
    wall = ev.wall_ahead(c["sigma"]).astype(jnp.int32)
    return FlightResult(
        c["status"], jnp.where(hit, c["t"], jnp.inf), wall, jnp.where(hit, c["y"][1], jnp.nan), c["seg"]
    )


def _start(wall, stick, sd, r):
    v0 = jnp.where(stick, 0.0, -r * sd)
    return v0, ev.restart_direction(wall, v0)


def step(state: MapState, p: ParamArrays, opts: Options = Options(), stick_time=STICK_TIME):
    """One impact-to-impact step by integration (reset Eq. 11 or the shared sticking policy with the
    threshold ``stick_time``, traced, then a numerically integrated flight).  Scalar state; terminal states
    are returned unchanged."""
    alpha, beta, gamma, r = p
    th, wall, sd = state.theta, state.wall, state.sdot
    dec = decide_stick(th, wall, sd, alpha, beta, gamma, r, stick_time)
    never = dec.stick & ~jnp.isfinite(dec.delay)
    released = dec.stick & ~never
    delay = jnp.where(released, dec.delay, 0.0)
    th0 = jnp.where(released, dec.phase, th)  # the canonical release phase (as the map)
    cyc0 = state.cycles + jnp.where(released, released_turns(th, delay, dec.phase), 0).astype(state.cycles.dtype)
    v0, sigma = _start(wall, dec.stick, sd, r)
    active = (state.status == Status.ACTIVE) & ~never
    fl = flight(th0, wall.astype(jnp.float64), v0, sigma, alpha, beta, gamma, opts, active=active)
    th1, cyc1 = reduce_phase(th0 + jnp.where(fl.status == FlightOutcome.HIT, fl.t, 0.0), cyc0)
    status = jnp.where(
        state.status != Status.ACTIVE,
        state.status,
        jnp.where(never, Status.STUCK_FOREVER, jnp.where(fl.status == FlightOutcome.HIT, Status.ACTIVE, fl.status)),
    ).astype(jnp.int32)
    advance = status == Status.ACTIVE
    new = MapState(
        theta=jnp.where(advance, th1, th),
        cycles=jnp.where(advance, cyc1, state.cycles),
        sdot=jnp.where(advance, fl.v, sd),
        wall=jnp.where(advance, fl.wall, wall),
        status=status,
    )
    tau_n = state.tau
    info = StepInfo(
        stuck=dec.stick & (state.status == Status.ACTIVE),
        stick_tau=jnp.where(dec.stick, tau_n + dec.t_acc, jnp.nan),
        release_tau=jnp.where(dec.stick & ~never, tau_n + delay, jnp.nan),
        segments=fl.segments,
    )
    return new, info


def _scan(state: MapState, p: ParamArrays, n: int, opts: Options, stick_time=STICK_TIME) -> Trajectory:
    def body(s, _):
        s1, info = step(s, p, opts, stick_time)
        return s1, (s1, info)

    _, (states, infos) = jax.lax.scan(body, state, None, length=n)
    return Trajectory(states, infos)


@partial(jax.jit, static_argnums=(2, 3))
def iterate(state: MapState, p: ParamArrays, n: int, opts: Options = Options(), stick_time=STICK_TIME) -> Trajectory:
    """``n`` integrated steps (``lax.scan``) recording every pre-impact state; jit-compiled (``stick_time``
    traced: one compilation serves every threshold)."""
    return _scan(state, p, n, opts, stick_time)


@partial(jax.jit, static_argnums=(2, 3))
def batch_iterate(states: MapState, p: ParamArrays, n: int, opts: Options = Options()) -> Trajectory:
    """:func:`iterate` vmapped over a batch of initial states (parameters shared or batched)."""
    axes = ParamArrays._make(0 if jnp.ndim(x) else None for x in p)  # vmap's in_axes for each parameter
    return jax.vmap(lambda s, q: _scan(s, q, n, opts), in_axes=(0, axes))(states, p)


@partial(jax.jit, static_argnums=(4,))
def _free_start(theta0, s0, v0, p: ParamArrays, opts: Options) -> MapState:
    alpha, beta, gamma, _ = p
    a0 = -alpha * jnp.sin(theta0) + alpha * beta * jnp.cos(theta0) + gamma
    fl = flight(theta0, s0, v0, ev.initial_direction(s0, v0, a0), alpha, beta, gamma, opts)
    hit = fl.status == FlightOutcome.HIT
    th1, cyc1 = reduce_phase(theta0 + jnp.where(hit, fl.t, 0.0), jnp.asarray(0, jnp.int64))
    status = jnp.where(hit, Status.ACTIVE, fl.status).astype(jnp.int32)
    return MapState(th1, cyc1, jnp.where(hit, fl.v, v0), jnp.where(hit, fl.wall, 0).astype(jnp.int32), status)


def start_state(params: Params, tau0: float, sdot0: float, s0: float | None, opts: Options) -> MapState:
    """The orbit's first pre-impact state: ``(tau0, sdot0)`` itself, or for a free state at ``s0`` the
    first impact of its flight (found by this track's own event solve)."""
    if s0 is None:
        return make_state(tau0, sdot0)
    theta, cycles = reduce_phase(jnp.asarray(float(tau0)), jnp.asarray(0, jnp.int64))
    wall = ev.pre_impact_wall(s0, sdot0, forcing_rhs(float(theta), params.alpha, params.beta, params.gamma))
    if wall is not None:  # already a pre-impact state
        return make_state(tau0, sdot0, wall=wall)
    st = _free_start(theta, jnp.asarray(float(s0)), jnp.asarray(float(sdot0)), params.arrays(), opts)
    return st._replace(cycles=st.cycles + cycles)


def orbit(
    params: Params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None = None,
    *,
    rtol: float = RTOL,
    atol: float = ATOL,
    dtmax: float = DTMAX,
    t_max: float = T_MAX,
    max_steps: int = MAX_STEPS,
    progress=None,
    stick_time: float = STICK_TIME,
) -> ImpactSequence:
    """Orbit of Eq. (3) integrated with diffrax: impact 0 plus ``n_impacts`` impacts (track ``"diffrax"``).

    Same signature, conventions and result type as :func:`mapimpl.orbit.map_orbit` (``stick_time``: the
    sticking policy's threshold, ``0 <= stick_time <= 1e-2``); runs in chunks of :data:`CHUNK` impacts
    like it (interruptible with Ctrl-C, the same result as one scan), with the same ``progress``.
    """
    n = validate_start(params, tau0, sdot0, n_impacts, s0)
    stick_time = check_stick_time(stick_time)
    opts = options(rtol, atol, dtmax, t_max, max_steps)
    first = start_state(params, tau0, sdot0, s0, opts)
    # in chunks of CHUNK impacts (Ctrl-C acts between them), bitwise the same as one scan of n steps
    traj = run_in_chunks(
        lambda s, p, length: iterate(s, p, length, opts, stick_time),
        first,
        params,
        n,
        CHUNK,
        progress=progress,
        label="diffrax orbit",
    )
    meta = {
        "tau0": tau0,
        "sdot0": sdot0,
        "s0": s0,
        "n_impacts": n,
        "method": "Dopri8",
        "rtol": opts.rtol,
        "atol": opts.atol,
        "dtmax": opts.dtmax,
        "t_max": opts.t_max,
        **stick_time_meta(stick_time),
    }
    return sequence_from_states(params, first, traj, track="diffrax", meta=meta)


def batch_orbit(params: Params, tau0, sdot0, n_impacts: int, **opt) -> Trajectory:
    """Batch of orbits from pre-impact states (arrays ``tau0``, ``sdot0``), one vmapped kernel.

    Returns the stacked :class:`Trajectory` (leading axis: batch, then impact index 1..n).
    """
    tau0 = check_array("tau0", tau0, -TAU0_MAX, TAU0_MAX)
    sdot0 = check_array("sdot0", sdot0, nonzero=True, max_size=tau0.size)
    n = validate_start(params, 0.0, 1.0, n_impacts, None)
    return batch_iterate(make_state(tau0, sdot0), params.arrays(), n, options(**opt))


def _one_step(x, wall, p: ParamArrays, opts: Options):
    """``(theta_n, sdot_n) -> (theta_n + dt, sdot_{n+1})`` without sticking: reset (Eq. 11) + flight.
    Also returns the wall and the flight status code of the new impact."""
    theta, sd = x[0], x[1]
    alpha, beta, gamma, r = p
    v0 = -r * sd
    fl = flight(theta, wall.astype(jnp.float64), v0, ev.restart_direction(wall, v0), alpha, beta, gamma, opts)
    return jnp.stack([theta + fl.t, fl.v]), (fl.wall, fl.status)


@partial(jax.jit, static_argnums=(3,))
def _step_and_jac(x, wall, p, opts: Options):
    out, (w, status) = _one_step(x, wall, p, opts)
    jac = jax.jacfwd(lambda z: _one_step(z, wall, p, opts)[0])(x)
    return out, w, status, jac


_FLIGHT_FAILURE = {FlightOutcome.NO_IMPACT: Status.NO_IMPACT.label, FlightOutcome.STEP_CAP: Status.STEP_CAP.label}


def step_jacobian(params: Params, tau_n: float, sdot_n: float, wall: int | None = None, **opt) -> StepJacobian:
    """``d(tau_{n+1}, sdot_{n+1}) / d(tau_n, sdot_n)`` by ``jax.jacfwd`` through the event solve and the
    reset (Eq. 11).  A step that sticks (shared policy) forgets its input: ``J = 0`` (the next state
    is the impact after the release, NaN if stuck forever); a flight without impact gives NaN."""
    validate_start(params, tau_n, sdot_n, 1, None, ("tau_n", "sdot_n"))
    opts = options(**opt)
    wall = start_wall(wall, sdot_n)
    theta, cycles = reduce_phase(jnp.asarray(float(tau_n)), jnp.asarray(0, jnp.int64))
    p = params.arrays()
    dec = decide_stick(theta, wall, float(sdot_n), *p)
    if bool(dec.stick):
        if not np.isfinite(float(dec.delay)):
            return StepJacobian(math.nan, math.nan, wall, np.zeros((2, 2)), True, Status.STUCK_FOREVER.label)
        new = jax.tree.map(lambda a: a[0], iterate(make_state(tau_n, sdot_n, wall), p, 1, opts).states)
        status = int(new.status)
        if status != Status.ACTIVE:
            return StepJacobian(math.nan, math.nan, wall, np.zeros((2, 2)), True, Status(status).label)
        return StepJacobian(float(new.tau), float(new.sdot), int(new.wall), np.zeros((2, 2)), True, Status.ACTIVE.label)
    out, w, fstat, jac = _step_and_jac(
        jnp.stack([theta, jnp.asarray(float(sdot_n))]), jnp.asarray(int(wall), jnp.int32), p, opts
    )
    if int(fstat) != FlightOutcome.HIT:
        return StepJacobian(
            math.nan, math.nan, wall, np.full((2, 2), np.nan), False, _FLIGHT_FAILURE[FlightOutcome(int(fstat))]
        )
    tau1 = float(cycles) * 2.0 * np.pi + float(out[0])
    return StepJacobian(tau1, float(out[1]), int(w), np.asarray(jac), False, Status.ACTIVE.label)


#: This track as a :class:`core.results.Track` (``orbit`` and ``step_jacobian`` take the options
#: ``rtol``, ``atol``, ``dtmax``, ``t_max``, ``max_steps``).
TRACK = TrackFunctions("diffrax", orbit, step_jacobian)

__all__ = [
    "Options",
    "options",
    "flight",
    "FlightResult",
    "StepInfo",
    "step",
    "iterate",
    "batch_iterate",
    "orbit",
    "batch_orbit",
    "step_jacobian",
    "TRACK",
    "RTOL",
    "ATOL",
    "DTMAX",
]
