"""Certified first-impact finder: the first flight time ``t > 0`` at which ``s`` reaches 0 or -1.

Method (never skips a crossing, never stops on an absolute gap tolerance):

1. **Safe steps.**  At a flight time ``t_a`` the gap ``d`` to each wall, the velocity ``u`` toward it
   and a bound ``A`` on the acceleration toward it over a window ``[t_a, t_a + H]`` are known:
   ``A = min(a_toward(t_a) + M3 H, M2)`` with ``M2 >= |s''|``, ``M3 >= |s'''|`` from
   :func:`mapimpl.flight.derivative_bounds`.  Then ``gap(t_a + h) >= d - u h - A h^2 / 2``, so no
   wall can be reached for ``h < safe_time(d, u, A)`` (smallest positive root).  Stepping by the
   smaller safe time of the two walls is certified.
2. **Certified bracket.**  A step that is not a full window ``H`` looks at a point ``t_b`` in
   ``(t_a, t_a + w]``, ``w = min(2 h_near, h_far, H)``: just past the root that the local quadratic
   predicts (else ``t_a + w``).  If the near wall is crossed at ``t_b`` *and* either the velocity or
   the acceleration provably keeps its sign on ``[t_a, t_b]`` (bounds again, applied from both ends:
   :func:`bracket_unique`), the gap is monotone or convex/concave there, so the bracket ``[t_a, t_b]``
   holds exactly one root, and no earlier root exists (step 1; the far wall is not reached before
   ``t_a + w``).  A safeguarded iteration on the local quadratic model (:func:`root_step`: the
   evaluations give ``s''`` too), started at ``t_b``, finds it to a few ulps.  When the quadratic
   predicts no root inside the window the test is skipped: a failed test would continue at
   ``t_a + h_near``, which is where the step goes.
3. **Start on a wall.**  A flight that starts on a wall (gap exactly 0, see :mod:`mapimpl.flight`)
   first gets a departure certificate ``[0, t_dep]`` during which it provably cannot return
   (Taylor bounds of order 2, 3 or 4, so it also covers a release from sticking with
   ``sdot0 = 0`` and ``s'' = 0``).  Its own start is never re-detected and there is no 0/0.
4. **Termination.**  A safe step below one ulp of ``t_a`` means the orbit touches the wall to within
   rounding (a grazing contact with zero normal velocity): it is reported as an impact there
   (status ``GRAZE``).  Flights longer than ``t_max`` (status ``NO_IMPACT``: the orbit never reaches
   a wall, e.g. small ``alpha`` and ``gamma``) and more than ``max_steps`` iterations (status
   ``STEP_CAP``) end the search.  Every loop is bounded.

All code is branch-free ``jax.numpy`` inside ``lax.while_loop`` so it jit-compiles and vmaps.  The
decisions :func:`safe_step`, :func:`bracket_unique`, :func:`bracket_test` and :func:`root_step` and the
departure certificate :func:`departure_time_sc` are the one implementation of the method: the many-orbit
engine's kernel (:mod:`mapimpl.engine.kernel`) calls the same functions.
"""

from __future__ import annotations

from typing import NamedTuple

from ..core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from .flight import derivative_bounds, flight
from .forcing import forcing_rate_sc, forcing_sc
from ..core.status import FlightOutcome
from ..core.checks import check_int, check_real, check_tau0, is_traced
from ..core.params import check_param
from ..core.horizons import T_MAX  # the orbit horizon: NO_IMPACT beyond it (every track's rule)


#: Most safe-step iterations per flight before giving up with STEP_CAP.
MAX_STEPS = 4000
#: The first safe step's window (time units); the window grows to at most ``_H_MAX``.
H0, _H_MAX = 0.5, 2.0
_EPS = 2.220446049250313e-16
#: Most safeguarded root iterations on a certified bracket (:func:`root_step`).
NEWTON_ITERS = 80


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


