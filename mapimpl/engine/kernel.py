"""The transient engine's jit-compiled, vmapped kernel: many orbits of the impact map, results only.

Why not ``vmap(mapimpl.impact_map.step)``?  A vmapped ``lax.while_loop`` runs until its *slowest*
lane is done, so a batch of map steps costs the maximum, not the mean, number of finder iterations
(safe steps + Newton) over the batch, and a batch of orbits costs its longest transient.  This
kernel flattens everything into one uniform *micro-step*, one closed-form flight evaluation per
lane, driven by a per-lane state machine:

``A``  safe step at ``t_a`` (:func:`mapimpl.finder.safe_step`);
``B``  bracket test at ``t_b`` (:func:`mapimpl.finder.bracket_test`, when the step did not move on);
``N``  one safeguarded Newton iteration on the certified bracket (:func:`mapimpl.finder.newton_step`);
``S``  set-up of a flight that starts after a sticking episode (needs sin/cos of a new phase);
``L``  a freshly loaded initial condition (its pre-impact state is processed as an impact).

When a lane's search ends, the impact is applied in the same micro-step (Eqs. 11-13, sticking
policy of :mod:`mapimpl.sticking`), the distance to the periodic orbit is checked, and the next
flight is set up.  When its orbit is done, the lane is refilled from the queue of initial
conditions at the end of the current block of micro-steps.  So lanes are busy almost all the time
regardless of how the finder iterations and transient lengths are distributed.

The decisions are the finder's own functions -- :func:`mapimpl.finder.safe_step`,
:func:`~mapimpl.finder.bracket_test`, :func:`~mapimpl.finder.newton_step` and
:func:`~mapimpl.finder.departure_time_sc` -- and the sticking policy is that of
:mod:`mapimpl.sticking`; only the control flow differs (one evaluation per micro-step instead of
nested loops).  A new flight's first safe step needs no evaluation: its state at ``t = 0`` is
``(0, v0, a0)`` in closed form, so it is taken in the impact's micro-step.  Three performance changes
move results by a few ulps only (tests compare with :func:`mapimpl.impact_map.step`): sin/cos of the
flight start phase are computed once per flight instead of at every evaluation, sin/cos come from
:func:`mapimpl.engine.fastmath.sincos` (vectorised fdlibm kernels), and ``sin t`` inside
``sigma`` is taken from the double-angle formula.  The velocity at the Newton root is extrapolated
from the last Newton evaluation (``v + a dx`` with ``dx`` below rounding).
"""

from __future__ import annotations

from functools import partial

from .. import _jax  # noqa: F401
import jax
import jax.numpy as jnp

from ..finder import _H0, MAX_STEPS, T_MAX, _gaps, bracket_test, departure_time_sc, newton_step, safe_step
from ..flight import TWO_PI, TWO_PI_HI, TWO_PI_LO, _SERIES_X, _SIGMA_COEFFS, _horner, forcing_sc, phi1, phi2
from ..sticking import STICK_TIME, decide_stick_sc
from .fastmath import sincos

# lane modes
MODE_A, MODE_B, MODE_N, MODE_S, MODE_L, MODE_IDLE = 0, 1, 2, 3, 4, 5

# final orbit status of an initial condition
CONVERGED, CAPPED, STUCK_FOREVER, ESCAPED, FAILED, NOT_RUN = 0, 1, 2, 3, 4, -1
STATUS_NAMES = {CONVERGED: "converged", CAPPED: "capped", STUCK_FOREVER: "stuck_forever",
                ESCAPED: "no_impact", FAILED: "step_cap", NOT_RUN: "not_run"}


def _barrier(x, pred):
    """Materialise ``x`` once.  Without it XLA:CPU fuses the shared flight evaluation (cheap
    multiply-adds, hence duplicated) into every one of the ~30 output fusions of the micro-step:
    30x the work.  ``optimization_barrier`` is removed before fusion on CPU, but the operands and
    results of a ``lax.cond`` on a run-time predicate (always true here) are real buffers."""
    return jax.lax.cond(pred, lambda y: y, lambda y: jax.tree_util.tree_map(jnp.zeros_like, y), x)


def _reduce(theta):
    """:func:`mapimpl.flight.reduce_phase` without the turn counter (same arithmetic)."""
    m = jnp.floor(theta / TWO_PI)
    th = (theta - m * TWO_PI_HI) - m * TWO_PI_LO
    adj = jnp.where(th >= TWO_PI, 1.0, jnp.where(th < 0.0, -1.0, 0.0))
    th = (th - adj * TWO_PI_HI) - adj * TWO_PI_LO
    return jnp.clip(th, 0.0, jnp.nextafter(TWO_PI, 0.0))


