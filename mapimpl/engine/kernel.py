"""The engine's jit-compiled, vmapped kernel: many orbits of the impact map advanced together, results
only.

Why not ``vmap(mapimpl.impact_map.step)``?  A vmapped ``lax.while_loop`` runs until its *slowest*
lane is done, so a batch of map steps costs the maximum, not the mean, number of finder iterations
(safe steps + Newton) over the batch, and a batch of orbits costs its longest orbit.  This kernel
flattens everything into one uniform *micro-step*, one closed-form flight evaluation per lane,
driven by a per-lane state machine:

``A``  safe step at ``t_a`` (:func:`mapimpl.finder.safe_step`);
``B``  bracket test at ``t_b`` (:func:`mapimpl.finder.bracket_test`, when the step did not move on);
``N``  one safeguarded Newton iteration on the certified bracket (:func:`mapimpl.finder.newton_step`);
``L``  a freshly loaded initial condition (its pre-impact state is processed as an arrival).

When a lane's search ends, the impact is applied in the same micro-step: the arrival is shown to
the observers (:mod:`gear_rattle.mapimpl.engine.observers`), the sticking policy of
:mod:`mapimpl.sticking` decides the next flight (Eq. 11 reset, or the release at the canonical
release phase), and that flight's first safe step is taken (its state at ``t = 0`` is known in closed
form).  When its orbit is done, the lane is refilled from the queue of initial conditions at the end
of the current block of micro-steps, so lanes are busy almost all the time.

Every lane carries its own parameters (alpha, beta, gamma, r) and the constants that depend on them
alone (the release phase of each wall and its sin/cos), prepared once per initial condition by
:func:`prepare_queue`: one kernel serves a fixed parameter set (Figs. 9-11) and a parameter plane
(the atlas) alike.

The decisions are the finder's own functions -- :func:`mapimpl.finder.safe_step`,
:func:`~mapimpl.finder.bracket_test`, :func:`~mapimpl.finder.newton_step`,
:func:`~mapimpl.finder.departure_time_sc` -- and the sticking policy is
:func:`mapimpl.sticking.decide_stick_sc`; only the control flow differs from
:func:`mapimpl.impact_map.step` (one evaluation per micro-step instead of nested loops).  The
arithmetic differs by a few ulps per step (tests compare with ``step``): sin/cos come from
:func:`mapimpl.engine.fastmath.sincos` (vectorised fdlibm kernels), sin/cos of the flight start phase
are computed once per flight, ``sin t`` inside ``sigma`` comes from the double angle, and at the
root the velocity and sin/cos of the phase are extrapolated from the last evaluation to first order
in the final Newton correction (below ~1e-9, so the neglected term is below 1e-18).

**Determinism.**  Each lane's arithmetic is its own: results do not depend on the number of lanes,
their order, the block, the chunk or the number of devices of one backend.  One exception was found
and is designed out: XLA compiles a one-lane block into scalar code whose floating-point contraction
differs from the vectorised code of wider blocks, so lane blocks are always a multiple of
:data:`LANE_QUANTUM` lanes (padded with idle lanes; tested).
"""

from __future__ import annotations

from functools import partial

from .. import _jax  # noqa: F401
import jax
import jax.numpy as jnp

from ..finder import _H0, MAX_STEPS, T_MAX, _gaps, bracket_test, departure_time_sc, newton_step, safe_step
from ..flight import _SERIES_X, _SIGMA_COEFFS, _horner, forcing_sc, phi1, phi2, reduce_phase
from ..status import Orbit
from ..sticking import STICK_TIME, decide_stick_sc, release_phase, released_turns
from .fastmath import sincos
from .observers import Impact, Observer

# lane modes
MODE_A, MODE_B, MODE_N, MODE_L, MODE_IDLE = 0, 1, 2, 3, 4
#: Lane blocks are padded to a multiple of this many lanes (see the module docstring).
LANE_QUANTUM = 8