def quadratic_time(d, u, a):
    """Smallest ``h > 0`` with ``d - u h - a h^2/2 = 0`` (``+inf`` if none), in the rounding-stable
    forms, without guarding against underflow: the estimate of a root (``safe_step``'s test point);
    :func:`safe_time` is the certified bound.

    ``d >= 0``: a gap to a wall; ``u``: the velocity toward it; ``a``: the acceleration toward it.
    Returns ``(h, disc, none)``: the root, the discriminant ``u^2 + 2 a d`` and where no root exists
    (the last two for :func:`safe_time`'s guard).
    """
    disc = u * u + 2.0 * a * d
    root = jnp.sqrt(jnp.maximum(disc, 0.0))
    # approaching: stable form 2d / (u + sqrt(disc)); receding with a > 0: (-u + sqrt(disc)) / a (one
    # division of the selected operands; +inf where no root exists)
    approach = u > 0.0
    num = jnp.where(approach, 2.0 * d, root - u)
    den = jnp.where(approach, u + root, jnp.where(a > 0.0, a, 1.0))
    none = jnp.where(approach, jnp.logical_not(disc >= 0.0), jnp.logical_not(a > 0.0))
    return jnp.where(none, jnp.inf, num / den), disc, none


def safe_time(d, u, A):
    """Smallest ``h > 0`` with ``d - u h - A h^2/2 = 0`` (``+inf`` if none).

    ``d >= 0`` is the gap to a wall, ``u`` the velocity toward it and ``A`` an upper bound of the
    acceleration toward it; before that time the wall provably cannot be reached.  The root of
    :func:`quadratic_time`, kept a lower bound where ``u^2 + 2 A d`` underflows.
    """
    h, disc, none = quadratic_time(d, u, A)
    # where u^2 + 2 A d underflows (|u| and A d near the smallest normal numbers, e.g. alpha ~ 1e-308)
    # the forms above lose the 2 A d term: receding, they would give 0 -- a false graze -- and
    # approaching, more than the root.  Lower bounds without the underflow there (they hold
    # everywhere: sqrt(u^2 + 2 A d) <= |u| + sqrt(2 A) sqrt(d)); elsewhere h is unchanged, bit for bit.
    tiny = disc < 1e-290
    sq = jnp.sqrt(2.0 * jnp.maximum(A, 0.0)) * jnp.sqrt(d)
    h_tiny = jnp.where(u > 0.0, 2.0 * d / (2.0 * u + sq), jnp.maximum(h, sq / jnp.where(A > 0.0, A, 1.0)))
    return jnp.where(tiny & ~none, h_tiny, h)


def wall_gaps(s0, ds):
    """Gaps to the upper and lower wall; exact (= ds) for the wall the flight starts on."""
    return -s0 - ds, (s0 + 1.0) + ds


def departure_time_sc(sin0, cos0, s0, v0, alpha, beta, gamma):
    """Length of an interval ``[0, t_dep]`` in which a flight starting on a wall cannot return to it
    (``sin0, cos0``: sin and cos of the start phase).

    Zero when the start is not on a wall or nothing can be certified (moving into the wall, or at
    rest and pressed into it).  Taylor bounds: ``u t + A t^2/2`` (moving away), ``a t^2/2 + M3 t^3/6``
    (at rest, pulled away), ``j t^3/6 + M4 t^4/24`` (release point, ``a = 0``, ``j`` pulls away), with
    ``M2, M3, M4`` of :func:`mapimpl.flight.derivative_bounds` at ``t = 0``.
    """
    on_top, on_bot = s0 == 0.0, s0 == -1.0
    sgn = jnp.where(on_top, 1.0, -1.0)  # direction toward the start wall
    a0 = forcing_sc(sin0, cos0, alpha, beta, gamma) - beta * v0  # Eq. (3) at t = 0
    bc = jnp.abs(beta * (v0 - alpha * cos0) - gamma)
    m2, m3, m4 = alpha + bc, alpha + beta * bc, alpha + beta * beta * bc
    u, a = sgn * v0, sgn * a0
    j = sgn * (forcing_rate_sc(sin0, cos0, alpha, beta) - beta * a0)
    # at a release the contact force is zero only to rounding: treat |a| at rounding level as 0
    a_tol = 32.0 * _EPS * (alpha * (1.0 + beta) + jnp.abs(gamma) + beta * jnp.abs(v0))
    a = jnp.where(jnp.abs(a) <= a_tol, 0.0, a)
    tiny = 1e-300
    c1 = jnp.where(u < 0.0, 2.0 * (-u) / jnp.maximum(m2, tiny), 0.0)
    c2 = jnp.where((u <= 0.0) & (a < 0.0), 1.5 * (-a) / jnp.maximum(m3, tiny), 0.0)
    c3 = jnp.where((u <= 0.0) & (a <= 0.0) & (j < 0.0), 2.0 * (-j) / jnp.maximum(m4, tiny), 0.0)
    return jnp.where(on_top | on_bot, 0.5 * jnp.maximum(c1, jnp.maximum(c2, c3)), 0.0)