def _sigma_from_sin(t, sin_t):
    big = jnp.abs(t) >= _SERIES_X
    tb = jnp.where(big, t, 1.0)
    direct = (tb - jnp.where(big, sin_t, 0.0)) / (tb * tb * tb)
    ts = jnp.where(big, 0.0, t)
    return jnp.where(big, direct, _horner(ts * ts, _SIGMA_COEFFS))


def flight_sc(t, sn0, cs0, v0, alpha, beta, gamma):
    """:func:`mapimpl.flight.flight` with ``sin/cos(tau0)`` given; also returns ``exp(-beta t)``."""
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
    return ds, v, a, e


def make_consts(params, orbit_theta, orbit_sdot, orbit_wall, deltas, cap, stick_time=STICK_TIME, t_max=T_MAX,
                max_steps=MAX_STEPS):
    """Pytree of run constants (float64 / int32 JAX arrays)."""
    alpha, beta, gamma, r = (jnp.asarray(x, jnp.float64) for x in params)
    return dict(
        alpha=alpha, beta=beta, gamma=gamma, r=r,
        po_th=jnp.asarray(orbit_theta, jnp.float64), po_v=jnp.asarray(orbit_sdot, jnp.float64),
        po_w=jnp.asarray(orbit_wall, jnp.int32), deltas=jnp.asarray(deltas, jnp.float64),
        cap=jnp.asarray(cap, jnp.int32), stick_time=jnp.asarray(stick_time, jnp.float64),
        t_max=jnp.asarray(t_max, jnp.float64), max_steps=jnp.asarray(max_steps, jnp.int32),
        true=jnp.asarray(True),
    )


def distance(theta, sdot, wall, k):
    """Sup-norm distance of a pre-impact state to the nearest point of the periodic orbit on the same
    wall (phase difference wrapped to ``[-pi, pi]``)."""
    dth = jnp.abs(theta - k["po_th"])
    dth = jnp.minimum(dth, TWO_PI - dth)
    d = jnp.maximum(dth, jnp.abs(sdot - k["po_v"]))
    d = jnp.where(wall == k["po_w"], d, jnp.inf)
    return jnp.min(d)


def lane_fields(ndelta):
    """Names and dtypes of the per-lane state."""
    f64, i32 = jnp.float64, jnp.int32
    return dict(
        mode=i32, ic=i32, n=i32, th=f64, sd=f64, wall=i32, nst=i32, hitn=(i32, ndelta), ostat=i32,
        th0=f64, sn0=f64, cs0=f64, v0=f64, s0=f64, tdep=f64, bc=f64,
        ta=f64, H=f64, it=i32, tb=f64, topn=jnp.bool_, uniq=jnp.bool_, hnear=f64, hnew=f64, va=f64,
        x=f64, lo=f64, hi=f64, top=jnp.bool_, k=i32,
    )


def idle_lanes(nlanes, ndelta):
    """A block of idle lanes."""
    out = {}
    for name, dt in lane_fields(ndelta).items():
        shape = (nlanes,) + ((dt[1],) if isinstance(dt, tuple) else ())
        dtype = dt[0] if isinstance(dt, tuple) else dt
        out[name] = jnp.zeros(shape, dtype)
    out["mode"] = jnp.full((nlanes,), MODE_IDLE, jnp.int32)
    out["ic"] = jnp.full((nlanes,), -1, jnp.int32)
    out["hitn"] = jnp.full((nlanes, ndelta), -1, jnp.int32)
    return out