def _barrier(x, pred):
    """Materialise ``x`` once.  Without it XLA:CPU fuses the shared flight evaluation (cheap
    multiply-adds, hence duplicated) into every one of the ~30 output fusions of the micro-step:
    30x the work.  ``optimization_barrier`` is removed before fusion on CPU, but the operands and
    results of a ``lax.cond`` on a run-time predicate (always true here) are real buffers."""
    return jax.lax.cond(pred, lambda y: y, lambda y: jax.tree_util.tree_map(jnp.zeros_like, y), x)


def _sigma_from_sin(t, sin_t):
    big = jnp.abs(t) >= _SERIES_X
    tb = jnp.where(big, t, 1.0)
    direct = (tb - jnp.where(big, sin_t, 0.0)) / (tb * tb * tb)
    ts = jnp.where(big, 0.0, t)
    return jnp.where(big, direct, _horner(ts * ts, _SIGMA_COEFFS))


def flight_sc(t, sn0, cs0, v0, alpha, beta, gamma):
    """:func:`mapimpl.flight.flight` (Eqs. 7-8, cancellation-free) with ``sin/cos(tau0)`` given.

    Returns ``(ds, v, a, e, sin(tau0 + t), cos(tau0 + t))`` with ``e = exp(-beta t)``."""
    sh, ch = sincos(0.5 * t)
    bt = beta * t
    e = jnp.exp(-bt)
    p1 = phi1(bt)
    p2 = phi2(bt)
    half = 0.5 * t
    small = jnp.abs(half) < 1e-8
    sc = jnp.where(small, 1.0 - half * half / 6.0, sh / jnp.where(small, 1.0, half))
    st, ct = 2.0 * sh * ch, 1.0 - 2.0 * sh * sh
    q = -0.5 * alpha * sn0 * sc * sc + alpha * cs0 * (beta * p2 - t * _sigma_from_sin(t, st)) + gamma * p2
    ds = t * v0 * p1 + t * t * q
    sin_mid = sn0 * ch + cs0 * sh
    v = v0 * e + t * (-alpha * sin_mid * sc + (alpha * beta * cs0 + gamma) * p1)
    sin_t = sn0 * ct + cs0 * st
    cos_t = cs0 * ct - sn0 * st
    a = -alpha * sin_t + alpha * beta * cos_t + gamma - beta * v
    return ds, v, a, e, sin_t, cos_t


def make_consts(cap, observers: tuple[Observer, ...], stop_at_stick=False, stick_time=STICK_TIME, t_max=T_MAX,
                max_steps=MAX_STEPS) -> dict:
    """Pytree of run constants (JAX arrays): caps, the sticking threshold and the observers' constants
    (under ``"obs"``, one dict per observer)."""
    return dict(
        cap=jnp.asarray(cap, jnp.int32), stick_time=jnp.asarray(stick_time, jnp.float64),
        t_max=jnp.asarray(t_max, jnp.float64), max_steps=jnp.asarray(max_steps, jnp.int32),
        stop_at_stick=jnp.asarray(bool(stop_at_stick)), true=jnp.asarray(True),
        obs=tuple(o.consts() for o in observers),
    )


# ------------------------------------------------------------------------------------ lane state

_F64, _I32, _BOOL = jnp.float64, jnp.int32, jnp.bool_

