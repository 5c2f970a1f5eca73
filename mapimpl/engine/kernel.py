"""The engine's jit-compiled, vmapped kernel: many orbits of the impact map advanced together, results
only.

Why not ``vmap(mapimpl.impact_map.step)``?  A vmapped ``lax.while_loop`` runs until its *slowest*
lane is done, so a batch of map steps costs the maximum, not the mean, number of finder iterations
(safe steps + root iterations) over the batch, and a batch of orbits costs its longest orbit.  This
kernel flattens the search for the next impact into uniform *search micro-steps*, one closed-form
flight evaluation per lane (:func:`search_step`), driven by a per-lane state machine:

* ``A``  safe step at ``t_a`` (:func:`mapimpl.finder.safe_step`);
* ``B``  bracket test at ``t_b`` (:func:`mapimpl.finder.bracket_unique`, :func:`~mapimpl.finder.bracket_test`)
  and, on a bracket, the first root step from that evaluation;
* ``N``  one safeguarded root iteration on the certified bracket (:func:`mapimpl.finder.root_step`);
* ``H``  an impact found, waiting for the next arrival pass;
* ``L``  a freshly loaded initial condition (its pre-impact state is processed as an arrival).

The modes use disjoint quantities, so they share the search fields (:data:`SEARCH_FIELDS`).  Every few
micro-steps an *arrival pass* (:func:`arrival`) processes the lanes in ``H`` and ``L``: the observers
(:mod:`gear_rattle.mapimpl.engine.observers`) see the pre-impact state, the sticking policy of
:mod:`mapimpl.sticking` decides the next flight (Eq. 11 reset, or the release at the canonical
release phase), and that flight's first safe step is taken (its state at ``t = 0`` is known in closed
form).  All lanes advance in lock step and pay for every code path of a pass, so the arrival, as
costly as a search step but needed once per ~5 evaluations, runs every :data:`ARRIVE_EVERY` steps
rather than at every one (:func:`run_blocks`).  When its orbit is done, the lane is refilled from the
queue of initial conditions at the end of the current block, so lanes are busy almost all the time.

Every lane carries its own parameters (alpha, beta, gamma, r) and the constants that depend on them
alone (the release phase of each wall and its sin/cos), prepared once per initial condition by
:func:`prepare_queue`: one kernel serves a fixed parameter set (Figs. 9-11) and a parameter plane
(the atlas) alike; when all orbits of a run share one parameter set the lanes read it from the run
constants instead (:func:`make_consts`, same arithmetic).  The parameters keep the caller's form, a
:class:`~gear_rattle.core.params.ParamArrays`, down to the lane (``lane.par.params``), and the lane
state, the queue, the run constants and the results are named structures (:mod:`.lanes`).

The decisions are the finder's own functions -- :func:`mapimpl.finder.safe_step`,
:func:`~mapimpl.finder.bracket_unique`, :func:`~mapimpl.finder.bracket_test`,
:func:`~mapimpl.finder.root_step`, :func:`~mapimpl.finder.departure_time_sc` -- and the sticking policy
is :func:`mapimpl.sticking.decide_stick_sc`; only the control flow differs from
:func:`mapimpl.impact_map.step` (one evaluation per micro-step instead of nested loops).  The
arithmetic differs by a few ulps per step (tests compare with ``step``): sin/cos come from
:func:`mapimpl.engine.fastmath.sincos` (vectorised fdlibm kernels), sin/cos of the flight start phase
are computed once per flight, ``sin t`` inside ``sigma`` comes from the double angle, one reciprocal
of ``t`` serves ``sinc`` and ``sigma``, and at the root the velocity and sin/cos of the phase are
extrapolated from the last evaluation to second order in the last correction (the map evaluates the
flight there again).

**Determinism.**  Each lane's arithmetic is its own: results do not depend on the number of lanes,
their order, the block, the chunk, the number of devices of one backend, or on when a lane's arrival
is processed.  One exception was found and is designed out: XLA compiles a one-lane block into scalar
code whose floating-point contraction differs from the vectorised code of wider blocks, so lane
blocks are always a multiple of :data:`LANE_QUANTUM` lanes (padded with idle lanes; tested).  The
compiler and its options (:data:`gear_rattle.core.jax_config.ENGINE_XLA_FLAGS`) decide where
multiply-adds are fused, so float64 samples of chaotic orbits depend on them.
"""

from __future__ import annotations

from functools import partial
from typing import Any, NamedTuple

from ...core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from ..finder import (
    H0,
    NEWTON_ITERS,
    MAX_STEPS,
    wall_gaps,
    bracket_test,
    bracket_unique,
    departure_time_sc,
    root_step,
    safe_step,
)
from ..flight import SERIES_X, SIGMA_COEFFS, horner, phi12
from ..forcing import forcing_rate_sc, forcing_sc
from ...core.phase import reduce_phase
from ..impact_map import jacobian_sc
from ...core.status import Status
from ..sticking import decide_stick_sc, release_phase, released_turns
from .fastmath import sincos
from ...core.params import ParamArrays
from .lanes import (
    RESULT_DTYPES,
    Flight,
    Lane,
    LaneParams,
    Point,
    Queue,
    ReleasePhase,
    Results,
    RunConsts,
    Search,
    fill,
    lane_dtypes,
)
from .observers import Impact, Observer
from .options import DEFAULT_RULES, StepRules

