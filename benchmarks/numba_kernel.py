"""A numba reference kernel of the transient engine's method (benchmark baseline, issue 12).

:func:`numba_transients` computes what :func:`gear_rattle.mapimpl.engine.transients.transient_times`
computes -- for every initial condition (a pre-impact state of the impact map), the first map
iteration at which the pre-impact state lies within each ``delta`` of the stable periodic orbit --
with the same method, written the way a careful numba user would write it: one scalar loop per
orbit, ``prange`` over the initial conditions (dynamic chunks, so long and short transients balance
over the cores), ``float64`` and ``fastmath=False``, transcendental functions from :mod:`math`, no
Python objects in the loop.  It exists only as the baseline of ``bench_engine_vs_numba.py``.

The method (mirrored decision for decision from :mod:`gear_rattle.mapimpl.finder`,
:mod:`~gear_rattle.mapimpl.flight`, :mod:`~gear_rattle.mapimpl.sticking` and the engine's micro-step
:mod:`gear_rattle.mapimpl.engine.kernel`):

* closed-form flight, Eqs. (7)-(8) in the cancellation-free form of ``mapimpl.flight``
  (``phi12``: one Taylor series for ``phi2`` below argument 1 with ``phi1 = 1 - x phi2``, the direct
  forms with ``expm1(-x) = e - 1`` above; ``sigma`` by its 9-term series below 1), sin/cos of the
  flight's start phase once per flight, ``sin t`` inside ``sigma`` from the double angle of ``t/2``;
* certified safe steps (``safe_step``: derivative bounds ``M2 = alpha + b e^{-beta t}``,
  ``M3 = alpha + beta b e^{-beta t}``, window ``H`` doubling to 2), the bracket test at the point
  just past the root predicted by the local quadratic (skipped when no root is predicted in the
  window; uniqueness certified on the test interval from both ends, ``bracket_unique``), the
  safeguarded root iteration on the local quadratic model from the test point (``root_step``) with
  the same stopping rules (2 ulp, predicted error far below an ulp, bracket width, 80 iterations),
  the velocity at the root extrapolated to second order from the last evaluation; the first safe
  step of a flight from its closed-form state at ``t = 0`` (no evaluation); a safe step below one
  ulp is a graze;
* the departure certificate of a flight that starts on a wall (``departure_time_sc``);
* the sticking policy (``decide_stick_sc``) with the canonical release phase of each wall
  (``release_phase``, a function of the parameters alone: computed once per run here);
* capture: sup-norm distance of ``(tau mod 2 pi, sdot)`` to a point of the periodic orbit on the
  same wall, phase difference wrapped, checked at every pre-impact state including the initial one;
  an orbit ends when it is within every ``delta``, after ``cap`` iterations, when it sticks forever,
  when a flight exceeds ``T_MAX`` (escaped) or a search ``MAX_STEPS`` safe steps (failed).

Every loop is bounded (``cap`` impacts, ``MAX_STEPS`` safe steps per flight, 80 Newton iterations).
The differences from the engine are arithmetic only: libm ``sin``/``cos``/``exp`` (the engine: fdlibm
polynomial kernels and XLA's own ``exp``; one reciprocal of ``t`` where this kernel divides twice), so
orbits agree to a few ulps per impact;
chaotic orbits then separate after ~50-100 impacts while short transients end identically.

    from numba_kernel import numba_transients
    res = numba_transients(theta0, sdot0, params, target_theta, target_sdot, target_wall, deltas, cap)
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import njit, prange

# ---- constants of the method (same values as gear_rattle.mapimpl.finder / flight / sticking) ----
TWO_PI = 2.0 * math.pi
TWO_PI_HI = float.fromhex("0x1.921fb54400000p+2")  # three-term Cody-Waite split (mapimpl.flight)
TWO_PI_MID = float.fromhex("0x1.0b4611a600000p-32")
TWO_PI_LO = 8.089064995183803e-21
TWO_PI_BELOW = float(np.nextafter(TWO_PI, 0.0))
EPS = 2.220446049250313e-16
H0, H_MAX = 0.5, 2.0
T_MAX = 2000.0
MAX_STEPS = 4000
NEWTON_ITERS = 80
STICK_TIME = 1e-6
SERIES_X = 1.0  # phi2 and (in the engine's flight) sigma use their Taylor series below this

# status codes (the engine's names; the values of gear_rattle.mapimpl.engine.kernel)
CONVERGED, CAPPED, STUCK_FOREVER, ESCAPED, FAILED = 0, 1, 2, 3, 4
STATUS_NAMES = {
    CONVERGED: "converged",
    CAPPED: "capped",
    STUCK_FOREVER: "stuck_forever",
    ESCAPED: "no_impact",
    FAILED: "step_cap",
}


def _inv_factorials(start: int, n: int) -> list[float]:
    out, f = [], 1.0
    for k in range(1, start + n):
        f *= k
        if k >= start:
            out.append(1.0 / f)
    return out


# Taylor coefficients, built exactly as in mapimpl.flight; stored highest order first for Horner
# (acc = c[-1]; acc = acc * x + c for c in c[-2::-1]).
_PHI2 = [((-1.0) ** k) * c for k, c in enumerate(_inv_factorials(2, 18))]
_SIGMA = [((-1.0) ** k) * c for k, c in enumerate(_inv_factorials(3, 30)[::2][:9])]  # the engine's 9 terms
PHI2_TOP, PHI2_REST = _PHI2[-1], tuple(_PHI2[-2::-1])
SIGMA_TOP, SIGMA_REST = _SIGMA[-1], tuple(_SIGMA[-2::-1])

_JIT = dict(fastmath=False, error_model="numpy", nogil=True, cache=False)
INF = math.inf


# ------------------------------------------------------------------------------ flight, Eqs. (7)-(8)


@njit(inline="always", **_JIT)
def _phi12(x, e):
    """mapimpl.flight.phi12: (phi1, phi2) given e = exp(-x); one series (phi2) below x = 1 with
    phi1 = 1 - x phi2, the direct forms with expm1(-x) = e - 1 above."""
    if x >= SERIES_X:
        return -(e - 1.0) / x, ((x - 1.0) + e) / (x * x)
    acc = PHI2_TOP
    for c in PHI2_REST:
        acc = acc * x + c
    return 1.0 - x * acc, acc


@njit(inline="always", **_JIT)
def _sigma_from_sin(t, sin_t):
    """(t - sin t) / t^3 with ``sin t`` given; Taylor series below |t| = 1."""
    if abs(t) >= SERIES_X:
        return (t - sin_t) / (t * t * t)
    ts = t * t
    acc = SIGMA_TOP
    for c in SIGMA_REST:
        acc = acc * ts + c
    return acc


@njit(inline="always", **_JIT)
def _flight(t, sn0, cs0, v0, alpha, beta, gamma):
    """Flight time ``t`` after leaving phase ``tau0`` (``sn0, cs0 = sin, cos tau0``) with velocity
    ``v0``: ``(ds, v, a, exp(-beta t), sin(tau0 + t), cos(tau0 + t))``, ``ds = s - s0`` (Eqs. 7-8,
    cancellation-free)."""
    half = 0.5 * t
    sh = math.sin(half)
    ch = math.cos(half)
    bt = beta * t
    e = math.exp(-bt)
    p1, p2 = _phi12(bt, e)
    if abs(half) < 1e-8:
        sc = 1.0 - half * half / 6.0
    else:
        sc = sh / half
    st = 2.0 * sh * ch
    ct = 1.0 - 2.0 * sh * sh
    q = -0.5 * alpha * sn0 * sc * sc + alpha * cs0 * (beta * p2 - t * _sigma_from_sin(t, st)) + gamma * p2
    ds = t * v0 * p1 + t * t * q
    sin_mid = sn0 * ch + cs0 * sh
    v = v0 * e + t * (-alpha * sin_mid * sc + (alpha * beta * cs0 + gamma) * p1)
    sin_t = sn0 * ct + cs0 * st
    cos_t = cs0 * ct - sn0 * st
    a = -alpha * sin_t + alpha * beta * cos_t + gamma - beta * v
    return ds, v, a, e, sin_t, cos_t


@njit(inline="always", **_JIT)
def _forcing(sn, cs, alpha, beta, gamma):
    return -alpha * sn + alpha * beta * cs + gamma


@njit(inline="always", **_JIT)
def _forcing_rate(sn, cs, alpha, beta):
    return -alpha * cs - alpha * beta * sn


@njit(inline="always", **_JIT)
def _reduce(theta):
    """Phase mod 2 pi by a two-term 2 pi (``mapimpl.flight.reduce_phase`` without the turn counter)."""
    m = math.floor(theta / TWO_PI)
    th = ((theta - m * TWO_PI_HI) - m * TWO_PI_MID) - m * TWO_PI_LO
    if th >= TWO_PI:
        adj = 1.0
    elif th < 0.0:
        adj = -1.0
    else:
        adj = 0.0
    th = ((th - adj * TWO_PI_HI) - adj * TWO_PI_MID) - adj * TWO_PI_LO
    return min(max(th, 0.0), TWO_PI_BELOW)


# ------------------------------------------------------------------------------ the finder's decisions


@njit(inline="always", **_JIT)
def _bracket_unique(v_a, a_a, v_b, a_b, m2, m3, ell):
    """mapimpl.finder.bracket_unique: velocity or acceleration keeps its sign on [t_a, t_b], bounds
    applied from both ends."""
    A = min(min(abs(a_a), abs(a_b)) + m3 * ell, m2)
    if v_a * v_b > 0.0 and abs(v_a) + abs(v_b) > A * ell:
        return True
    return a_a * a_b > 0.0 and abs(a_a) + abs(a_b) > m3 * ell


@njit(inline="always", **_JIT)
def _quadratic_time(d, u, a):
    """Smallest h > 0 with d - u h - a h^2 / 2 = 0 (inf if none), no underflow guard: the estimate of
    a root (mapimpl.finder.quadratic_time)."""
    disc = u * u + 2.0 * a * d
    if u > 0.0:
        if disc >= 0.0:
            return 2.0 * d / (u + math.sqrt(disc))
        return INF
    if a > 0.0:
        return (math.sqrt(max(disc, 0.0)) - u) / a
    return INF


@njit(inline="always", **_JIT)
def _safe_time(d, u, A):
    """Smallest h > 0 with d - u h - A h^2 / 2 = 0 (inf if none); mapimpl.finder.safe_time: the root of
    _quadratic_time, with its lower bounds where u^2 + 2 A d underflows."""
    h = _quadratic_time(d, u, A)
    disc = u * u + 2.0 * A * d
    if disc < 1e-290 and (disc >= 0.0 if u > 0.0 else A > 0.0):  # a root exists, its forms underflow
        sq = math.sqrt(2.0 * max(A, 0.0)) * math.sqrt(d)
        if u > 0.0:
            return 2.0 * d / (2.0 * u + sq)
        return max(h, sq / A)
    return h


@njit(inline="always", **_JIT)
def _departure_time(sin0, cos0, s0, v0, alpha, beta, gamma):
    """Certified interval [0, t_dep] in which a flight starting on a wall cannot return to it."""
    on_top = s0 == 0.0
    if not (on_top or s0 == -1.0):
        return 0.0
    sgn = 1.0 if on_top else -1.0
    a0 = _forcing(sin0, cos0, alpha, beta, gamma) - beta * v0
    bc = abs(beta * (v0 - alpha * cos0) - gamma)
    m2 = alpha + bc
    m3 = alpha + beta * bc
    m4 = alpha + beta * beta * bc
    u = sgn * v0
    a = sgn * a0
    j = sgn * (_forcing_rate(sin0, cos0, alpha, beta) - beta * a0)
    a_tol = 32.0 * EPS * (alpha * (1.0 + beta) + abs(gamma) + beta * abs(v0))
    if abs(a) <= a_tol:
        a = 0.0
    tiny = 1e-300
    c1 = 2.0 * (-u) / max(m2, tiny) if u < 0.0 else 0.0
    c2 = 1.5 * (-a) / max(m3, tiny) if (u <= 0.0 and a < 0.0) else 0.0
    c3 = 2.0 * (-j) / max(m4, tiny) if (u <= 0.0 and a <= 0.0 and j < 0.0) else 0.0
    return 0.5 * max(c1, max(c2, c3))


@njit(inline="always", **_JIT)
def _distance(theta, sdot, wall, po_th, po_v, po_w):
    """Sup-norm distance to the nearest periodic-orbit point on the same wall (phase wrapped)."""
    best = INF
    for i in range(po_th.shape[0]):
        if po_w[i] != wall:
            continue
        dth = abs(theta - po_th[i])
        dth = min(dth, TWO_PI - dth)
        d = max(dth, abs(sdot - po_v[i]))
        if d < best:
            best = d
    return best


# ------------------------------------------------------------------------------ one orbit


@njit(**_JIT)
def _orbit(
    th1,
    v1,
    alpha,
    beta,
    gamma,
    r,
    po_th,
    po_v,
    po_w,
    deltas,
    hit,
    cap,
    stick_time,
    t_max,
    max_steps,
    rel_th,
    rel_sn,
    rel_cs,
    rel_never,
):
    """Run one orbit from the pre-impact state ``(th1, v1)`` (wall from the sign of ``v1``); fills
    ``hit`` (first iteration within each delta, -1 never) and returns ``(n, status, nstick, evals)``,
    ``evals``: closed-form flight evaluations (the engine's micro-steps, less loads and post-sticking set-ups)."""
    nd = deltas.shape[0]
    for j in range(nd):
        hit[j] = -1
    wall1 = 0 if v1 > 0.0 else -1
    n = 0
    nstick = 0
    evals = 0
    while True:
        # ---------------- a pre-impact state (th1, v1, wall1), iteration n ----------------
        sn1 = math.sin(th1)
        cs1 = math.cos(th1)
        dist = _distance(th1, v1, wall1, po_th, po_v, po_w)
        converged = True
        for j in range(nd):
            if hit[j] < 0:
                if dist < deltas[j]:
                    hit[j] = n
                else:
                    converged = False
        if converged:
            return n, CONVERGED, nstick, evals
        # sticking policy (mapimpl.sticking.decide_stick_sc)
        w = 0 if wall1 == 0 else 1
        d = 1.0 if wall1 == 0 else -1.0
        u = r * abs(v1)
        f_in = d * _forcing(sn1, cs1, alpha, beta, gamma)
        pressing = (f_in > 0.0) or (f_in == 0.0 and d * _forcing_rate(sn1, cs1, alpha, beta) > 0.0)
        stick = False
        if pressing:
            denom = (1.0 - r) * f_in
            if u == 0.0:
                t_acc = 0.0
            elif denom > 0.0:
                t_acc = 2.0 * u / denom
            else:
                t_acc = INF
            delay = INF if rel_never[w] else (rel_th[w] - th1) % TWO_PI
            stick = (t_acc <= stick_time) and (delay > t_acc)
            if stick and rel_never[w]:
                return n, STUCK_FOREVER, nstick + 1, evals
        if n >= cap:
            return n, CAPPED, nstick, evals
        # ---------------- set-up of the next flight ----------------
        s0 = float(wall1)
        if stick:
            nstick += 1
            v0, sn0, cs0, th0 = 0.0, rel_sn[w], rel_cs[w], rel_th[w]
        else:
            v0, sn0, cs0, th0 = -r * v1, sn1, cs1, th1
        tdep = _departure_time(sn0, cs0, s0, v0, alpha, beta, gamma)
        bc = abs(beta * (v0 - alpha * cs0) - gamma)
        # state at t = 0 in closed form: the first safe step needs no evaluation
        ds, v, a = 0.0, v0, _forcing(sn0, cs0, alpha, beta, gamma) - beta * v0
        b = bc
        ta, H, it = 0.0, H0, 0
        # ---------------- certified search for the first impact ----------------
        while True:
            # safe step at ta (mapimpl.finder.safe_step)
            m2 = alpha + b
            m3 = alpha + beta * b
            du = max(-s0 - ds, 0.0)
            dl = max((s0 + 1.0) + ds, 0.0)
            hu = _safe_time(du, v, min(a + m3 * H, m2))
            hl = _safe_time(dl, -v, min(-a + m3 * H, m2))
            rem = tdep - ta
            if rem > 0.0:
                if s0 == 0.0:
                    hu = max(hu, rem)
                elif s0 == -1.0:
                    hl = max(hl, rem)
            top_near = hu <= hl
            h_near = min(hu, hl)
            it += 1
            if h_near >= H:  # a full window: no wall within it
                t_next = ta + H
                H_new = min(2.0 * H, H_MAX)
                move = True
            else:
                h_far = max(hu, hl)
                wdw = min(min(2.0 * h_near, h_far), H)
                if top_near:
                    d_near, u_near, a_near = du, v, a
                else:
                    d_near, u_near, a_near = dl, -v, -a
                h_est = _quadratic_time(d_near, u_near, a_near)
                H_new = min(max(3.0 * h_near, 1e-300), H_MAX)
                t_next = ta + h_near
                # no root predicted in the window: go straight on to ta + h_near
                move = not (math.isfinite(h_est) and h_est < wdw) and (t_next > ta)
            if move:
                if t_next > t_max:
                    return n, ESCAPED, nstick, evals
                if it >= max_steps:
                    return n, FAILED, nstick, evals
                ta = t_next
                H = H_new
                ds, v, a, e, _, _ = _flight(ta, sn0, cs0, v0, alpha, beta, gamma)
                evals += 1
                b = bc * e
                continue
            # bracket test at t_b (mapimpl.finder.bracket_test)
            slope = max(u_near + a_near * h_est, 1e-300)
            h_try = h_est + 2.0 * (m3 * h_est * h_est * h_est / 6.0) / slope + 4.0 * EPS * (ta + h_est)
            w_b = min(wdw, h_try) if (math.isfinite(h_try) and h_try > 0.0) else wdw
            tb = ta + w_b
            v_a = v
            dsb, vb, ab, eb, sb, cb = _flight(tb, sn0, cs0, v0, alpha, beta, gamma)
            evals += 1
            if top_near:
                g_b, dg_b = -s0 - dsb, -vb
            else:
                g_b, dg_b = (s0 + 1.0) + dsb, vb
            bracket = (g_b <= 0.0) and _bracket_unique(v_a, a, vb, ab, m2, m3, tb - ta)
            if not bracket:
                if ta + h_near <= ta:  # stalled: a graze at ta
                    t_hit, v_hit, top_hit = ta, v_a, top_near
                    break
                t_new = ta + h_near
                if t_new > t_max:
                    return n, ESCAPED, nstick, evals
                if it >= max_steps:
                    return n, FAILED, nstick, evals
                ta = t_new
                H = H_new
                ds, v, a, e, _, _ = _flight(ta, sn0, cs0, v0, alpha, beta, gamma)
                evals += 1
                b = bc * e
                continue
            # safeguarded root iteration on [ta, tb] (mapimpl.finder.root_step), from tb with its evaluation;
            # derivative bounds at ta (valid for all later times)
            x, g, dg, d2g, vx, ax, sx, cx = tb, g_b, dg_b, (-ab if top_near else ab), vb, ab, sb, cb
            lo, hi, top, k = ta, tb, top_near, 0
            while True:
                if g > 0.0:
                    lo = x
                else:
                    hi = x
                disc = dg * dg - 2.0 * g * d2g
                model = disc >= 0.0
                if model:
                    raw = x - 2.0 * g / (dg + math.copysign(math.sqrt(disc), 1.0 if dg >= 0.0 else -1.0))
                else:
                    raw = x - g / dg
                fin = math.isfinite(raw)
                tiny = fin and abs(raw - x) <= 2.0 * EPS * abs(x)
                ok = fin and raw > lo and raw < hi
                if ok:
                    xn = raw
                elif tiny:
                    xn = x
                else:
                    xn = 0.5 * (lo + hi)
                step = abs(xn - x)
                small = m3 * step * step * step * (1.0 / 6.0) if model else 0.5 * m2 * step * step
                bound_ok = ok and (small <= 5e-4 * EPS * abs(dg) * abs(xn))
                k += 1
                conv = (
                    (g == 0.0)
                    or tiny
                    or (step <= 2.0 * EPS * abs(x))
                    or (hi - lo <= 2.0 * EPS * hi)
                    or bound_ok
                    or k >= NEWTON_ITERS
                )
                if g == 0.0:
                    xn = x
                if conv:
                    # the velocity at the root, to second order from the last evaluation (the engine's)
                    dx = xn - x
                    jerk = _forcing_rate(sx, cx, alpha, beta) - beta * ax
                    t_hit, v_hit, top_hit = xn, vx + ax * dx + jerk * 0.5 * dx * dx, top
                    break
                x = xn
                dsx, vx, ax, ex, sx, cx = _flight(x, sn0, cs0, v0, alpha, beta, gamma)
                evals += 1
                if top:
                    g, dg, d2g = -s0 - dsx, -vx, -ax
                else:
                    g, dg, d2g = (s0 + 1.0) + dsx, vx, ax
            break
        # ---------------- the impact: next pre-impact state ----------------
        th1 = _reduce(th0 + t_hit)
        v1 = v_hit
        wall1 = 0 if top_hit else -1
        n += 1


@njit(parallel=True, **_JIT)
def _run(
    theta0,
    sdot0,
    alpha,
    beta,
    gamma,
    r,
    po_th,
    po_v,
    po_w,
    deltas,
    cap,
    stick_time,
    t_max,
    max_steps,
    rel_th,
    rel_sn,
    rel_cs,
    rel_never,
    out_n,
    out_status,
    out_nstick,
    out_hit,
    out_evals,
):
    m = theta0.shape[0]
    for i in prange(m):
        n, st, ns, ev = _orbit(
            _reduce(theta0[i]),
            sdot0[i],
            alpha,
            beta,
            gamma,
            r,
            po_th,
            po_v,
            po_w,
            deltas,
            out_hit[i],
            cap,
            stick_time,
            t_max,
            max_steps,
            rel_th,
            rel_sn,
            rel_cs,
            rel_never,
        )
        out_n[i] = n
        out_status[i] = st
        out_nstick[i] = ns
        out_evals[i] = ev


# ------------------------------------------------------------------------------ Python entry point


def release_phases(alpha: float, beta: float, gamma: float) -> tuple[np.ndarray, np.ndarray]:
    """Canonical release phase of each wall (index 0: s = 0, 1: s = -1) and whether the tooth never
    leaves it, as ``mapimpl.sticking.release_phase``: the contact force ``gamma - R sin(tau - phi)``
    stops pressing into the upper wall at ``phi + asin(gamma/R)`` and into the lower one at
    ``phi + pi - asin(gamma/R)`` (mod 2 pi)."""
    R = alpha * math.sqrt(1.0 + beta * beta)
    phi = math.atan(beta)
    c = gamma / (R if R > 0.0 else 1.0)
    cc = min(max(c, -1.0), 1.0)
    phase = np.array([_reduce(phi + math.asin(cc)), _reduce(phi + (math.pi - math.asin(cc)))])
    never = np.array([R <= 0.0 or c >= 1.0, R <= 0.0 or -c >= 1.0])
    return phase, never


def numba_transients(
    theta0,
    sdot0,
    params,
    target_theta,
    target_sdot,
    target_wall,
    deltas,
    cap: int,
    stick_time: float = STICK_TIME,
    chunksize: int = 16,
    release=None,
) -> dict:
    """Transient durations of the pre-impact initial states ``(theta0[i], sdot0[i])`` (``sdot0 > 0``
    hits ``s = 0``): the first iteration within each of ``deltas`` (sorted largest first) of the periodic
    orbit ``(target_theta, target_sdot, target_wall)``, at most ``cap`` iterations.

    ``params``: anything with ``alpha, beta, gamma, r`` attributes.  ``chunksize``: initial conditions
    per dynamically scheduled ``prange`` chunk.  ``release``: ``(phase[2], never[2])`` to override
    :func:`release_phases`.  Returns a dict of numpy arrays ``n``, ``status``, ``nstick``, ``hit``
    (shape ``(N, len(deltas))``), ``evals`` (flight evaluations per orbit), like :class:`~gear_rattle.mapimpl.engine.transients.TransientResult`.
    """
    theta0 = np.ascontiguousarray(np.ravel(theta0), dtype=np.float64)
    sdot0 = np.ascontiguousarray(np.ravel(sdot0), dtype=np.float64)
    if theta0.shape != sdot0.shape:
        raise ValueError(f"theta0 and sdot0 must have the same length (got {theta0.size} and {sdot0.size})")
    if np.any(sdot0 == 0.0) or not np.all(np.isfinite(sdot0)) or not np.all(np.isfinite(theta0)):
        raise ValueError("sdot0 is out of range: allowed finite pre-impact velocities sdot0 != 0")
    deltas = np.asarray(sorted((float(d) for d in np.ravel(deltas)), reverse=True), dtype=np.float64)
    if int(cap) != cap or not 1 <= int(cap) <= 10**8:
        raise ValueError(f"cap={cap!r} is out of range: allowed integer 1 <= cap <= 1e8")
    a, b, g, r = (float(params.alpha), float(params.beta), float(params.gamma), float(params.r))
    rel_th, rel_never = release_phases(a, b, g) if release is None else (np.asarray(x) for x in release)
    rel_th = np.asarray(rel_th, dtype=np.float64)
    rel_sn = np.array([math.sin(x) for x in rel_th])
    rel_cs = np.array([math.cos(x) for x in rel_th])
    m = theta0.size
    out = dict(
        n=np.zeros(m, np.int32),
        status=np.zeros(m, np.int32),
        nstick=np.zeros(m, np.int32),
        hit=np.full((m, deltas.size), -1, np.int32),
        evals=np.zeros(m, np.int64),
    )
    with numba.parallel_chunksize(int(chunksize)):
        _run(
            theta0,
            sdot0,
            a,
            b,
            g,
            r,
            np.asarray(target_theta, np.float64),
            np.asarray(target_sdot, np.float64),
            np.asarray(target_wall, np.int64),
            deltas,
            int(cap),
            float(stick_time),
            T_MAX,
            MAX_STEPS,
            rel_th,
            rel_sn,
            rel_cs,
            np.asarray(rel_never, dtype=np.bool_),
            out["n"],
            out["status"],
            out["nstick"],
            out["hit"],
            out["evals"],
        )
    out["deltas"] = deltas
    return out