#: Per-lane fields of the engine (observer fields are added under ``"obs"``).
LANE_FIELDS = dict(
    # control and orbit bookkeeping
    mode=_I32, ic=_I32, n=_I32, nst=_I32, nstk=_I32, ostat=_I32,
    # parameters and the constants that depend on them alone (release phase of each wall, its sin/cos)
    al=_F64, be=_F64, ga=_F64, rr=_F64, rp0=_F64, rs0=_F64, rc0=_F64, nv0=_BOOL, rp1=_F64, rs1=_F64, rc1=_F64,
    nv1=_BOOL,
    # the current pre-impact state
    th=_F64, sd=_F64, wall=_I32, cyc=_I32, sn=_F64, cs=_F64,
    # the current flight: start phase and its sin/cos, velocity, wall, turns, sticking delay, whether it
    # starts from a release, departure certificate, decaying bound term, acceleration at t = 0
    th0=_F64, sn0=_F64, cs0=_F64, v0=_F64, s0=_F64, cyc0=_I32, tdl=_F64, rel=_BOOL, tdep=_F64, bc=_F64,
    # the search
    ta=_F64, H=_F64, it=_I32, tb=_F64, topn=_BOOL, uniq=_BOOL, hnear=_F64, hnew=_F64, va=_F64,
    x=_F64, lo=_F64, hi=_F64, top=_BOOL, k=_I32,
)

#: Fields copied from the queue when a lane is loaded (see :func:`prepare_queue`).
QUEUE_FIELDS = ("th", "sd", "wall", "sn", "cs", "al", "be", "ga", "rr",
                "rp0", "rs0", "rc0", "nv0", "rp1", "rs1", "rc1", "nv1")

#: Per-initial-condition results of the engine itself (observer outputs are added under ``"obs"``).
RESULT_FIELDS = dict(n=_I32, status=_I32, nst=_I32, nstk=_I32, th=_F64, sd=_F64, wall=_I32, cyc=_I32)


def idle_lanes(nlanes: int, observers: tuple[Observer, ...]) -> dict:
    """A block of ``nlanes`` idle lanes."""
    out = {name: jnp.zeros((nlanes,), dt) for name, dt in LANE_FIELDS.items()}
    out["mode"] = jnp.full((nlanes,), MODE_IDLE, _I32)
    out["ic"] = jnp.full((nlanes,), -1, _I32)
    out["obs"] = tuple({name: jnp.broadcast_to(jnp.asarray(init, dt), (nlanes,) + tuple(shape)).astype(dt)
                        for name, (dt, shape, init) in o.fields().items()} for o in observers)
    return out


def empty_results(m: int, observers: tuple[Observer, ...]) -> dict:
    """Result arrays for ``m`` initial conditions (status NOT_RUN until written)."""
    res = {name: jnp.zeros((m,), dt) for name, dt in RESULT_FIELDS.items()}
    res["status"] = jnp.full((m,), int(Orbit.NOT_RUN), _I32)
    res["nstk"] = jnp.full((m,), -1, _I32)
    res["obs"] = tuple({name: jnp.zeros((m,) + tuple(o.fields()[name][1]), o.fields()[name][0])
                        for name in o.outputs()} for o in observers)
    return res


@jax.jit
def prepare_queue(theta, sdot, wall, alpha, beta, gamma, r):
    """Queue arrays of initial conditions (pre-impact states ``(theta in [0, 2 pi), sdot, wall)``) with
    per-orbit parameters: sin/cos of the phase and the release constants of both walls
    (:func:`mapimpl.sticking.release_phase`), computed once per orbit."""
    f = lambda x: jnp.asarray(x, _F64) + jnp.zeros(jnp.shape(theta), _F64)  # noqa: E731
    al, be, ga, rr = f(alpha), f(beta), f(gamma), f(r)
    sn, cs = sincos(theta)
    q = dict(th=f(theta), sd=f(sdot), wall=jnp.asarray(wall, _I32) + jnp.zeros(jnp.shape(theta), _I32), sn=sn, cs=cs,
             al=al, be=be, ga=ga, rr=rr)
    for w, tag in ((0, "0"), (-1, "1")):
        ph, never = release_phase(jnp.full(jnp.shape(theta), w, _I32), al, be, ga)
        s, c = sincos(ph)
        q.update({"rp" + tag: ph, "rs" + tag: s, "rc" + tag: c, "nv" + tag: never})
    return q