# lane modes: searching (A: safe step, B: bracket test, N: root iteration), pending arrival (L: a loaded
# initial condition, H: an impact found), idle
MODE_A, MODE_B, MODE_N, MODE_L, MODE_IDLE, MODE_H = 0, 1, 2, 3, 4, 5
#: Default number of search micro-steps between two arrival passes (see :func:`run_blocks`).
ARRIVE_EVERY = 4
#: Lane blocks are padded to a multiple of this many lanes (see the module docstring).
LANE_QUANTUM = 8


def _barrier(x, pred):
    """Materialise ``x`` once, where that pays: on the CPU without the engine's XLA options
    (:data:`gear_rattle.core.jax_config.ENGINE_XLA_FLAGS`).  There XLA:CPU fuses a value that several
    results need (the flight evaluation: cheap multiply-adds) into each result's loop -- 2.6x the work
    of the search step -- and ``optimization_barrier`` is removed before fusion, but the operands and
    results of a ``lax.cond`` on a run-time predicate (always true here) are real buffers.  With the
    options (multi-output fusion, no duplication) and on an accelerator the barrier only costs copies
    (and, on a GPU, a predicate read per micro-step), so ``x`` is returned as it is."""
    if not _BARRIERS:
        return x
    return jax.lax.cond(pred, lambda y: y, lambda y: jax.tree_util.tree_map(jnp.zeros_like, y), x)


#: Whether :func:`_barrier` materialises (decided when the kernel is first traced; see there).
_BARRIERS = None


def _decide_barriers() -> None:
    global _BARRIERS
    if _BARRIERS is None:
        from ...core.jax_config import xla_tuning_active

        _BARRIERS = jax.default_backend() == "cpu" and not xla_tuning_active()


#: The Taylor series of sigma below |t| = 1 needs 9 terms (the next, t^18/21!, is below 2e-20 of 1/6).
_SIGMA_COEFFS_1 = SIGMA_COEFFS[:9]


def flight_sc(t, sn0, cs0, v0, alpha, beta, gamma):
    """:func:`mapimpl.flight.flight` (Eqs. 7-8, cancellation-free) with ``sin/cos(tau0)`` given.

    Returns ``(ds, v, a, e, sin(tau0 + t), cos(tau0 + t))`` with ``e = exp(-beta t)``.  The same
    formulas with fewer operations for vector units: one reciprocal of ``t`` serves ``sinc(t/2)`` and
    the direct form of ``sigma(t) = (t - sin t)/t^3`` (``sin t`` from the double angle), whose Taylor
    series below ``|t| = 1`` needs 9 terms."""
    sh, ch = sincos(0.5 * t)
    bt = beta * t
    e = jnp.exp(-bt)
    p1, p2 = phi12(bt, e)
    half = 0.5 * t
    small = jnp.abs(half) < 1e-8
    big = jnp.abs(t) >= SERIES_X
    inv_t = 1.0 / jnp.where(small, 1.0, t)
    sc = jnp.where(small, 1.0 - half * half * (1.0 / 6.0), 2.0 * sh * inv_t)
    st, ct = 2.0 * sh * ch, 1.0 - 2.0 * sh * sh
    ts = jnp.where(big, 0.0, t)
    sig = jnp.where(big, (t - st) * (inv_t * inv_t * inv_t), horner(ts * ts, _SIGMA_COEFFS_1))
    q = -0.5 * alpha * sn0 * sc * sc + alpha * cs0 * (beta * p2 - t * sig) + gamma * p2
    ds = t * v0 * p1 + t * t * q
    sin_mid = sn0 * ch + cs0 * sh
    v = v0 * e + t * (-alpha * sin_mid * sc + (alpha * beta * cs0 + gamma) * p1)
    sin_t = sn0 * ct + cs0 * st
    cos_t = cs0 * ct - sn0 * st
    a = -alpha * sin_t + alpha * beta * cos_t + gamma - beta * v
    return ds, v, a, e, sin_t, cos_t


def make_consts(
    cap,
    observers: tuple[Observer, ...],
    stop_at_stick=False,
    rules: StepRules = DEFAULT_RULES,
    params: ParamArrays | None = None,
) -> RunConsts:
    """The run constants (:class:`~.lanes.RunConsts`, JAX arrays): caps, the sticking threshold and the
    finder's caps of ``rules`` (:class:`~.options.StepRules`), the observers' constants (one dict per
    observer) and, when every orbit of the run has the same parameters ``params`` (a
    :class:`~gear_rattle.core.params.ParamArrays` of scalars), those parameters and their release
    constants (``uniform``, a :class:`~.lanes.LaneParams` of scalars: the lanes then read them from here
    instead of from their own fields, which saves memory traffic; same arithmetic, same results)."""
    return RunConsts(
        cap=jnp.asarray(cap, jnp.int32),
        stick_time=jnp.asarray(rules.stick_time, jnp.float64),
        t_max=jnp.asarray(rules.t_max, jnp.float64),
        max_steps=jnp.asarray(rules.max_steps, jnp.int32),
        stop_at_stick=jnp.asarray(bool(stop_at_stick)),
        true=jnp.asarray(True),
        obs=tuple(o.consts() for o in observers),
        uniform=None if params is None else param_consts(params),
    )


# ------------------------------------------------------------------------------------ lane state

_F64, _I32, _BOOL = jnp.float64, jnp.int32, jnp.bool_

