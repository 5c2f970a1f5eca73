"""Certified first-impact finder: the first flight time ``t > 0`` at which ``s`` reaches 0 or -1.

Method (never skips a crossing, never stops on an absolute gap tolerance):

1. **Safe steps.**  At a flight time ``t_a`` the gap ``d`` to each wall, the velocity ``u`` toward it
   and a bound ``A`` on the acceleration toward it over a window ``[t_a, t_a + H]`` are known:
   ``A = min(a_toward(t_a) + M3 H, M2)`` with ``M2 >= |s''|``, ``M3 >= |s'''|`` from
   :func:`mapimpl.flight.derivative_bounds`.  Then ``gap(t_a + h) >= d - u h - A h^2 / 2``, so no
   wall can be reached for ``h < safe_time(d, u, A)`` (smallest positive root).  Stepping by the
   smaller safe time of the two walls is certified.
2. **Certified bracket.**  Each step also looks at ``t_b = t_a + min(2 h_near, h_far, H)``.  If the
   near wall is crossed at ``t_b`` *and* either the velocity or the acceleration provably keeps its
   sign on ``[t_a, t_b]`` (bounds again), the gap is monotone or convex/concave there, so the bracket
   holds exactly one root, and no earlier root exists (step 1).  A safeguarded Newton iteration then
   finds it to a few ulps.
3. **Start on a wall.**  A flight that starts on a wall (gap exactly 0, see :mod:`mapimpl.flight`)
   first gets a departure certificate ``[0, t_dep]`` during which it provably cannot return
   (Taylor bounds of order 2, 3 or 4, so it also covers a release from sticking with
   ``sdot0 = 0`` and ``s'' = 0``).  Its own start is never re-detected and there is no 0/0.
4. **Termination.**  A safe step below one ulp of ``t_a`` means the orbit touches the wall to within
   rounding (a grazing contact with zero normal velocity): it is reported as an impact there
   (status ``GRAZE``).  Flights longer than ``t_max`` (status ``NO_IMPACT``: the orbit never reaches
   a wall, e.g. small ``alpha`` and ``gamma``) and more than ``max_steps`` iterations (status
   ``STEP_CAP``) end the search.  Every loop is bounded.

All code is branch-free ``jax.numpy`` inside ``lax.while_loop`` so it jit-compiles and vmaps.
"""

from __future__ import annotations

from typing import NamedTuple

from mapimpl import _jax  # noqa: F401
import jax
import jax.numpy as jnp

from mapimpl.flight import derivative_bounds, flight, forcing_rate

#: Status codes of a flight search.
HIT, GRAZE, NO_IMPACT, STEP_CAP = 0, 1, 2, 3
STATUS_NAMES = {HIT: "hit", GRAZE: "graze", NO_IMPACT: "no_impact", STEP_CAP: "step_cap"}

#: Longest flight searched (in units of tau) before giving up with NO_IMPACT.
T_MAX = 2000.0
#: Most safe-step iterations per flight before giving up with STEP_CAP.
MAX_STEPS = 4000
_H0, _H_MAX = 0.5, 2.0
_EPS = 2.220446049250313e-16
_NEWTON_ITERS = 80


class Hit(NamedTuple):
    """Result of :func:`first_impact`.

    ``t``: flight time to the impact; ``wall``: 0 (upper, ``s = 0``) or -1 (lower, ``s = -1``);
    ``v``: velocity just before the impact; ``status``: HIT/GRAZE/NO_IMPACT/STEP_CAP;
    ``steps``: safe-step iterations used (diagnostic).
    """

    t: jnp.ndarray
    wall: jnp.ndarray
    v: jnp.ndarray
    status: jnp.ndarray
    steps: jnp.ndarray


def safe_time(d, u, A):
    """Smallest ``h > 0`` with ``d - u h - A h^2/2 = 0`` (``+inf`` if none).

    ``d >= 0`` is the gap to a wall, ``u`` the velocity toward it and ``A`` an upper bound of the
    acceleration toward it; before that time the wall provably cannot be reached.
    """
    inf = jnp.inf
    disc = u * u + 2.0 * A * d
    root = jnp.sqrt(jnp.maximum(disc, 0.0))
    # approaching: stable form 2d / (u + sqrt(disc)); receding with A > 0: (-u + sqrt(disc)) / A
    approach = jnp.where(disc >= 0.0, 2.0 * d / (u + root), inf)
    recede = jnp.where(A > 0.0, (root - u) / jnp.where(A > 0.0, A, 1.0), inf)
    return jnp.where(u > 0.0, approach, recede)