def _step_jacobian(s, t_hit, v1, sn1, cs1):
    """Analytic Jacobian ``d(tau_{n+1}, sdot_{n+1})/d(tau_n, sdot_n)`` of the step that ends at this
    arrival (:func:`mapimpl.impact_map._jacobian`, implicit differentiation of the impact condition,
    Eqs. 12-13); zero after a release (a sticking step forgets its input)."""
    al, be, ga, rr = s["al"], s["be"], s["ga"], s["rr"]
    e = jnp.exp(-be * t_hit)
    e1 = t_hit * phi1(be * t_hit)
    a0 = forcing_sc(s["sn0"], s["cs0"], al, be, ga) - be * s["v0"]
    a1 = forcing_sc(sn1, cs1, al, be, ga) - be * v1
    dt1_dtau = (s["v0"] + e1 * a0) / v1
    dt1_dsd = rr * e1 / v1
    J = jnp.array([[dt1_dtau, dt1_dsd], [a1 * dt1_dtau - e * a0, a1 * dt1_dsd - rr * e]])
    return jnp.where(s["rel"], jnp.zeros((2, 2)), J)


def micro_step(s, k, observers: tuple[Observer, ...]):
    """One micro-step of one lane (scalar state ``s``; vmapped by the engine)."""
    alpha, beta, gamma, r = s["al"], s["be"], s["ga"], s["rr"]
    mode = s["mode"]
    inA, inB, inN, inL = (mode == MODE_A), (mode == MODE_B), (mode == MODE_N), (mode == MODE_L)
    # ---------------- one flight evaluation ----------------
    t_eval = jnp.where(inA, s["ta"], jnp.where(inB, s["tb"], jnp.where(inN, s["x"], 0.0)))
    ds, v, a, e, sin_t, cos_t = _barrier(flight_sc(t_eval, s["sn0"], s["cs0"], s["v0"], alpha, beta, gamma),
                                         k["true"])
    b = s["bc"] * e
    m2 = alpha + b
    du, dl = _gaps(s["s0"], ds)
    ta, H = s["ta"], s["H"]

    # ---------------- B: bracket test at t_b ----------------
    g_b = jnp.where(s["topn"], du, dl)
    dg_b = jnp.where(s["topn"], -v, v)
    bracket, stalled, x_b = bracket_test(g_b, dg_b, ta, s["tb"], s["hnear"], s["uniq"])
    B_t_new = ta + s["hnear"]
    B_beyond = B_t_new > k["t_max"]
    B_capped = s["it"] >= k["max_steps"]

    # ---------------- N: safeguarded Newton iteration ----------------
    x = s["x"]
    g = jnp.where(s["top"], du, dl)
    dg = jnp.where(s["top"], -v, v)
    xn, lo_n, hi_n, N_done, kN = newton_step(x, g, dg, s["lo"], s["hi"], m2, s["k"])
    lo_n, hi_n, xn, N_done = _barrier((lo_n, hi_n, xn, N_done), k["true"])

    # ---------------- search outcome ----------------
    got_hit = (inN & N_done) | (inB & stalled & ~bracket)
    t_hit = jnp.where(inN, xn, ta)
    # first-order extrapolation from this evaluation to the root: velocity and sin/cos of the phase
    dx = t_hit - t_eval
    v_hit = jnp.where(inN, v + a * dx, s["va"])
    top_hit = jnp.where(inN, s["top"], s["topn"])
    escaped = inB & ~bracket & ~stalled & B_beyond
    failed = inB & ~bracket & ~stalled & ~B_beyond & B_capped

    # ---------------- arrival at a pre-impact state (an impact found now, or a loaded state) ----------
    arrive = got_hit | inL
    th_r, turns = reduce_phase(s["th0"] + t_hit, jnp.asarray(0, _I32))
    th1 = jnp.where(inL, s["th"], th_r)
    cyc1 = jnp.where(inL, s["cyc"], s["cyc0"] + turns)
    v1 = jnp.where(inL, s["sd"], v_hit)
    wall1 = jnp.where(inL, s["wall"], jnp.where(top_hit, 0, -1)).astype(_I32)
    sn1 = jnp.where(inL, s["sn"], sin_t + cos_t * dx)
    cs1 = jnp.where(inL, s["cs"], cos_t - sin_t * dx)
    dt1 = jnp.where(inL, 0.0, s["tdl"] + t_hit)
    n1 = jnp.where(inL, s["n"], s["n"] + 1)
    (th1, cyc1, v1, sn1, cs1, dt1, n1, arrive, got_hit, escaped, failed, bracket, stalled) = _barrier(
        (th1, cyc1, v1, sn1, cs1, dt1, n1, arrive, got_hit, escaped, failed, bracket, stalled), k["true"])
    # the sticking policy for the step from this impact (release constants of the lane's parameters)
    top1 = wall1 == 0
    rel_ph = jnp.where(top1, s["rp0"], s["rp1"])
    never = jnp.where(top1, s["nv0"], s["nv1"])
    stick, _, delay, _ = decide_stick_sc(th1, sn1, cs1, wall1, v1, alpha, beta, gamma, r, k["stick_time"],
                                         release=(rel_ph, never))
    stuck_forever = stick & ~jnp.isfinite(delay)
    # the observers
    jac = None
    if any(o.needs_jacobian for o in observers):
        jac = _step_jacobian(s, t_hit, v1, sn1, cs1)
    ev = Impact(n=n1, theta=th1, sdot=v1, wall=wall1, cycles=cyc1, dt=dt1, loaded=inL, stick=stick, jac=jac,
                jac_ok=~inL)
    obs_new, stop = [], jnp.asarray(False)
    for o, so, ko in zip(observers, s["obs"], k["obs"]):
        upd, st = o.update(so, ev, ko)
        obs_new.append({name: jnp.where(arrive, upd[name], so[name]) for name in so})
        stop = stop | st
    stop = arrive & stop
    capped = arrive & (n1 >= k["cap"])
    stick_stop = arrive & stick & ~stuck_forever & k["stop_at_stick"]
    orbit_end = stop | capped | (arrive & stuck_forever) | stick_stop
    go_on = arrive & ~orbit_end
    go_stick = go_on & stick
    # the next flight: off the wall just hit with -r v1 (Eq. 11), or from the release state
    th0_new = jnp.where(go_stick, rel_ph, th1)
    sn0_new = jnp.where(go_stick, jnp.where(top1, s["rs0"], s["rs1"]), sn1)
    cs0_new = jnp.where(go_stick, jnp.where(top1, s["rc0"], s["rc1"]), cs1)
    v0_new = jnp.where(go_stick, 0.0, -r * v1)
    s0_new = wall1.astype(_F64)
    delay_used = jnp.where(go_stick, delay, 0.0)
    cyc0_new = cyc1 + jnp.where(go_stick, released_turns(th1, delay_used, rel_ph), 0)
    tdep_new = departure_time_sc(sn0_new, cs0_new, s0_new, v0_new, alpha, beta, gamma)
    bc_new = jnp.abs(beta * (v0_new - alpha * cs0_new) - gamma)
    a0_new = forcing_sc(sn0_new, cs0_new, alpha, beta, gamma) - beta * v0_new
    (stop, capped, stick_stop, orbit_end, go_on, go_stick, th0_new, sn0_new, cs0_new, v0_new, delay_used, cyc0_new,
     tdep_new, bc_new, a0_new) = _barrier((stop, capped, stick_stop, orbit_end, go_on, go_stick, th0_new, sn0_new,
                                           cs0_new, v0_new, delay_used, cyc0_new, tdep_new, bc_new, a0_new), k["true"])

    # ---------------- A: one safe step ----------------
    # from this micro-step's evaluation (mode A), or from t = 0 of the flight that starts now: its state
    # there is (ds, v, a) = (0, v0, a0) in closed form, so a new flight needs no evaluation for its first
    # step.  (A lane never does both: lanes in mode A do not arrive at an impact.)
    doA = inA | go_on
    ta_in = jnp.where(inA, ta, 0.0)
    H_in = jnp.where(inA, H, _H0)
    v_in = jnp.where(inA, v, v0_new)
    b_in = jnp.where(inA, b, bc_new)
    A = _barrier(safe_step(jnp.where(inA, ds, 0.0), v_in, jnp.where(inA, a, a0_new), alpha + b_in, alpha + beta * b_in,
                           ta_in, H_in, jnp.where(inA, s["it"], 0), jnp.where(inA, s["tdep"], tdep_new),
                           jnp.where(inA, s["s0"], s0_new), k["t_max"], k["max_steps"]), k["true"])
    escaped = escaped | (doA & A.move & A.beyond)
    failed = failed | (doA & A.move & ~A.beyond & A.capped)

    # ---------------- next state ----------------
    ns = dict(s)
    new_mode = mode
    new_mode = jnp.where(inB & bracket, MODE_N, new_mode)
    new_mode = jnp.where(inB & ~bracket & ~stalled, MODE_A, new_mode)
    new_mode = jnp.where(doA, jnp.where(A.move, MODE_A, MODE_B), new_mode)
    lane_end = orbit_end | escaped | failed
    ns["mode"] = jnp.where(lane_end, MODE_IDLE, new_mode).astype(_I32)
    # A (after a safe step) and B -> A (after a failed bracket test)
    ns["ta"] = jnp.where(doA, jnp.where(A.move, A.t_next, ta_in), jnp.where(inB & ~bracket & ~stalled, B_t_new, ta))
    ns["H"] = jnp.where(doA, jnp.where(A.move, A.H_new, H_in), jnp.where(inB, s["hnew"], H))
    ns["it"] = jnp.where(doA, A.it, s["it"])
    ns["tb"] = jnp.where(doA, A.t_b, s["tb"])
    ns["topn"] = jnp.where(doA, A.top_near, s["topn"])
    ns["uniq"] = jnp.where(doA, A.unique, s["uniq"])
    ns["hnear"] = jnp.where(doA, A.h_near, s["hnear"])
    ns["hnew"] = jnp.where(doA, A.H_new, s["hnew"])
    ns["va"] = jnp.where(doA, v_in, s["va"])
    # B -> N initialisation (lo = t_a, hi = t_b, x = the tangent's zero); N update
    ns["lo"] = jnp.where(inB, ta, jnp.where(inN, lo_n, s["lo"]))
    ns["hi"] = jnp.where(inB, s["tb"], jnp.where(inN, hi_n, s["hi"]))
    ns["x"] = jnp.where(inB, x_b, jnp.where(inN, xn, x))
    ns["k"] = jnp.where(inB, 0, jnp.where(inN, kN, s["k"]))
    ns["top"] = jnp.where(inB, s["topn"], s["top"])
    # arrival at a pre-impact state
    ns["th"] = jnp.where(arrive, th1, s["th"])
    ns["sd"] = jnp.where(arrive, v1, s["sd"])
    ns["wall"] = jnp.where(arrive, wall1, s["wall"])
    ns["cyc"] = jnp.where(arrive, cyc1, s["cyc"])
    ns["sn"] = jnp.where(arrive, sn1, s["sn"])
    ns["cs"] = jnp.where(arrive, cs1, s["cs"])
    ns["n"] = jnp.where(arrive, n1, s["n"])
    ns["obs"] = tuple(obs_new)
    sticks = arrive & stick
    ns["nst"] = s["nst"] + sticks.astype(_I32)
    ns["nstk"] = jnp.where(sticks & (s["nstk"] < 0), n1, s["nstk"])
    ostat = jnp.where(stop, int(Orbit.STOPPED), jnp.where(arrive & stuck_forever, int(Orbit.STUCK_FOREVER),
                      jnp.where(stick_stop, int(Orbit.STUCK), jnp.where(capped, int(Orbit.CAPPED), s["ostat"]))))
    ostat = jnp.where(escaped, int(Orbit.NO_IMPACT), jnp.where(failed, int(Orbit.STEP_CAP), ostat))
    ns["ostat"] = ostat.astype(_I32)
    # the new flight
    ns["th0"] = jnp.where(go_on, th0_new, s["th0"])
    ns["sn0"] = jnp.where(go_on, sn0_new, s["sn0"])
    ns["cs0"] = jnp.where(go_on, cs0_new, s["cs0"])
    ns["v0"] = jnp.where(go_on, v0_new, s["v0"])
    ns["s0"] = jnp.where(go_on, s0_new, s["s0"])
    ns["cyc0"] = jnp.where(go_on, cyc0_new, s["cyc0"])
    ns["tdl"] = jnp.where(go_on, delay_used, s["tdl"])
    ns["rel"] = jnp.where(go_on, go_stick, s["rel"])
    ns["tdep"] = jnp.where(go_on, tdep_new, s["tdep"])
    ns["bc"] = jnp.where(go_on, bc_new, s["bc"])
    # idle lanes do not change
    idle = mode == MODE_IDLE
    return jax.tree_util.tree_map(lambda old, new: jnp.where(idle, old, new), s, ns)