#: The search fields (:class:`~.lanes.Search`) by lane mode, in the order ``t, p1, p2, window, v_a,
#: a_a, b_a, top, steps (root_iters)``.  A lane's modes use disjoint quantities, so they share fields:
#: a search micro-step then reads and writes few arrays, which is what it costs on a CPU.
SEARCH_FIELDS = {
    "A": ("t_a", None, None, "window H", None, None, None, None, "safe steps"),
    "B": (
        "t_b",
        "t_a",
        "h_near",
        "window after a failed test",
        "v(t_a)",
        "a(t_a)",
        "b(t_a)",
        "near wall",
        "safe steps",
    ),
    "N": ("x", "lo", "hi", None, None, None, "b(t_a)", "wall", "root iterations"),
    "H": ("t_hit", "sin(phase)", "cos(phase)", None, "v(t_hit)", None, None, "wall", None),
}


def idle_lanes(nlanes: int, observers: tuple[Observer, ...]) -> Lane:
    """A block of ``nlanes`` idle lanes (:class:`~.lanes.Lane`)."""
    lanes = fill(lane_dtypes(), (nlanes,))
    obs = tuple(
        {
            name: jnp.broadcast_to(jnp.asarray(init, dt), (nlanes,) + tuple(shape)).astype(dt)
            for name, (dt, shape, init) in o.fields().items()
        }
        for o in observers
    )
    return lanes._replace(mode=jnp.full((nlanes,), MODE_IDLE, _I32), ic=jnp.full((nlanes,), -1, _I32), obs=obs)


def empty_results(m: int, observers: tuple[Observer, ...]) -> Results:
    """Result arrays (:class:`~.lanes.Results`) for ``m`` initial conditions (status NOT_RUN until written)."""
    res = fill(RESULT_DTYPES, (m,))
    obs = tuple(
        {name: jnp.zeros((m,) + tuple(o.fields()[name][1]), o.fields()[name][0]) for name in o.outputs()}
        for o in observers
    )
    return res._replace(status=jnp.full((m,), int(Status.NOT_RUN), _I32), first_stick=jnp.full((m,), -1, _I32), obs=obs)


@jax.jit
def prepare_queue(theta, sdot, wall, params: ParamArrays, n_ic=None) -> Queue:
    """A queue (:class:`~.lanes.Queue`) of initial conditions -- pre-impact states ``(theta in [0, 2 pi),
    sdot, wall)`` -- with their parameters ``params`` (a :class:`~gear_rattle.core.params.ParamArrays`,
    each field one value or one per orbit): sin/cos of the phase and the release constants of both
    walls (:func:`mapimpl.sticking.release_phase`), computed once per orbit.  ``n_ic``: how many are
    loaded (default all; the rest pads the queue to a length that is compiled once)."""
    f = lambda x: jnp.asarray(x, _F64) + jnp.zeros(jnp.shape(theta), _F64)  # noqa: E731
    pa = ParamArrays(*(f(x) for x in params))
    sn, cs = sincos(theta)
    start = Point(
        theta=f(theta), sdot=f(sdot), wall=jnp.asarray(wall, _I32) + jnp.zeros(jnp.shape(theta), _I32), sin=sn, cos=cs
    )

    def release(w):
        ph, never = release_phase(jnp.full(jnp.shape(theta), w, _I32), pa.alpha, pa.beta, pa.gamma)
        s, c = sincos(ph)
        return ReleasePhase(phase=ph, sin=s, cos=c, never=never)

    n = jnp.asarray(jnp.shape(theta)[0] if n_ic is None else n_ic, _I32)
    return Queue(start=start, par=LaneParams(params=pa, top=release(0), bottom=release(-1)), n_ic=n)


def param_consts(params: ParamArrays) -> LaneParams:
    """The :class:`~.lanes.LaneParams` of one parameter set, as scalars, computed by :func:`prepare_queue`
    on a block of :data:`LANE_QUANTUM` orbits (the same compiled arithmetic as a queue's)."""
    z = jnp.zeros(LANE_QUANTUM, _F64)
    q = prepare_queue(z, z + 1.0, jnp.zeros(LANE_QUANTUM, _I32), ParamArrays(*(jnp.asarray(x, _F64) for x in params)))
    return jax.tree_util.tree_map(lambda x: x[0], q.par)


def _with_run_params(fn, k: RunConsts):
    """``fn`` (one lane's state -> its new state), seeing a run's uniform parameters (``k.uniform``)
    instead of the lane's own parameter fields, which it leaves as they were."""
    up = k.uniform
    if up is None:
        return fn

    def one(s):
        return fn(s._replace(par=up))._replace(par=s.par)

    return one


def _lanewise(fn, k):
    """:func:`_with_run_params` of ``fn``, vmapped over the lanes."""
    return jax.vmap(_with_run_params(fn, k))


def _step_jacobian(s: Lane, t_hit, v1, sn1, cs1):
    """Analytic Jacobian ``d(tau_{n+1}, sdot_{n+1})/d(tau_n, sdot_n)`` of the step that ends at this
    arrival (:func:`mapimpl.impact_map.jacobian_sc`, Eqs. 12-13); zero after a release (a sticking
    step forgets its input)."""
    f, p = s.flight, s.par.params
    J = jacobian_sc(f.sin0, f.cos0, f.v0, t_hit, sn1, cs1, v1, p.alpha, p.beta, p.gamma, p.r)
    return jnp.where(f.released, jnp.zeros((2, 2)), J)