def micro_step(s, k):
    """One micro-step of one lane (scalar state ``s``; vmapped by the engine)."""
    alpha, beta, gamma, r = k["alpha"], k["beta"], k["gamma"], k["r"]
    mode = s["mode"]
    inA, inB, inN, inS, inL = (mode == MODE_A), (mode == MODE_B), (mode == MODE_N), (mode == MODE_S), (mode == MODE_L)
    # ---------------- one flight evaluation ----------------
    t_eval = jnp.where(inA, s["ta"], jnp.where(inB, s["tb"], jnp.where(inN, s["x"], 0.0)))
    ds, v, a, e = _barrier(flight_sc(t_eval, s["sn0"], s["cs0"], s["v0"], alpha, beta, gamma), k["true"])
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
    v_hit = jnp.where(inN, v + a * (xn - x), s["va"])
    top_hit = jnp.where(inN, s["top"], s["topn"])
    escaped = inB & ~bracket & ~stalled & B_beyond
    failed = inB & ~bracket & ~stalled & ~B_beyond & B_capped

    # ---------------- impact processing (or a freshly loaded pre-impact state) ----------------
    th1 = jnp.where(inL, s["th"], _reduce(s["th0"] + t_hit))
    v1 = jnp.where(inL, s["sd"], v_hit)
    wall1 = jnp.where(inL, s["wall"], jnp.where(top_hit, 0, -1)).astype(jnp.int32)
    n1 = jnp.where(inL, s["n"], s["n"] + 1)
    arrive = got_hit | inL
    # second sin/cos unit: phase of the arriving impact, or the new start phase after sticking
    th1, v1, n1, arrive, got_hit, escaped, failed, bracket, stalled = _barrier(
        (th1, v1, n1, arrive, got_hit, escaped, failed, bracket, stalled), k["true"])
    sn1, cs1 = _barrier(sincos(jnp.where(inS, s["th0"], th1)), k["true"])
    # distance to the periodic orbit and first-hit iterations for each delta
    dist = distance(th1, v1, wall1, k)
    newly = arrive & (s["hitn"] < 0) & (dist < k["deltas"])
    hitn = jnp.where(newly, n1, s["hitn"])
    converged = jnp.all(hitn >= 0)
    capped = n1 >= k["cap"]
    # sticking policy
    stick, _, delay, rel_phase = decide_stick_sc(th1, sn1, cs1, wall1, v1, alpha, beta, gamma, r, k["stick_time"])
    stuck_forever = stick & ~jnp.isfinite(delay)
    orbit_end = arrive & (converged | capped | stuck_forever)
    go_on = arrive & ~orbit_end
    go_stick = go_on & stick
    go_free = go_on & ~stick
    th0_stick = rel_phase  # the canonical release phase: every stuck orbit leaves from the same state

    # set-up of a new flight from (th0, s0, v0) with known sin/cos: departure certificate, the
    # decaying part of the derivative bounds, the acceleration at t = 0 (Eq. 3)
    def setup(sn0, cs0, v0, s0):
        tdep = departure_time_sc(sn0, cs0, s0, v0, alpha, beta, gamma)
        bc = jnp.abs(beta * (v0 - alpha * cs0) - gamma)
        a0 = forcing_sc(sn0, cs0, alpha, beta, gamma) - beta * v0
        return tdep, bc, a0

    # free flight right after the impact (no sticking): start phase th1, v0 = -r v1
    s0_new = wall1.astype(jnp.float64)
    # S mode: th0/s0 already stored, v0 = 0, sin/cos(th0) = (sn1, cs1) from the second unit
    su_v0 = jnp.where(inS, 0.0, -r * v1)
    su_s0 = jnp.where(inS, s["s0"], s0_new)
    tdep_new, bc_new, a0_new = setup(sn1, cs1, su_v0, su_s0)
    start_flight = go_free | inS
    (hitn, converged, stuck_forever, orbit_end, go_on, go_stick, go_free, th0_stick, tdep_new, bc_new, a0_new,
     su_v0, su_s0, start_flight) = _barrier((hitn, converged, stuck_forever, orbit_end, go_on, go_stick, go_free,
                                            th0_stick, tdep_new, bc_new, a0_new, su_v0, su_s0, start_flight),
                                           k["true"])

    # ---------------- A: one safe step ----------------
    # from this micro-step's evaluation (mode A), or from t = 0 of the flight that starts now: the
    # state there is (ds, v, a) = (0, v0, a0) in closed form, so a new flight needs no evaluation
    # for its first step.  (A lane never does both: lanes in mode A do not arrive at an impact.)
    doA = inA | start_flight
    ta_in = jnp.where(inA, ta, 0.0)
    H_in = jnp.where(inA, H, _H0)
    v_in = jnp.where(inA, v, su_v0)
    b_in = jnp.where(inA, b, bc_new)
    A = _barrier(safe_step(jnp.where(inA, ds, 0.0), v_in, jnp.where(inA, a, a0_new), alpha + b_in, alpha + beta * b_in,
                           ta_in, H_in, jnp.where(inA, s["it"], 0), jnp.where(inA, s["tdep"], tdep_new),
                           jnp.where(inA, s["s0"], su_s0), k["t_max"], k["max_steps"]), k["true"])
    escaped = escaped | (doA & A.move & A.beyond)
    failed = failed | (doA & A.move & ~A.beyond & A.capped)

    # ---------------- next state ----------------
    ns = dict(s)
    # mode transitions
    new_mode = mode
    new_mode = jnp.where(inB & bracket, MODE_N, new_mode)
    new_mode = jnp.where(inB & ~bracket & ~stalled, MODE_A, new_mode)
    new_mode = jnp.where(doA, jnp.where(A.move, MODE_A, MODE_B), new_mode)
    new_mode = jnp.where(go_stick, MODE_S, new_mode)
    lane_end = orbit_end | escaped | failed
    new_mode = jnp.where(lane_end, MODE_IDLE, new_mode)
    ns["mode"] = new_mode.astype(jnp.int32)
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
    # B -> N initialisation (lo = t_a, hi = t_b, x = midpoint); N update
    ns["lo"] = jnp.where(inB, ta, jnp.where(inN, lo_n, s["lo"]))
    ns["hi"] = jnp.where(inB, s["tb"], jnp.where(inN, hi_n, s["hi"]))
    ns["x"] = jnp.where(inB, x_b, jnp.where(inN, xn, x))
    ns["k"] = jnp.where(inB, 0, jnp.where(inN, kN, s["k"]))
    ns["top"] = jnp.where(inB, s["topn"], s["top"])
    # arrival at a pre-impact state
    ns["th"] = jnp.where(arrive, th1, s["th"])
    ns["sd"] = jnp.where(arrive, v1, s["sd"])
    ns["wall"] = jnp.where(arrive, wall1, s["wall"])
    ns["n"] = jnp.where(arrive, n1, s["n"])
    ns["hitn"] = hitn
    ns["nst"] = s["nst"] + (go_stick | (arrive & stuck_forever)).astype(jnp.int32)
    ostat = jnp.where(converged, CONVERGED, jnp.where(stuck_forever, STUCK_FOREVER, CAPPED))
    ostat = jnp.where(arrive, ostat, s["ostat"])
    ostat = jnp.where(escaped, ESCAPED, jnp.where(failed, FAILED, ostat))
    ns["ostat"] = ostat.astype(jnp.int32)
    # new flight
    ns["th0"] = jnp.where(go_free, th1, jnp.where(go_stick, th0_stick, s["th0"]))
    ns["s0"] = jnp.where(go_on, s0_new, s["s0"])
    ns["v0"] = jnp.where(start_flight, su_v0, jnp.where(go_stick, 0.0, s["v0"]))
    ns["sn0"] = jnp.where(start_flight, sn1, s["sn0"])
    ns["cs0"] = jnp.where(start_flight, cs1, s["cs0"])
    ns["tdep"] = jnp.where(start_flight, tdep_new, s["tdep"])
    ns["bc"] = jnp.where(start_flight, bc_new, s["bc"])
    # idle lanes do not change
    idle = mode == MODE_IDLE
    return jax.tree_util.tree_map(lambda old, new: jnp.where(idle, old, new), s, ns)