def _load(lanes, queue, next_ic, n_ic, observers):
    """Refill idle lanes from the queue (in lane order); returns ``(lanes, next_ic)``."""
    idle = lanes["mode"] == MODE_IDLE
    rank = jnp.cumsum(idle.astype(_I32)) - 1
    idx = next_ic + rank
    take = idle & (idx < n_ic)
    j = jnp.clip(idx, 0, jnp.maximum(n_ic - 1, 0))
    new = dict(lanes)
    new["mode"] = jnp.where(take, MODE_L, lanes["mode"])
    new["ic"] = jnp.where(take, idx, jnp.where(idle, -1, lanes["ic"]))
    for name in QUEUE_FIELDS:
        new[name] = jnp.where(take, queue[name][j], lanes[name])
    for name, val in (("n", 0), ("cyc", 0), ("nst", 0), ("nstk", -1), ("ostat", int(Orbit.CAPPED))):
        new[name] = jnp.where(take, val, lanes[name])

    def reset(o, fields):
        return {name: jnp.where(take.reshape((-1,) + (1,) * (o[name].ndim - 1)),
                                jnp.asarray(fields[name][2], fields[name][0]), o[name]) for name in o}

    new["obs"] = tuple(reset(o, ob.fields()) for o, ob in zip(lanes["obs"], observers))
    return new, (next_ic + jnp.sum(take.astype(_I32))).astype(_I32)