def _gaps(s0, ds):
    """Gaps to the upper and lower wall; exact (= ds) for the wall the flight starts on."""
    return -s0 - ds, (s0 + 1.0) + ds


def departure_time(tau0, s0, v0, alpha, beta, gamma):
    """Length of an interval ``[0, t_dep]`` in which a flight starting on a wall cannot return to it.

    Zero when the start is not on a wall or nothing can be certified (moving into the wall, or at
    rest and pressed into it).  Taylor bounds: ``u t + A t^2/2`` (moving away), ``a t^2/2 + M3 t^3/6``
    (at rest, pulled away), ``j t^3/6 + M4 t^4/24`` (release point, ``a = 0``, ``j`` pulls away).
    """
    on_top, on_bot = s0 == 0.0, s0 == -1.0
    sgn = jnp.where(on_top, 1.0, -1.0)  # direction toward the start wall
    fp = flight(jnp.zeros_like(v0), tau0, v0, alpha, beta, gamma)
    m2, m3, m4 = derivative_bounds(0.0, tau0, v0, alpha, beta, gamma)
    u, a = sgn * v0, sgn * fp.a
    j = sgn * (forcing_rate(tau0, alpha, beta) - beta * fp.a)
    # at a release the contact force is zero only to rounding: treat |a| at rounding level as 0
    a_tol = 32.0 * _EPS * (alpha * (1.0 + beta) + jnp.abs(gamma) + beta * jnp.abs(v0))
    a = jnp.where(jnp.abs(a) <= a_tol, 0.0, a)
    tiny = 1e-300
    c1 = jnp.where(u < 0.0, 2.0 * (-u) / jnp.maximum(m2, tiny), 0.0)
    c2 = jnp.where((u <= 0.0) & (a < 0.0), 1.5 * (-a) / jnp.maximum(m3, tiny), 0.0)
    c3 = jnp.where((u <= 0.0) & (a <= 0.0) & (j < 0.0), 2.0 * (-j) / jnp.maximum(m4, tiny), 0.0)
    return jnp.where(on_top | on_bot, 0.5 * jnp.maximum(c1, jnp.maximum(c2, c3)), 0.0)