def search_step(s, k):
    """One search micro-step of one lane (scalar state ``s``; vmapped by the engine): one flight
    evaluation (Eqs. 7-8) at ``te`` and the finder's decision for the lane's mode
    (:data:`SEARCH_FIELDS` says what each search field holds in each mode).

    ``A``: a certified safe step from ``t_a`` (:func:`mapimpl.finder.safe_step`): move on, or test the
    near wall at ``t_b`` next; ``B``: the bracket test (:func:`~mapimpl.finder.bracket_unique`,
    :func:`~mapimpl.finder.bracket_test`): the first root step on the certified bracket ``[t_a, t_b]``
    from this evaluation, or back to safe steps from ``t_a + h_near``, or a graze at ``t_a``; ``N``:
    one safeguarded root iteration (:func:`~mapimpl.finder.root_step`).  A search that ends leaves the
    lane in mode ``H`` with the impact -- flight time, wall, velocity and sin/cos of the phase,
    extrapolated from this evaluation to the root to second order in the last correction (below ~1e-6,
    so the neglected terms are below ~1e-18) -- for the next :func:`arrival` pass.  Lanes in other modes
    are left unchanged."""
    _decide_barriers()
    p, f, S = s.par.params, s.flight, s.search
    alpha, beta, gamma = p.alpha, p.beta, p.gamma
    mode = s.mode
    inA, inB, inN = (mode == MODE_A), (mode == MODE_B), (mode == MODE_N)
    te, p1, p2, top = S.t, S.p1, S.p2, S.top
    ds, v, a, e, sin_t, cos_t = _barrier(flight_sc(te, f.sin0, f.cos0, f.v0, alpha, beta, gamma), k.true)
    b = f.bound * e
    du, dl = wall_gaps(f.s0, ds)
    g = jnp.where(top, du, dl)
    dg = jnp.where(top, -v, v)
    # A: one safe step from te = t_a
    A = safe_step(ds, v, a, alpha + b, alpha + beta * b, te, S.window, S.steps, f.t_depart, f.s0, k.t_max, k.max_steps)
    # B: the bracket test at te = t_b (p1 = t_a, p2 = h_near), uniqueness from both ends of [t_a, t_b],
    # with the derivative bounds at t_a (valid for all later times)
    ba = S.b_a
    m2_a, m3_a = alpha + ba, alpha + beta * ba
    bracket, stalled = bracket_test(g, p1, p2, bracket_unique(S.v_a, S.a_a, v, a, m2_a, m3_a, te - p1))
    # B (on a bracket) and N: one root step at te, on [t_a, t_b] or on [p1, p2] = [lo, hi]
    xr, lo_r, hi_r, r_done, kr = root_step(
        te, g, dg, jnp.where(top, -a, a), p1, jnp.where(inB, te, p2), m2_a, m3_a, jnp.where(inB, 0, S.root_iters)
    )
    A, bracket, stalled, xr, lo_r, hi_r, r_done, kr = _barrier(
        (A, bracket, stalled, xr, lo_r, hi_r, r_done, kr), k.true
    )

    # outcome
    graze = inB & stalled
    root = inN | (inB & bracket)
    hit = (root & r_done) | graze
    t_hit = jnp.where(graze, p1, xr)  # a graze is an impact at t_a
    dx = t_hit - te
    jerk = forcing_rate_sc(sin_t, cos_t, alpha, beta) - beta * a
    B_retry = inB & ~bracket & ~stalled  # no root in [t_a, t_b]: go on to t_a + h_near
    B_t_new = p1 + p2
    B_beyond = B_t_new > k.t_max
    escaped = (B_retry & B_beyond) | (inA & A.move & A.beyond)
    failed = (B_retry & ~B_beyond & (S.steps >= k.max_steps)) | (inA & A.move & ~A.beyond & A.capped)
    toB = inA & ~A.move

    new_mode = jnp.where(
        inA,
        jnp.where(A.move, MODE_A, MODE_B),
        jnp.where(root, jnp.where(r_done, MODE_H, MODE_N), jnp.where(inB, jnp.where(stalled, MODE_H, MODE_A), mode)),
    )
    half_dx2 = 0.5 * dx * dx
    search = Search(
        t=jnp.where(
            inA, jnp.where(A.move, A.t_next, A.t_b), jnp.where(root | graze, t_hit, jnp.where(inB, B_t_new, te))
        ),
        p1=jnp.where(hit, sin_t + cos_t * dx - sin_t * half_dx2, jnp.where(toB, te, jnp.where(root, lo_r, p1))),
        p2=jnp.where(hit, cos_t - sin_t * dx - cos_t * half_dx2, jnp.where(toB, A.h_near, jnp.where(root, hi_r, p2))),
        window=jnp.where(inA, A.H_new, S.window),
        v_a=jnp.where(toB, v, jnp.where(root & r_done, v + a * dx + jerk * half_dx2, S.v_a)),
        a_a=jnp.where(toB, a, S.a_a),
        b_a=jnp.where(toB, b, S.b_a),
        top=jnp.where(toB, A.top_near, top),
        steps=jnp.where(inA, A.it, S.steps),
        root_iters=jnp.where(root, kr, S.root_iters),
    )
    return s._replace(
        mode=jnp.where(escaped | failed, MODE_IDLE, new_mode).astype(_I32),
        status=jnp.where(escaped, int(Status.NO_IMPACT), jnp.where(failed, int(Status.STEP_CAP), s.status)).astype(
            _I32
        ),
        search=search,
    )