def _store(res, lanes, observers):
    """Write the results of lanes whose orbit has ended (idle with an IC index) into ``res``."""
    done = (lanes["mode"] == MODE_IDLE) & (lanes["ic"] >= 0)
    n_ic = res["n"].shape[0]
    j = jnp.where(done, lanes["ic"], n_ic)  # out of range -> dropped
    out = {}
    for name, src in (("n", "n"), ("status", "ostat"), ("nst", "nst"), ("nstk", "nstk"), ("th", "th"), ("sd", "sd"),
                      ("wall", "wall"), ("cyc", "cyc")):
        out[name] = res[name].at[j].set(lanes[src], mode="drop")
    out["obs"] = tuple({name: r_o[name].at[j].set(l_o[name], mode="drop") for name in r_o}
                       for r_o, l_o in zip(res["obs"], lanes["obs"]))
    lanes = dict(lanes)
    lanes["ic"] = jnp.where(done, -1, lanes["ic"])
    return out, lanes


@partial(jax.jit, static_argnames=("size",))
def compact(lanes, size: int):
    """The lanes packed into a block of ``size`` lanes: busy ones first (in lane order), then idle ones.

    For the tail of a run, when the queue is empty and only a few long orbits are left: a micro-step
    costs the same for idle and busy lanes, so the last orbits finish far sooner on fewer lanes.  The
    caller ensures at most ``size`` lanes are busy (a lane whose finished orbit is not yet stored
    counts as busy) and that ``size`` is a multiple of :data:`LANE_QUANTUM`."""
    busy = (lanes["mode"] != MODE_IDLE) | (lanes["ic"] >= 0)
    order = jnp.argsort(~busy, stable=True)[:size]
    return jax.tree_util.tree_map(lambda x: x[order], lanes)