def departure_time(tau0, s0, v0, alpha, beta, gamma):
    """:func:`departure_time_sc` at the start phase ``tau0``."""
    return departure_time_sc(jnp.sin(tau0), jnp.cos(tau0), s0, v0, alpha, beta, gamma)


class SafeStep(NamedTuple):
    """Result of :func:`safe_step`.

    ``move``: go on to ``t_next`` with window ``H_new`` (a full window, or straight on to
    ``t_a + h_near`` when no root is predicted inside the window); ``beyond`` / ``capped``: that move
    passes ``t_max`` / uses up ``max_steps``.  Otherwise test the near wall (``top_near``) at ``t_b``
    with :func:`bracket_unique` and :func:`bracket_test`.  ``it``: steps used including this one.
    """

    move: jnp.ndarray
    t_next: jnp.ndarray
    H_new: jnp.ndarray
    beyond: jnp.ndarray
    capped: jnp.ndarray
    it: jnp.ndarray
    top_near: jnp.ndarray
    h_near: jnp.ndarray
    t_b: jnp.ndarray


def safe_step(ds, v, a, m2, m3, t_a, H, it, t_dep, s0, t_max, max_steps) -> SafeStep:
    """One certified safe step (method, steps 1-2) from the flight state at ``t_a``.

    ``ds, v, a``: displacement from ``s0``, velocity and acceleration at ``t_a`` (Eqs. 7-8 and
    Eq. 3); ``m2, m3``: bounds of ``|s''|``, ``|s'''|`` for times ``>= t_a``; ``H``: the current window;
    ``it``: steps so far; ``t_dep``: departure certificate of the flight.
    """
    du, dl = wall_gaps(s0, ds)
    on_top, on_bot = s0 == 0.0, s0 == -1.0
    du, dl = jnp.maximum(du, 0.0), jnp.maximum(dl, 0.0)
    hu = safe_time(du, v, jnp.minimum(a + m3 * H, m2))
    hl = safe_time(dl, -v, jnp.minimum(-a + m3 * H, m2))
    rem = t_dep - t_a
    hu = jnp.where(on_top & (rem > 0.0), jnp.maximum(hu, rem), hu)
    hl = jnp.where(on_bot & (rem > 0.0), jnp.maximum(hl, rem), hl)
    top_near = hu <= hl
    h_near = jnp.minimum(hu, hl)
    h_far = jnp.maximum(hu, hl)
    windowed = h_near >= H
    w = jnp.minimum(jnp.minimum(2.0 * h_near, h_far), H)
    # test point: just past the root predicted by the local quadratic (Taylor error <= M3 h^3/6),
    # inside [t_a, t_a + w] (no other wall before it); on a bracket the test's evaluation starts the root
    # iteration
    d_near = jnp.where(top_near, du, dl)
    u_near = jnp.where(top_near, v, -v)
    a_near = jnp.where(top_near, a, -a)
    h_est = quadratic_time(d_near, u_near, a_near)[0]  # an estimate: no underflow guard needed
    slope = jnp.maximum(u_near + a_near * h_est, 1e-300)
    h_try = h_est + 2.0 * (m3 * h_est * h_est * h_est / 6.0) / slope + 4.0 * _EPS * (t_a + h_est)
    w_b = jnp.where(jnp.isfinite(h_try) & (h_try > 0.0), jnp.minimum(w, h_try), w)
    # no root predicted inside the window: a test at its end would almost surely fail, and a failed
    # test continues at t_a + h_near anyway, so go there at once (same certificate, one evaluation less)
    skip_test = ~windowed & ~(jnp.isfinite(h_est) & (h_est < w)) & (t_a + h_near > t_a)
    H_new = jnp.where(windowed, jnp.minimum(2.0 * H, _H_MAX), jnp.clip(3.0 * h_near, 1e-300, _H_MAX))
    it_new = it + 1
    t_next = jnp.where(windowed, t_a + H, t_a + h_near)
    return SafeStep(
        move=windowed | skip_test,
        t_next=t_next,
        H_new=H_new,
        beyond=t_next > t_max,
        capped=it_new >= max_steps,
        it=it_new,
        top_near=top_near,
        h_near=h_near,
        t_b=t_a + w_b,
    )