def _load(lanes, queue_th, queue_sd, queue_wall, next_ic, n_ic, ndelta):
    """Refill idle lanes from the queue (in lane order); returns (lanes, next_ic)."""
    idle = lanes["mode"] == MODE_IDLE
    rank = jnp.cumsum(idle.astype(jnp.int32)) - 1
    idx = next_ic + rank
    take = idle & (idx < n_ic)
    j = jnp.clip(idx, 0, jnp.maximum(n_ic - 1, 0))
    new = dict(lanes)
    new["mode"] = jnp.where(take, MODE_L, lanes["mode"])
    new["ic"] = jnp.where(take, idx, jnp.where(idle, -1, lanes["ic"]))
    new["th"] = jnp.where(take, queue_th[j], lanes["th"])
    new["sd"] = jnp.where(take, queue_sd[j], lanes["sd"])
    new["wall"] = jnp.where(take, queue_wall[j], lanes["wall"])
    new["n"] = jnp.where(take, 0, lanes["n"])
    new["nst"] = jnp.where(take, 0, lanes["nst"])
    new["hitn"] = jnp.where(take[:, None], -1, lanes["hitn"])
    new["ostat"] = jnp.where(take, CAPPED, lanes["ostat"])
    return new, (next_ic + jnp.sum(take.astype(jnp.int32))).astype(jnp.int32)