@partial(jax.jit, static_argnames=("observers", "block", "max_blocks"))
def run_blocks(carry, queue, k, observers, block=32, max_blocks=64):
    """Advance the engine by up to ``max_blocks`` blocks of ``block`` micro-steps (early exit when
    every initial condition of the queue is done).  ``carry = (lanes, res, next_ic)``; ``queue``: the
    arrays of :func:`prepare_queue` (possibly padded) and ``n_ic``, the number of initial conditions in
    it (a run-time value, so one compilation serves every queue of the same padded length)."""
    n_ic = queue["n_ic"]
    step_v = jax.vmap(lambda s: micro_step(s, k, observers))

    def cond(c):
        lanes, res, next_ic, nb = c
        busy = jnp.any(lanes["mode"] != MODE_IDLE) | (next_ic < n_ic)
        return busy & (nb < max_blocks)

    def body(c):
        lanes, res, next_ic, nb = c
        lanes, next_ic = _load(lanes, queue, next_ic, n_ic, observers)
        lanes = jax.lax.fori_loop(0, block, lambda _, L: step_v(L), lanes)
        res, lanes = _store(res, lanes, observers)
        return lanes, res, next_ic, nb + 1

    lanes, res, next_ic = carry
    lanes, res, next_ic, nb = jax.lax.while_loop(cond, body, (lanes, res, next_ic, jnp.asarray(0, _I32)))
    return (lanes, res, next_ic), nb