def bracket_unique(v_a, a_a, v_b, a_b, m2, m3, ell):
    """Whether the gap to a wall is monotone or convex/concave on a test interval ``[t_a, t_b]`` of
    length ``ell = t_b - t_a`` (as computed: within an ulp of the represented interval), so that a sign
    change across it is exactly one root (method, step 2).

    ``v, a``: velocity and acceleration at both ends; ``m2 >= |s''|``, ``m3 >= |s'''|`` for times
    ``>= t_a``.  The velocity keeps its sign if it has the same sign at both ends and
    ``|v_a| + |v_b| > A ell`` with ``A = min(|a_a| + m3 ell, |a_b| + m3 ell, m2) >= |s''|`` on the
    interval (``v`` lies above both lines ``v_a - A (t - t_a)`` and ``v_b - A (t_b - t)``, whose
    maximum is at least ``(|v_a| + |v_b| - A ell) / 2``); likewise the acceleration with ``m3``.  Bounds
    from both ends certify about twice as long intervals as bounds from ``t_a`` alone."""
    A = jnp.minimum(jnp.minimum(jnp.abs(a_a), jnp.abs(a_b)) + m3 * ell, m2)
    keep_v = (v_a * v_b > 0.0) & (jnp.abs(v_a) + jnp.abs(v_b) > A * ell)
    keep_a = (a_a * a_b > 0.0) & (jnp.abs(a_a) + jnp.abs(a_b) > m3 * ell)
    return keep_v | keep_a


def bracket_test(g_b, t_a, h_near, unique):
    """Method, step 2: the gap ``g_b`` to the near wall at the test point ``t_b``.

    Returns ``(bracket, stalled)``: whether ``[t_a, t_b]`` holds exactly one root (``unique``:
    :func:`bracket_unique`); whether no progress is possible (a safe step below one ulp of ``t_a``: a
    graze at ``t_a``).  Neither: go on to ``t_a + h_near``.  On a bracket the root iteration
    (:func:`root_step`) starts from ``t_b`` with this evaluation.
    """
    bracket = (g_b <= 0.0) & unique
    stalled = (~bracket) & (t_a + h_near <= t_a)
    return bracket, stalled


def root_step(x, g, dg, d2g, lo, hi, m2, m3, k):
    """One safeguarded root iteration on a certified bracket ``[lo, hi]`` (method, step 2).

    ``g, dg, d2g``: gap and its first two derivatives at ``x`` (``d2g = -+ s''``, known from the same
    evaluation); ``m2 >= |g''|``, ``m3 >= |g'''|`` on the bracket; ``k``: iterations so far.  The step
    goes to the zero of the local quadratic model ``g + dg d + d2g d^2/2`` nearest ``x`` (Newton's step
    where the model has none) when that lies inside the bracket, else bisects.  Returns
    ``(x_new, lo, hi, done, k + 1)``; ``done`` when ``x_new`` is the root to rounding: ``x`` itself, or a
    point whose error, at most ``m3 d^3 / (6 |dg|)`` after a model step (``m2 d^2 / (2 |dg|)`` after a
    Newton step), is far below an ulp -- it is accepted without evaluating there -- or after
    ``NEWTON_ITERS`` iterations.  Near a transversal root the error goes from ``e`` to
    ``~ e^3 m3 / |dg|`` per step: one evaluation past a good start suffices.
    """
    lo_n = jnp.where(g > 0.0, x, lo)
    hi_n = jnp.where(g > 0.0, hi, x)
    disc = dg * dg - 2.0 * g * d2g
    model = disc >= 0.0
    # stable form of the model's nearer zero, -2 g / (dg + sgn(dg) sqrt(disc)); one division of the
    # selected operands
    den = dg + jnp.where(dg >= 0.0, 1.0, -1.0) * jnp.sqrt(jnp.maximum(disc, 0.0))
    raw = x + jnp.where(model, -2.0 * g, -g) / jnp.where(model, den, dg)
    # a step below 2 ulp means x is the root to rounding (checked before the bracket safeguard, which
    # would reject the step raw == x == hi that rounding produces there and bisect ~50 times)
    tiny = jnp.isfinite(raw) & (jnp.abs(raw - x) <= 2.0 * _EPS * jnp.abs(x))
    ok = jnp.isfinite(raw) & (raw > lo_n) & (raw < hi_n)
    xn = jnp.where(ok, raw, jnp.where(tiny, x, 0.5 * (lo_n + hi_n)))
    step = jnp.abs(xn - x)
    # accept without another evaluation when the error bound is far below an ulp of the root
    small = jnp.where(model, m3 * step * step * step * (1.0 / 6.0), 0.5 * m2 * step * step)
    bound_ok = ok & (small <= 5e-4 * _EPS * jnp.abs(dg) * jnp.abs(xn))
    conv = (g == 0.0) | tiny | (step <= 2.0 * _EPS * jnp.abs(x)) | (hi_n - lo_n <= 2.0 * _EPS * hi_n) | bound_ok
    xn = jnp.where(g == 0.0, x, xn)
    k_new = k + 1
    return xn, lo_n, hi_n, conv | (k_new >= NEWTON_ITERS), k_new