def _store(res, lanes):
    """Write the results of lanes whose orbit has ended (idle with an IC index) into ``res``."""
    done = (lanes["mode"] == MODE_IDLE) & (lanes["ic"] >= 0)
    n_ic = res["n"].shape[0]
    j = jnp.where(done, lanes["ic"], n_ic)  # out of range -> dropped
    out = {}
    out["n"] = res["n"].at[j].set(lanes["n"], mode="drop")
    out["status"] = res["status"].at[j].set(lanes["ostat"], mode="drop")
    out["nstick"] = res["nstick"].at[j].set(lanes["nst"], mode="drop")
    out["hitn"] = res["hitn"].at[j].set(lanes["hitn"], mode="drop")
    lanes = dict(lanes)
    lanes["ic"] = jnp.where(done, -1, lanes["ic"])
    return out, lanes


@partial(jax.jit, static_argnames=("size",))
def compact(lanes, size: int):
    """The lanes packed into a block of ``size`` lanes: busy ones first (in lane order), then idle ones.

    For the tail of a run, when the queue is empty and only a few long orbits are left: a micro-step
    costs the same for idle and busy lanes, so the last orbits finish far sooner on fewer lanes.  The
    caller ensures at most ``size`` lanes are busy (a lane whose finished orbit is not yet stored
    counts as busy)."""
    busy = (lanes["mode"] != MODE_IDLE) | (lanes["ic"] >= 0)
    order = jnp.argsort(~busy, stable=True)[:size]
    return jax.tree_util.tree_map(lambda x: x[order], lanes)


@partial(jax.jit, static_argnames=("block", "max_blocks"))
def run_blocks(carry, queue_th, queue_sd, queue_wall, k, block=32, max_blocks=64):
    """Advance the engine by up to ``max_blocks`` blocks of ``block`` micro-steps (early exit when
    every initial condition of the queue is done).  ``carry = (lanes, res, next_ic)``."""
    n_ic = queue_th.shape[0]
    ndelta = k["deltas"].shape[0]
    step_v = jax.vmap(micro_step, in_axes=(0, None))

    def cond(c):
        lanes, res, next_ic, nb = c
        busy = jnp.any(lanes["mode"] != MODE_IDLE) | (next_ic < n_ic)
        return busy & (nb < max_blocks)

    def body(c):
        lanes, res, next_ic, nb = c
        lanes, next_ic = _load(lanes, queue_th, queue_sd, queue_wall, next_ic, n_ic, ndelta)
        lanes = jax.lax.fori_loop(0, block, lambda _, L: step_v(L, k), lanes)
        res, lanes = _store(res, lanes)
        return lanes, res, next_ic, nb + 1

    lanes, res, next_ic = carry
    lanes, res, next_ic, nb = jax.lax.while_loop(cond, body, (lanes, res, next_ic, jnp.asarray(0, jnp.int32)))
    return (lanes, res, next_ic), nb


@partial(jax.jit, static_argnames=("n_impacts",))
def trace(theta0, sdot0, wall0, k, n_impacts: int):
    """Pre-impact states ``(theta, sdot, wall, nstick)`` after each of ``n_impacts`` map iterations of
    one orbit, computed by the engine's micro-steps (for tests against :func:`mapimpl.impact_map.step`).
    Entries after the orbit ended (stuck forever, escaped) are NaN."""
    lane = jax.tree_util.tree_map(lambda x: x[0], idle_lanes(1, k["deltas"].shape[0]))
    lane.update(mode=jnp.int32(MODE_L), ic=jnp.int32(0), th=jnp.asarray(theta0, jnp.float64),
                sd=jnp.asarray(sdot0, jnp.float64), wall=jnp.asarray(wall0, jnp.int32))
    hist = jnp.full((n_impacts + 1, 3), jnp.nan)

    def cond(c):
        l, h, it = c
        return (l["mode"] != MODE_IDLE) & (l["n"] < n_impacts) & (it < 200 * (n_impacts + 1))

    def body(c):
        l, h, it = c
        l2 = micro_step(l, k)
        arrived = l2["n"] != l["n"]
        row = jnp.stack([l2["th"], l2["sd"], l2["wall"].astype(jnp.float64)])
        h = jnp.where(arrived, h.at[l2["n"]].set(row), h)
        return l2, h, it + 1

    hist = hist.at[0].set(jnp.stack([lane["th"], lane["sd"], lane["wall"].astype(jnp.float64)]))
    lane, hist, _ = jax.lax.while_loop(cond, body, (lane, hist, jnp.asarray(0, jnp.int32)))
    return hist