def _arrived_state(s: Lane, k: RunConsts):
    """The pre-impact state a lane in mode ``L`` (loaded) or ``H`` (impact found) arrives at: ``(inL,
    arrive, t_hit, (theta, cycles, sdot, wall, sin, cos, dt, n))`` behind one barrier (part of :func:`arrival`)."""
    mode, at, S, f = s.mode, s.at, s.search, s.flight
    inL = mode == MODE_L
    arrive = inL | (mode == MODE_H)
    t_hit = S.t
    th_r, turns = reduce_phase(f.theta0 + t_hit, jnp.asarray(0, _I32))
    th1 = jnp.where(inL, at.theta, th_r)
    cyc1 = jnp.where(inL, s.cycles, f.cycles0 + turns)
    v1 = jnp.where(inL, at.sdot, S.v_a)
    wall1 = jnp.where(inL, at.wall, jnp.where(S.top, 0, -1)).astype(_I32)
    sn1 = jnp.where(inL, at.sin, S.p1)
    cs1 = jnp.where(inL, at.cos, S.p2)
    dt1 = jnp.where(inL, 0.0, f.delay + t_hit)
    n1 = jnp.where(inL, s.n, s.n + 1)
    return inL, arrive, t_hit, _barrier((th1, cyc1, v1, wall1, sn1, cs1, dt1, n1), k.true)


def _observe(s: Lane, k: RunConsts, observers: tuple[Observer, ...], ev: Impact, arrive):
    """Every observer sees the arrival ``ev`` (its state kept where the lane did not arrive): ``(the new
    observer states, stop)`` (part of :func:`arrival`)."""
    obs_new, stop = [], jnp.asarray(False)
    for o, so, ko in zip(observers, s.obs, k.obs):
        upd, st = o.update(so, ev, ko)
        obs_new.append({name: jnp.where(arrive, upd[name], so[name]) for name in so})
        stop = stop | st
    return obs_new, arrive & stop


def _stick_policy(s: Lane, k: RunConsts, th1, sn1, cs1, wall1, v1):
    """The sticking policy (:func:`mapimpl.sticking.decide_stick_sc`, with the release constants of the
    lane's parameters) for the step from the arrived state: ``(top1, rel_ph, stick, delay,
    stuck_forever)`` (part of :func:`arrival`)."""
    p, top_rel, bot_rel = s.par.params, s.par.top, s.par.bottom
    top1 = wall1 == 0
    rel_ph = jnp.where(top1, top_rel.phase, bot_rel.phase)
    never = jnp.where(top1, top_rel.never, bot_rel.never)
    stick, _, delay, _ = decide_stick_sc(
        th1, sn1, cs1, wall1, v1, p.alpha, p.beta, p.gamma, p.r, k.stick_time, release=(rel_ph, never)
    )
    return top1, rel_ph, stick, delay, stick & ~jnp.isfinite(delay)


def _orbit_end(k: RunConsts, arrive, stop, stick, stuck_forever, n1):
    """Whether the arrived lane's orbit ends (observers' stop, the impact cap, sticking forever or, with
    ``stop_at_stick``, at all) or goes on, and with a release: ``(capped, stick_stop, orbit_end, go_on,
    go_stick)`` (part of :func:`arrival`)."""
    capped = arrive & (n1 >= k.cap)
    stick_stop = arrive & stick & ~stuck_forever & k.stop_at_stick
    orbit_end = stop | capped | (arrive & stuck_forever) | stick_stop
    go_on = arrive & ~orbit_end
    return capped, stick_stop, orbit_end, go_on, go_on & stick


class _FlightStart(NamedTuple):
    """The start of the next flight computed by :func:`arrival` (behind one barrier): phase and its
    sin/cos, velocity, release delay, whole periods, departure time, bound ``|b|`` and acceleration."""

    theta0: Any
    sin0: Any
    cos0: Any
    v0: Any
    delay: Any
    cycles0: Any
    t_depart: Any
    bound: Any
    a0: Any


def _next_flight(s: Lane, go_stick, top1, rel_ph, delay, th1, sn1, cs1, wall1, v1, cyc1):
    """The start of the next flight: off the wall just hit with ``-r v1`` (Eq. 11), or from the release
    state.  Returns ``(s0_new, _FlightStart)``, the wall position apart (part of :func:`arrival`)."""
    p, top_rel, bot_rel = s.par.params, s.par.top, s.par.bottom
    alpha, beta, gamma, r = p.alpha, p.beta, p.gamma, p.r
    th0_new = jnp.where(go_stick, rel_ph, th1)
    sn0_new = jnp.where(go_stick, jnp.where(top1, top_rel.sin, bot_rel.sin), sn1)
    cs0_new = jnp.where(go_stick, jnp.where(top1, top_rel.cos, bot_rel.cos), cs1)
    v0_new = jnp.where(go_stick, 0.0, -r * v1)
    s0_new = wall1.astype(_F64)
    delay_used = jnp.where(go_stick, delay, 0.0)
    cyc0_new = cyc1 + jnp.where(go_stick, released_turns(th1, delay_used, rel_ph), 0)
    tdep_new = departure_time_sc(sn0_new, cs0_new, s0_new, v0_new, alpha, beta, gamma)
    bc_new = jnp.abs(beta * (v0_new - alpha * cs0_new) - gamma)
    a0_new = forcing_sc(sn0_new, cs0_new, alpha, beta, gamma) - beta * v0_new
    return s0_new, _FlightStart(th0_new, sn0_new, cs0_new, v0_new, delay_used, cyc0_new, tdep_new, bc_new, a0_new)