def first_impact(tau0, s0, v0, alpha, beta, gamma, t_max=T_MAX, max_steps=MAX_STEPS) -> Hit:
    """First impact of the flight leaving ``(tau0, s0, v0)``, ``-1 <= s0 <= 0`` (scalar inputs).

    ``tau0`` should be reduced mod 2*pi; the returned ``t`` is the flight time.  Use ``jax.vmap``
    for batches.  See the module docstring for the method and the status codes.
    """
    tau0, s0, v0 = (jnp.asarray(x, jnp.float64) for x in (tau0, s0, v0))
    t_dep = departure_time(tau0, s0, v0, alpha, beta, gamma)
    on_top, on_bot = s0 == 0.0, s0 == -1.0

    def gap_of(t, wall_top):
        fp = flight(t, tau0, v0, alpha, beta, gamma)
        du, dl = _gaps(s0, fp.ds)
        return jnp.where(wall_top, du, dl), jnp.where(wall_top, -fp.v, fp.v)

    # ---- phase 1: certified safe stepping until a bracket [lo, hi] with one root ----
    def cond(c):
        return ~c["done"]

    def body(c):
        t_a, H = c["t"], c["H"]
        fp = flight(t_a, tau0, v0, alpha, beta, gamma)
        m2, m3, _ = derivative_bounds(t_a, tau0, v0, alpha, beta, gamma)
        du, dl = _gaps(s0, fp.ds)
        du, dl = jnp.maximum(du, 0.0), jnp.maximum(dl, 0.0)
        hu = safe_time(du, fp.v, jnp.minimum(fp.a + m3 * H, m2))
        hl = safe_time(dl, -fp.v, jnp.minimum(-fp.a + m3 * H, m2))
        rem = t_dep - t_a
        hu = jnp.where(on_top & (rem > 0.0), jnp.maximum(hu, rem), hu)
        hl = jnp.where(on_bot & (rem > 0.0), jnp.maximum(hl, rem), hl)
        top_near = hu <= hl
        h_near = jnp.minimum(hu, hl)
        h_far = jnp.maximum(hu, hl)
        windowed = h_near >= H
        # certified bracket test
        w = jnp.minimum(jnp.minimum(2.0 * h_near, h_far), H)
        t_b = t_a + w
        g_b, _ = gap_of(t_b, top_near)
        amax = jnp.minimum(jnp.abs(fp.a) + m3 * w, m2)
        unique = (jnp.abs(fp.v) > amax * w) | (jnp.abs(fp.a) > m3 * w)
        bracket = (~windowed) & (g_b <= 0.0) & unique
        # no progress possible: touching the wall to within rounding
        stalled = (~windowed) & (~bracket) & (t_a + h_near <= t_a)
        step = jnp.where(windowed, H, h_near)
        t_new = jnp.where(bracket | stalled, t_a, t_a + step)
        H_new = jnp.where(windowed, jnp.minimum(2.0 * H, _H_MAX), jnp.clip(3.0 * h_near, 1e-300, _H_MAX))
        it = c["it"] + 1
        beyond = t_new > t_max
        capped = it >= max_steps
        status = jnp.where(bracket, HIT, jnp.where(stalled, GRAZE, jnp.where(beyond, NO_IMPACT, STEP_CAP)))
        done = bracket | stalled | beyond | capped
        return dict(
            t=t_new, H=H_new, it=it, done=done, hi=jnp.where(bracket, t_b, t_new),
            top=jnp.where(bracket | stalled, top_near, c["top"]), status=status,
        )

    init = dict(
        t=jnp.zeros_like(v0), H=jnp.asarray(_H0, jnp.float64), it=jnp.asarray(0, jnp.int32),
        done=jnp.asarray(False), hi=jnp.zeros_like(v0), top=jnp.asarray(True), status=jnp.asarray(STEP_CAP),
    )
    c = jax.lax.while_loop(cond, body, init)
    lo, hi, top, status = c["t"], c["hi"], c["top"], c["status"]

    # ---- phase 2: safeguarded Newton on the bracket (exactly one root inside) ----
    def ncond(n):
        return (~n["conv"]) & (n["k"] < _NEWTON_ITERS)

    def nbody(n):
        x = n["x"]
        g, dg = gap_of(x, top)
        lo_n = jnp.where(g > 0.0, x, n["lo"])
        hi_n = jnp.where(g > 0.0, n["hi"], x)
        dx = -g / dg
        # converged when the Newton correction is below rounding: checked before the bracket
        # safeguard, which would otherwise reject a sub-ulp step and fall back to bisection
        landed = (g == 0.0) | (jnp.isfinite(dx) & (jnp.abs(dx) <= 2.0 * _EPS * jnp.abs(x)))
        xn = x + dx
        ok = jnp.isfinite(xn) & (xn > lo_n) & (xn < hi_n)
        xn = jnp.where(ok, xn, 0.5 * (lo_n + hi_n))
        conv = landed | (jnp.abs(xn - x) <= 2.0 * _EPS * jnp.abs(x)) | (hi_n - lo_n <= 2.0 * _EPS * hi_n)
        xn = jnp.where(landed, x, xn)
        return dict(x=xn, lo=lo_n, hi=hi_n, conv=conv, k=n["k"] + 1)

    need = status == HIT
    n0 = dict(x=0.5 * (lo + hi), lo=lo, hi=hi, conv=~need, k=jnp.asarray(0, jnp.int32))
    n = jax.lax.while_loop(ncond, nbody, n0)
    t_hit = jnp.where(need, n["x"], lo)
    ok = (status == HIT) | (status == GRAZE)
    v_hit = flight(t_hit, tau0, v0, alpha, beta, gamma).v
    wall = jnp.where(top, 0, -1).astype(jnp.int32)
    return Hit(
        t=jnp.where(ok, t_hit, jnp.inf), wall=wall, v=jnp.where(ok, v_hit, jnp.nan),
        status=status.astype(jnp.int32), steps=c["it"],
    )