def check_flight(tau0, s0, v0, alpha, beta, gamma, t_max=T_MAX, max_steps=MAX_STEPS) -> None:
    """The arguments of :func:`first_impact` called with concrete values (:mod:`core.checks`):
    ``|tau0| <= 1e6``, ``-1 <= s0 <= 0``, a finite ``v0``, ``alpha, beta, gamma`` in the ranges of
    :class:`~gear_rattle.core.params.Params`, ``0 < t_max <= 1e6``, ``1 <= max_steps <= 1e6``."""
    check_tau0(tau0)
    check_real("s0", s0, -1.0, 0.0)
    check_real("v0", v0)
    for name, value in (("alpha", alpha), ("beta", beta), ("gamma", gamma)):
        check_param(name, value)
    check_real("t_max", t_max, 0.0, 1e6, lo_open=True)
    check_int("max_steps", max_steps, 1, 1_000_000)


def first_impact(tau0, s0, v0, alpha, beta, gamma, t_max=T_MAX, max_steps=MAX_STEPS) -> Hit:
    """First impact of the flight leaving ``(tau0, s0, v0)``: the certified impact finder.

    The flight is the closed form of Eqs. (7)-(8) (:mod:`mapimpl.flight`); the first root of the gap to
    either wall is bracketed by certified safe steps and located by safeguarded root iterations (the
    module docstring: method, guarantees and status codes).  Scalar inputs; use ``jax.vmap`` for batches.
    Called with concrete values (not under ``jit``/``vmap``) it checks them first (:func:`check_flight`:
    ``ValueError``/``TypeError`` naming the argument); traced, its caller has checked them.

    Parameters
    ----------
    tau0 : float
        Departure phase, reduced to ``[0, 2 pi)``.
    s0 : float
        Departure position, ``-1 <= s0 <= 0`` (a wall, or inside the backlash).
    v0 : float
        Departure velocity ``sdot`` (after the reset of Eq. 11 when leaving a wall).
    alpha, beta, gamma : float
        The parameters of Eq. (3).
    t_max : float, optional
        Longest flight searched (status ``NO_IMPACT`` beyond), ``0 < t_max <= 1e6``.
    max_steps : int, optional
        Most safe steps (status ``STEP_CAP`` beyond), ``1 <= max_steps <= 1e6``.

    Returns
    -------
    Hit
        ``t`` the flight time, ``wall`` (0: ``s = 0``, -1: ``s = -1``), ``v`` the velocity just before
        the impact, ``status`` (:class:`core.status.FlightOutcome` codes) and ``steps`` (JAX scalars).

    Examples
    --------
    From the middle of the backlash, moving up at alpha = 3: the forcing turns the flight back to the
    lower wall.

    >>> from gear_rattle.core.status import FlightOutcome
    >>> from gear_rattle.mapimpl.finder import first_impact
    >>> hit = first_impact(0.0, -0.5, 0.3, 3.0, 0.1, 0.1)
    >>> print(f"t = {float(hit.t):.8f}, wall {int(hit.wall)}, v = {float(hit.v):.8f}")
    t = 1.41311122, wall -1, v = -1.74131349
    >>> FlightOutcome(int(hit.status)).label
    'hit'

    The position there is the wall's, by Eqs. (7)-(8):

    >>> from gear_rattle.mapimpl.flight import flight
    >>> print(f"{-0.5 + float(flight(hit.t, 0.0, 0.3, 3.0, 0.1, 0.1).ds):.12f}")
    -1.000000000000
    """
    if not is_traced(tau0, s0, v0, alpha, beta, gamma, t_max, max_steps):  # a call from Python: check it
        check_flight(tau0, s0, v0, alpha, beta, gamma, t_max, max_steps)
    tau0, s0, v0 = (jnp.asarray(x, jnp.float64) for x in (tau0, s0, v0))
    t_dep = departure_time(tau0, s0, v0, alpha, beta, gamma)

    def gap_of(t, wall_top):
        fp = flight(t, tau0, v0, alpha, beta, gamma)
        du, dl = wall_gaps(s0, fp.ds)
        return jnp.where(wall_top, du, dl), jnp.where(wall_top, -fp.v, fp.v), fp

    # ---- phase 1: certified safe steps until a bracket [lo, hi] with one root ----
    def cond(c):
        return ~c["done"]

    def body(c):
        t_a, H = c["t"], c["H"]
        fp = flight(t_a, tau0, v0, alpha, beta, gamma)
        m2, m3, _ = derivative_bounds(t_a, tau0, v0, alpha, beta, gamma)
        st = safe_step(fp.ds, fp.v, fp.a, m2, m3, t_a, H, c["it"], t_dep, s0, t_max, max_steps)
        g_b, dg_b, fb = gap_of(st.t_b, st.top_near)
        unique = bracket_unique(fp.v, fp.a, fb.v, fb.a, m2, m3, st.t_b - t_a)
        bracket, stalled = bracket_test(g_b, t_a, st.h_near, unique)
        # the first root step, from t_b with this evaluation (d2g = -+ s''; the bracket is [t_a, t_b])
        x0, _, _, done0, _ = root_step(st.t_b, g_b, dg_b, jnp.where(st.top_near, -fb.a, fb.a), t_a, st.t_b, m2, m3, 0)
        bracket, stalled = bracket & ~st.move, stalled & ~st.move
        t_new = jnp.where(st.move, st.t_next, jnp.where(bracket | stalled, t_a, t_a + st.h_near))
        beyond = t_new > t_max
        capped = st.it >= max_steps
        F = FlightOutcome
        status = jnp.where(bracket, F.HIT, jnp.where(stalled, F.GRAZE, jnp.where(beyond, F.NO_IMPACT, F.STEP_CAP)))
        return dict(
            t=t_new,
            H=st.H_new,
            it=st.it,
            done=bracket | stalled | beyond | capped,
            hi=jnp.where(bracket, st.t_b, t_new),
            x0=x0,
            rdone=done0,
            top=jnp.where(bracket | stalled, st.top_near, c["top"]),
            status=status,
        )

    init = dict(
        t=jnp.zeros_like(v0),
        H=jnp.asarray(H0, jnp.float64),
        it=jnp.asarray(0, jnp.int32),
        done=jnp.asarray(False),
        hi=jnp.zeros_like(v0),
        x0=jnp.zeros_like(v0),
        rdone=jnp.asarray(False),
        top=jnp.asarray(True),
        status=jnp.asarray(FlightOutcome.STEP_CAP),
    )
    c = jax.lax.while_loop(cond, body, init)
    lo, hi, top, status = c["t"], c["hi"], c["top"], c["status"]

    # ---- phase 2: safeguarded root iteration on the bracket (exactly one root inside) ----
    m2, m3, _ = derivative_bounds(lo, tau0, v0, alpha, beta, gamma)

    def nbody(n):
        g, dg, fp = gap_of(n["x"], top)
        x, lo_n, hi_n, done, k = root_step(n["x"], g, dg, jnp.where(top, -fp.a, fp.a), n["lo"], n["hi"], m2, m3, n["k"])
        return dict(x=x, lo=lo_n, hi=hi_n, done=done, k=k)

    need = status == FlightOutcome.HIT
    n0 = dict(x=c["x0"], lo=lo, hi=hi, done=~need | c["rdone"], k=jnp.asarray(1, jnp.int32))
    n = jax.lax.while_loop(lambda n: ~n["done"], nbody, n0)
    t_hit = jnp.where(need, n["x"], lo)
    ok = (status == FlightOutcome.HIT) | (status == FlightOutcome.GRAZE)
    v_hit = flight(t_hit, tau0, v0, alpha, beta, gamma).v
    wall = jnp.where(top, 0, -1).astype(jnp.int32)
    return Hit(
        t=jnp.where(ok, t_hit, jnp.inf),
        wall=wall,
        v=jnp.where(ok, v_hit, jnp.nan),
        status=status.astype(jnp.int32),
        steps=c["it"],
    )


__all__ = [
    "MAX_STEPS",
    "H0",
    "NEWTON_ITERS",
    "Hit",
    "quadratic_time",
    "safe_time",
    "wall_gaps",
    "departure_time_sc",
    "departure_time",
    "SafeStep",
    "safe_step",
    "bracket_unique",
    "bracket_test",
    "root_step",
    "check_flight",
    "first_impact",
]