def _first_safe_step(s: Lane, k: RunConsts, new: _FlightStart, s0_new):
    """The new flight's first safe step (:func:`mapimpl.finder.safe_step`), from its state at ``t = 0``:
    ``(ds, v, a) = (0, v0, a0)`` in closed form, behind a barrier (part of :func:`arrival`)."""
    alpha, beta = s.par.params.alpha, s.par.params.beta
    return _barrier(
        safe_step(
            0.0,
            new.v0,
            new.a0,
            alpha + new.bound,
            alpha + beta * new.bound,
            0.0,
            H0,
            0,
            new.t_depart,
            s0_new,
            k.t_max,
            k.max_steps,
        ),
        k.true,
    )


def _end_status(s: Lane, arrive, stop, stuck_forever, stick_stop, capped):
    """The status of an orbit that ended at this arrival (stopped, stuck forever, stuck, capped), else
    the lane's own (part of :func:`arrival`)."""
    return jnp.where(
        stop,
        int(Status.STOPPED),
        jnp.where(
            arrive & stuck_forever,
            int(Status.STUCK_FOREVER),
            jnp.where(stick_stop, int(Status.STUCK), jnp.where(capped, int(Status.CAPPED), s.status)),
        ),
    )


def _start_search(S: Search, go_on, A, new: _FlightStart) -> Search:
    """The search of the new flight: mode ``A`` from its first safe step ``A``, or ``B`` (``t_a = 0``)
    (part of :func:`arrival`)."""
    return S._replace(
        t=jnp.where(go_on, jnp.where(A.move, A.t_next, A.t_b), S.t),
        p1=jnp.where(go_on, 0.0, S.p1),
        p2=jnp.where(go_on, A.h_near, S.p2),
        window=jnp.where(go_on, A.H_new, S.window),
        v_a=jnp.where(go_on, new.v0, S.v_a),
        top=jnp.where(go_on, A.top_near, S.top),
        a_a=jnp.where(go_on, new.a0, S.a_a),
        b_a=jnp.where(go_on, new.bound, S.b_a),
        steps=jnp.where(go_on, A.it, S.steps),
    )


def _start_flight(f: Flight, go_on, go_stick, s0_new, new: _FlightStart) -> Flight:
    """The lane's flight: the new one (``new``, ``s0_new``, released where ``go_stick``) where the orbit
    goes on, else ``f`` (part of :func:`arrival`)."""
    return Flight(
        theta0=jnp.where(go_on, new.theta0, f.theta0),
        sin0=jnp.where(go_on, new.sin0, f.sin0),
        cos0=jnp.where(go_on, new.cos0, f.cos0),
        v0=jnp.where(go_on, new.v0, f.v0),
        s0=jnp.where(go_on, s0_new, f.s0),
        cycles0=jnp.where(go_on, new.cycles0, f.cycles0),
        delay=jnp.where(go_on, new.delay, f.delay),
        released=jnp.where(go_on, go_stick, f.released),
        t_depart=jnp.where(go_on, new.t_depart, f.t_depart),
        bound=jnp.where(go_on, new.bound, f.bound),
    )


def arrival(s: Lane, k: RunConsts, observers: tuple[Observer, ...]) -> Lane:
    """The arrival pass of one lane (scalar state ``s``; vmapped by the engine): a lane in mode ``H``
    (an impact found by :func:`search_step`) or ``L`` (a freshly loaded initial condition) arrives at a
    pre-impact state.  The observers see it, the sticking policy of :mod:`mapimpl.sticking` decides the
    next flight (Eq. 11 reset, or the release at the canonical release phase), and that flight's first
    safe step is taken from its closed-form state at ``t = 0`` (no evaluation); the lane goes on in
    mode ``A`` or ``B``, or its orbit ends.  Lanes in other modes are left unchanged.  The steps are
    traced in this order (the helpers are plain functions: one XLA program, as if written inline)."""
    _decide_barriers()
    mode = s.mode
    inL, arrive, t_hit, (th1, cyc1, v1, wall1, sn1, cs1, dt1, n1) = _arrived_state(s, k)
    top1, rel_ph, stick, delay, stuck_forever = _stick_policy(s, k, th1, sn1, cs1, wall1, v1)
    # the observers
    ev = Impact(
        n=n1,
        theta=th1,
        sdot=v1,
        wall=wall1,
        cycles=cyc1,
        dt=dt1,
        loaded=inL,
        stick=stick,
        jac=_step_jacobian(s, t_hit, v1, sn1, cs1) if any(o.needs_jacobian for o in observers) else None,
        jac_ok=~inL,
    )
    obs_new, stop = _observe(s, k, observers, ev, arrive)
    capped, stick_stop, orbit_end, go_on, go_stick = _orbit_end(k, arrive, stop, stick, stuck_forever, n1)
    s0_new, new = _next_flight(s, go_stick, top1, rel_ph, delay, th1, sn1, cs1, wall1, v1, cyc1)
    (stop, capped, stick_stop, orbit_end, go_on, go_stick), new = _barrier(
        ((stop, capped, stick_stop, orbit_end, go_on, go_stick), new), k.true
    )
    A = _first_safe_step(s, k, new, s0_new)
    escaped = go_on & A.move & A.beyond
    failed = go_on & A.move & ~A.beyond & A.capped
    status = _end_status(s, arrive, stop, stuck_forever, stick_stop, capped)
    search = _start_search(s.search, go_on, A, new)
    # arrival at a pre-impact state
    at = s.at._replace(
        theta=jnp.where(arrive, th1, s.at.theta),
        sdot=jnp.where(arrive, v1, s.at.sdot),
        wall=jnp.where(arrive, wall1, s.at.wall),
    )
    sticks = arrive & stick
    flight = _start_flight(s.flight, go_on, go_stick, s0_new, new)
    return s._replace(
        mode=jnp.where(
            arrive, jnp.where(orbit_end | escaped | failed, MODE_IDLE, jnp.where(A.move, MODE_A, MODE_B)), mode
        ).astype(_I32),
        status=jnp.where(escaped, int(Status.NO_IMPACT), jnp.where(failed, int(Status.STEP_CAP), status)).astype(_I32),
        search=search,
        at=at,
        cycles=jnp.where(arrive, cyc1, s.cycles),
        n=jnp.where(arrive, n1, s.n),
        obs=tuple(obs_new),
        nstick=s.nstick + sticks.astype(_I32),
        first_stick=jnp.where(sticks & (s.first_stick < 0), n1, s.first_stick),
        flight=flight,
    )