@partial(jax.jit, static_argnames=("n_impacts", "observers"))
def trace(queue1, k, n_impacts: int, observers=()):
    """Pre-impact states ``(theta, sdot, wall)`` after each of ``n_impacts`` map iterations of one orbit
    (``queue1``: a one-orbit queue from :func:`prepare_queue`), computed by the engine's micro-steps
    on a single unbatched lane (for tests against :func:`mapimpl.impact_map.step`).  Entries after the
    orbit ended are NaN."""
    lane = jax.tree_util.tree_map(lambda x: x[0], idle_lanes(1, observers))
    for name in QUEUE_FIELDS:
        lane[name] = queue1[name][0]
    lane.update(mode=jnp.int32(MODE_L), ic=jnp.int32(0), nstk=jnp.int32(-1), ostat=jnp.int32(int(Orbit.CAPPED)))
    hist = jnp.full((n_impacts + 1, 3), jnp.nan)

    def cond(c):
        l, h, it = c
        return (l["mode"] != MODE_IDLE) & (l["n"] < n_impacts) & (it < 200 * (n_impacts + 1))

    def body(c):
        l, h, it = c
        l2 = micro_step(l, k, observers)
        arrived = (l2["n"] != l["n"]) | (it == 0)
        row = jnp.stack([l2["th"], l2["sd"], l2["wall"].astype(_F64)])
        h = jnp.where(arrived, h.at[l2["n"]].set(row), h)
        return l2, h, it + 1

    lane, hist, _ = jax.lax.while_loop(cond, body, (lane, hist, jnp.asarray(0, _I32)))
    return hist


def padded_lanes(lanes: int) -> int:
    """``lanes`` rounded up to a multiple of :data:`LANE_QUANTUM` (at least one quantum)."""
    q = LANE_QUANTUM
    return max(q, -(-int(lanes) // q) * q)


__all__ = ["MODE_A", "MODE_B", "MODE_N", "MODE_L", "MODE_IDLE", "LANE_QUANTUM", "flight_sc", "make_consts",
           "idle_lanes", "empty_results", "prepare_queue", "micro_step", "compact", "run_blocks", "trace",
           "padded_lanes"]