def _load(lanes: Lane, queue: Queue, next_ic, observers) -> tuple[Lane, Any]:
    """Refill idle lanes from the queue (in lane order); returns ``(lanes, next_ic)``."""
    n_ic = queue.n_ic
    idle = lanes.mode == MODE_IDLE
    rank = jnp.cumsum(idle.astype(_I32)) - 1
    idx = next_ic + rank
    take = idle & (idx < n_ic)
    j = jnp.clip(idx, 0, jnp.maximum(n_ic - 1, 0))
    loaded = lambda q, lane: jnp.where(take, q[j], lane)  # noqa: E731
    at = jax.tree_util.tree_map(loaded, queue.start, lanes.at)
    par = jax.tree_util.tree_map(loaded, queue.par, lanes.par)

    def reset(o, fields):
        return {
            name: jnp.where(
                take.reshape((-1,) + (1,) * (o[name].ndim - 1)), jnp.asarray(fields[name][2], fields[name][0]), o[name]
            )
            for name in o
        }

    new = lanes._replace(
        mode=jnp.where(take, MODE_L, lanes.mode),
        ic=jnp.where(take, idx, jnp.where(idle, -1, lanes.ic)),
        at=at,
        par=par,
        n=jnp.where(take, 0, lanes.n),
        cycles=jnp.where(take, 0, lanes.cycles),
        nstick=jnp.where(take, 0, lanes.nstick),
        first_stick=jnp.where(take, -1, lanes.first_stick),
        status=jnp.where(take, int(Status.CAPPED), lanes.status),
        obs=tuple(reset(o, ob.fields()) for o, ob in zip(lanes.obs, observers)),
    )
    # (jnp.sum of int32 is int64 under x64: the count is added in int64, as before strict promotion)
    return new, (next_ic.astype(jnp.int64) + jnp.sum(take.astype(_I32))).astype(_I32)


def _store(res: Results, lanes: Lane) -> tuple[Results, Lane]:
    """Write the results of lanes whose orbit has ended (idle with an IC index) into ``res``."""
    done = (lanes.mode == MODE_IDLE) & (lanes.ic >= 0)
    n_ic = res.n.shape[0]
    j = jnp.where(done, lanes.ic, n_ic)  # out of range -> dropped
    put = lambda r, x: r.at[j].set(x, mode="drop")  # noqa: E731
    at = lanes.at
    out = Results(
        n=put(res.n, lanes.n),
        status=put(res.status, lanes.status),
        nstick=put(res.nstick, lanes.nstick),
        first_stick=put(res.first_stick, lanes.first_stick),
        theta=put(res.theta, at.theta),
        sdot=put(res.sdot, at.sdot),
        wall=put(res.wall, at.wall),
        cycles=put(res.cycles, lanes.cycles),
        obs=tuple({name: put(r_o[name], l_o[name]) for name in r_o} for r_o, l_o in zip(res.obs, lanes.obs)),
    )
    return out, lanes._replace(ic=jnp.where(done, -1, lanes.ic))


@partial(jax.jit, static_argnames=("size",))
def compact(lanes: Lane, size: int) -> Lane:
    """The lanes packed into a block of ``size`` lanes: busy ones first (in lane order), then idle ones.

    For the tail of a run, when the queue is empty and only a few long orbits are left: a micro-step
    costs the same for idle and busy lanes, so the last orbits finish far sooner on fewer lanes.  The
    caller ensures at most ``size`` lanes are busy (a lane whose finished orbit is not yet stored
    counts as busy) and that ``size`` is a multiple of :data:`LANE_QUANTUM`."""
    busy = (lanes.mode != MODE_IDLE) | (lanes.ic >= 0)
    order = jnp.argsort(~busy, stable=True)[:size]
    return jax.tree_util.tree_map(lambda x: x[order], lanes)


@partial(jax.jit, static_argnames=("observers", "block", "max_blocks", "every"))
def run_blocks(
    carry: tuple[Lane, Results, Any], queue: Queue, k: RunConsts, observers, block=32, max_blocks=64, every=ARRIVE_EVERY
):
    """Advance the engine by up to ``max_blocks`` blocks (early exit when every initial condition of
    the queue is done).  A block refills idle lanes from the queue, then runs ``block`` search
    micro-steps (:func:`search_step`) with an arrival pass (:func:`arrival`) before the first and after
    every ``every``-th of them, and stores the orbits that ended.  ``carry = (lanes, res, next_ic)``
    (:class:`~.lanes.Lane`, :class:`~.lanes.Results`, the next initial condition to load); ``queue``:
    a :class:`~.lanes.Queue` from :func:`prepare_queue`, possibly padded beyond its ``n_ic`` initial
    conditions (a run-time value, so one compilation serves every queue of the same padded length).

    Why an arrival pass every few steps, not at every one: the lanes advance in lock step, so every
    lane pays for every code path of a pass.  The search (one flight evaluation and a few decisions) is
    the common path; the arrival -- observers, sticking policy, the next flight's set-up and first safe
    step, about as costly as a search step (on the CPU: ~32 and ~40 ns per lane, docs/engine.md) --
    happens once per ~5 evaluations.  A lane whose search has ended waits (mode ``H``) for the next pass,
    about ``(every - 1) / 2`` micro-steps on average; each lane's arithmetic does not depend on when its
    arrival is processed."""
    n_ic = queue.n_ic
    search_v = _lanewise(lambda s: search_step(s, k), k)
    arrive_v = _lanewise(lambda s: arrival(s, k, observers), k)
    every = max(1, min(int(every), int(block)))

    def cond(c):
        lanes, res, next_ic, nb = c
        busy = jnp.any(lanes.mode != MODE_IDLE) | (next_ic < n_ic)
        return busy & (nb < max_blocks)

    def sub_block(_, lanes):
        lanes = jax.lax.fori_loop(0, every, lambda _, L: search_v(L), lanes)
        return arrive_v(lanes)

    def body(c):
        lanes, res, next_ic, nb = c
        lanes, next_ic = _load(lanes, queue, next_ic, observers)
        lanes = jax.lax.fori_loop(0, block // every, sub_block, arrive_v(lanes))
        res, lanes = _store(res, lanes)
        return lanes, res, next_ic, nb + 1

    lanes, res, next_ic = carry
    lanes, res, next_ic, nb = jax.lax.while_loop(cond, body, (lanes, res, next_ic, jnp.asarray(0, _I32)))
    return (lanes, res, next_ic), nb


@partial(jax.jit, static_argnames=("n_impacts", "observers"))
def trace(queue1: Queue, k: RunConsts, n_impacts: int, observers=()):
    """Pre-impact states ``(theta, sdot, wall)`` after each of ``n_impacts`` map iterations of one orbit
    (``queue1``: a one-orbit queue from :func:`prepare_queue`), computed by the engine's micro-steps
    on a single unbatched lane (for tests against :func:`mapimpl.impact_map.step`).  Entries after the
    orbit ended are NaN."""
    first = lambda tree: jax.tree_util.tree_map(lambda x: x[0], tree)  # noqa: E731
    lane = first(idle_lanes(1, observers))._replace(
        at=first(queue1.start),
        par=first(queue1.par),
        mode=jnp.int32(MODE_L),
        ic=jnp.int32(0),
        first_stick=jnp.int32(-1),
        status=jnp.int32(int(Status.CAPPED)),
    )
    hist = jnp.full((n_impacts + 1, 3), jnp.nan)
    # every flight ends within its micro-step bound (a guard against an engine bug, never reached)
    bound = (n_impacts + 1) * (flight_micro_steps(k.max_steps, every=1) + 1)

    def cond(c):
        l, h, it = c
        return (l.mode != MODE_IDLE) & (l.n < n_impacts) & (it < bound)

    one_micro_step = _with_run_params(lambda s: arrival(search_step(s, k), k, observers), k)

    def body(c):
        l, h, it = c
        l2 = one_micro_step(l)
        arrived = (l2.n != l.n) | (it == 0)
        row = jnp.stack([l2.at.theta, l2.at.sdot, l2.at.wall.astype(_F64)])
        h = jnp.where(arrived, h.at[l2.n].set(row), h)
        return l2, h, it + 1

    lane, hist, _ = jax.lax.while_loop(cond, body, (lane, hist, jnp.asarray(0, _I32)))
    return hist


def flight_micro_steps(max_steps: int = MAX_STEPS, every: int = ARRIVE_EVERY) -> int:
    """An upper bound on the search micro-steps of one flight, from the finder's caps: at most
    ``max_steps`` safe steps (mode ``A``), each followed by at most one bracket test (``B``), then at
    most ``mapimpl.finder.NEWTON_ITERS`` root iterations (``N``) and a wait of at most ``every``
    micro-steps for the arrival pass (``H``).  (Python integers, or a traced ``max_steps``.)"""
    return 2 * max_steps + NEWTON_ITERS + every + 2


def padded_lanes(lanes: int) -> int:
    """``lanes`` rounded up to a multiple of :data:`LANE_QUANTUM` (at least one quantum)."""
    q = LANE_QUANTUM
    return max(q, -(-int(lanes) // q) * q)


__all__ = [
    "MODE_A",
    "MODE_B",
    "MODE_N",
    "MODE_L",
    "MODE_IDLE",
    "MODE_H",
    "ARRIVE_EVERY",
    "LANE_QUANTUM",
    "SEARCH_FIELDS",
    "flight_sc",
    "make_consts",
    "param_consts",
    "idle_lanes",
    "empty_results",
    "prepare_queue",
    "search_step",
    "arrival",
    "compact",
    "run_blocks",
    "trace",
    "flight_micro_steps",
    "padded_lanes",
]
