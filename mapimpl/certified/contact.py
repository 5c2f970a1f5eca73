"""The first wall contact of a flight, certified: the proof behind every certified impact.

**One flight** (:func:`certified_flight`, the flight of :class:`~.model.Flight`, Eqs. 7-8) proves,
for *every* initial state in the input balls:

(b) *no earlier wall contact*: ``[0, t_lo]`` is covered by subintervals on which the enclosures of
    both gaps (``-s`` to the upper wall ``s = 0``, ``s + 1`` to the lower wall ``s = -1``) are
    strictly positive.  On a subinterval ``T = [a, b]`` with midpoint ``m`` and half-width ``h`` the
    enclosure is the second-order Taylor form ``s(m) + s'(m) [-h, h] + s''(T) [0, h^2]/2``; the
    interval is halved until it is positive (adaptive, bounded).  A flight that starts on a wall
    has gap exactly 0 at ``t = 0``: on ``(0, h0]`` the factored form ``gap/t`` (moving away:
    ``|v0| - s''([0, h0]) [0, h0]/2``), or ``gap/t^3`` after a release from sticking (``v0 = 0``
    and ``s''(0) = f(tau_release) = 0`` exactly), is shown positive instead;

(a) *a crossing with a unique root*: on the first subinterval ``[t_lo, t_hi]`` that is not
    positive, the gap is negative at ``t_hi`` and its derivative enclosure (``-+ s'(T)``) excludes 0,
    so the gap is strictly monotone there and has exactly one root, the first impact.  The root is
    then narrowed (Newton on midpoints) to ``[x - e, x + e]`` with the gap proven positive at
    ``x - e`` and negative at ``x + e``.

The velocity before the impact is ``s'`` evaluated on the root's ball; :func:`mean_value_impact`
tightens the impact's enclosure over a box of initial states by the mean-value form.

All loops are bounded; failure to certify raises :class:`CertificationError`, never loops.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from flint import arb, ctx

from ...core.checks import InputTypeError, check_int, check_real
from ...core.horizons import CERTIFIED_FLIGHT_T_MAX
from .balls import PREC, CertificationError, check_ball, check_prec, exact, span, upper_float
from .model import Flight, Model

#: Longest flight searched (tau units) by one certified flight: :data:`core.horizons.CERTIFIED_FLIGHT_T_MAX`
#: (a fifth of the orbit horizon; the module core/horizons.py says why).
T_MAX = CERTIFIED_FLIGHT_T_MAX
#: Most interval evaluations per flight.
MAX_EVALS = 200_000


class NoContactError(CertificationError):
    """Proven: the flight reaches no wall within ``t_max`` (both gaps positive on ``[0, t_max]``)."""


@dataclass
class FlightCertificate:
    """What one certified flight proved."""

    wall: int
    t: arb  # enclosure of the flight time
    v: arb  # enclosure of the pre-impact velocity
    bracket: tuple  # (t_lo, t_hi) as floats: interval with the unique root
    pieces: int  # subintervals covering [0, t_lo] with both gaps > 0
    evals: int  # interval evaluations used
    departure: float  # length of the departure certificate on the start wall (0 if none)
    root_bracket: tuple = field(default=(), repr=False)  # (t_lo, t_hi) as balls


def _departure(fl: Flight, start_wall: int, release: bool, prec: int) -> arb:
    """Largest tried ``h0`` (halving from 1/16) with the start gap provably > 0 on ``(0, h0]``
    and the far gap > 0 on ``[0, h0]``."""
    far = -1 if start_wall == 0 else 0
    sign = -1 if start_wall == 0 else 1  # gap to the start wall = sign * (s - s0)
    zero = arb(0)
    h0 = arb(1) / 16
    for _ in range(prec):
        I = span(zero, h0)
        if release:
            # v0 = 0 and s''(0) = f(tau_release) = 0 exactly: gap / t^3 = sign (j(0)/6 + s''''(xi) t/24)
            fac = sign * (fl.j(zero) / 6 + fl.snap(I) * I / 24)
        elif fl.v0.is_zero():
            # at rest, pulled away from the wall: gap / t^2 = sign s''(xi) / 2
            fac = sign * fl.a(I) / 2
        else:
            fac = sign * (fl.v0 + fl.a(I) * I / 2)
        if fac > 0 and fl.gap_enclosure(far, zero, h0) > 0:
            return h0
        h0 = h0 / 2
    raise CertificationError(
        "cannot certify the departure from the start wall (moving into the wall, or pressed into it at rest)"
    )


def check_flight_args(model, tau0, s0, v0, release, prec, t_max, max_evals) -> None:
    """The arguments of :func:`certified_flight` (:mod:`core.checks`): a :class:`~.model.Model`, finite
    balls ``tau0`` and ``v0``, ``-1 <= s0 <= 0``, a bool ``release``, ``64 <= prec <= 65536``,
    ``0 < t_max <= 1e6``, ``1 <= max_evals <= 1e8``."""
    if not isinstance(model, Model):
        raise InputTypeError(f"model is a {type(model).__name__}: allowed a mapimpl.certified.model.Model")
    check_ball("tau0", tau0)
    check_real("s0", s0, -1.0, 0.0)
    check_ball("v0", v0)
    if not isinstance(release, bool):
        raise InputTypeError(f"release={release!r} is a {type(release).__name__}: allowed True or False")
    check_prec(prec)
    check_real("t_max", t_max, 0.0, 1e6, lo_open=True)
    check_int("max_evals", max_evals, 1, 100_000_000)


def certified_flight(
    model: Model,
    tau0: arb,
    s0: float,
    v0: arb,
    *,
    release: bool = False,
    prec: int = PREC,
    t_max: float = T_MAX,
    max_evals: int = MAX_EVALS,
) -> FlightCertificate:
    """First wall contact of the flight leaving ``(tau0, s0, v0)``, certified (see module docstring).

    Parameters
    ----------
    model : Model
        The parameters as balls (:class:`~.model.Model`).
    tau0 : arb
        Departure time (a ball: every departure in it is covered).
    s0 : float
        Departure position, exact: a wall (0 or -1) or an interior float.
    v0 : arb
        Departure velocity (a ball).
    release : bool, optional
        A departure from sticking (``v0 = 0`` at a zero of the contact force).
    prec : int, optional
        Working precision in bits, ``64 <= prec <= 65536``.
    t_max : float, optional
        Longest flight searched, ``0 < t_max <= 1e6``.
    max_evals : int, optional
        Most interval evaluations, ``1 <= max_evals <= 1e8``.

    Returns
    -------
    FlightCertificate
        The wall hit, enclosures of the flight time and of the pre-impact velocity, and what the proof
        used.

    Raises
    ------
    CertificationError
        When the first contact cannot be proven (e.g. a tangential contact); never loops.
        :class:`NoContactError` (a subclass) when it is proven that no wall is reached within ``t_max``.

    Examples
    --------
    The flight of :func:`mapimpl.finder.first_impact`'s example, proven: the float64 flight time lies
    in a ball of radius ~1e-14.

    >>> from flint import arb
    >>> from gear_rattle.core.params import Params
    >>> from gear_rattle.mapimpl.certified.contact import certified_flight
    >>> from gear_rattle.mapimpl.certified.model import Model
    >>> cert = certified_flight(Model(Params(3.0, 0.1, 0.1, 0.9)), arb(0), -0.5, arb(0.3))
    >>> cert.wall, cert.bracket
    (-1, (1.25, 1.75))
    >>> print(cert.t.str(12, radius=False), bool(cert.t.rad() < 1e-13))
    1.41311122496 True
    """
    check_flight_args(model, tau0, s0, v0, release, prec, t_max, max_evals)
    s0_b = exact(s0)
    fl = Flight(model, tau0, s0_b, v0)
    start_wall = 0 if s0 == 0.0 else (-1 if s0 == -1.0 else None)
    t = arb(0)
    departure = 0.0
    if start_wall is not None:
        if release and not v0.is_zero():
            raise CertificationError("a release needs v0 = 0 exactly")
        t = _departure(fl, start_wall, release, prec)
        departure = float(t)
    else:
        if not (fl.gap(0, t) > 0 and fl.gap(-1, t) > 0):
            raise CertificationError(f"free-flight start s0={s0!r} is not strictly inside (-1, 0)")
    h = arb(1) / 4
    h_max = arb(1) / 2
    evals, pieces = 0, 1 if start_wall is not None else 0
    tmax = exact(t_max)
    while True:
        if evals >= max_evals:
            raise CertificationError(f"interval budget exhausted at flight time {float(t):.17g}")
        if t > tmax:
            raise NoContactError(f"no wall contact within t_max={t_max}")
        tb = t + h
        g = {w: fl.gap_enclosure(w, t, tb) for w in (0, -1)}
        evals += 2
        if g[0] > 0 and g[-1] > 0:
            t, pieces = tb, pieces + 1
            h = h * 2 if h * 2 < h_max else h_max
            continue
        for w in (0, -1):
            other = -1 - w
            if g[w] > 0 or not g[other] > 0:
                continue
            evals += 2
            if fl.gap(w, tb) < 0 and fl.gap_rate(w, span(t, tb)) < 0:
                troot = _refine(fl, w, t, tb, prec)
                v = fl.v(troot)
                if not ((w == 0 and v > 0) or (w == -1 and v < 0)):
                    raise CertificationError("impact velocity sign not certified")
                return FlightCertificate(w, troot, v, (float(t), float(tb)), pieces, evals, departure, (t, tb))
        h = h / 2
        if h < arb(2) ** (-(prec - 40)) * (t + 1):
            raise CertificationError(
                f"cannot separate the flight from the walls near t={float(t):.17g} (tangential contact?)"
            )


#: Working precision of the first Newton iterations of ``_refine`` (doubled as they converge).
NEWTON_START_PREC = 64


def _refine(fl: Flight, w: int, lo: arb, hi: arb, prec: int) -> arb:
    """Narrow the unique root of ``gap_w`` in ``[lo, hi]`` (gap(lo) > 0 > gap(hi), monotone).

    Newton on exact midpoints, at a working precision that starts at :data:`NEWTON_START_PREC` and
    doubles, up to ``prec``, whenever the step falls below the square root of its resolution (Newton
    squares the error, so the search costs about two iterations at ``prec``); the bracket only guards
    the iteration and the search stops when the gap ball at ``prec`` contains 0.  The
    enclosure is then certified at ``prec``: the gap is proven positive at ``x - e`` and negative at
    ``x + e`` (``e`` widened until it is), inside the certified bracket.
    """
    x = ((lo + hi) / 2).mid()
    tiny = arb(2) ** (-(prec - 12))
    lo0, hi0 = lo, hi  # the certified bracket (Newton narrows lo, hi)
    work = min(NEWTON_START_PREC, prec)
    for _ in range(400):
        full, resolved = work >= prec, False
        old_prec = ctx.prec
        ctx.prec = work
        try:
            gb = fl.gap(w, x)
            d = fl.gap_rate(w, x).mid()
            g = gb.mid()
            # narrow the guard bracket on certain signs only; at full precision a gap ball that
            # contains 0 means x is the root to within the enclosure's width: done
            if gb > 0:
                lo = x
            elif gb < 0:
                hi = x
            elif full:
                break
            else:
                resolved = True
            xn = (x - g / d).mid() if not d.is_zero() else x
        finally:
            ctx.prec = old_prec
        if full and abs(xn - x) < tiny * (abs(x) + 1):  # converged (the step is below resolution)
            if xn > lo0 and xn < hi0:
                x = xn
            break
        # more digits once this precision is used up: the step is below the square root of its
        # resolution (Newton squares the error), or the gap is below the resolution
        if not full and (resolved or abs(xn - x) < arb(2) ** (-(work // 2)) * (abs(x) + 1)):
            work = min(2 * work, prec)
        if not (xn > lo and xn < hi):
            xn = ((lo + hi) / 2).mid()
        x = xn
    gball = fl.gap(w, x)
    dball = fl.gap_rate(w, x).mid()
    eps = (gball.rad() / abs(dball) * 2).mid() + tiny * (abs(x) + 1)
    # a short float64 bound when eps is in float64's range, else the ball's exact upper end
    eps = arb(upper_float(eps)) if float(eps) > 1e-300 else arb(eps.upper())
    for _ in range(400):
        a = x - eps
        b = x + eps
        a = a if a > lo0 else lo0
        b = b if b < hi0 else hi0
        if fl.gap(w, a) > 0 and fl.gap(w, b) < 0:
            return span(a, b)
        eps = eps * 2
    raise CertificationError("root refinement failed")


def refine_from(fl: Flight, w: int, lo: arb, hi: arb, prec: int, x0: arb) -> arb:
    """The unique root of ``gap_w`` in the certified bracket ``[lo, hi]`` (as ``_refine``), from a
    start ``x0`` already accurate to :data:`LEAN_START_PREC` bits, at about one gap evaluation at ``prec``.

    Newton on exact midpoints at a precision that doubles from there up to about ``prec / 2`` (Newton
    squares the error), then one *interval* Newton step at ``prec``: with ``X = [x - e, x + e]`` inside
    the bracket, ``N = x - gap(x) / gap'(X)`` (``gap(x)`` at ``prec``, ``gap'(X)`` at half of it: ``X`` is
    ``2^(-prec/2)`` wide, so ``N`` is ``2^-prec`` wide).  ``N`` inside ``X`` proves that ``X`` holds
    exactly one root, in ``N`` (Moore's interval Newton theorem; the gap is monotone on the bracket
    anyway).  ``_refine`` where Newton leaves the bracket or the step does not contract."""
    x = arb(x0.mid())
    half = prec // 2 + 32
    work = min(LEAN_START_PREC, half)
    old_prec = ctx.prec
    try:
        for _ in range(200):
            ctx.prec = work
            g, d = fl.gap(w, x).mid(), fl.gap_rate(w, x).mid()
            if d.is_zero():
                return _refine(fl, w, lo, hi, prec)
            xn = (x - g / d).mid()
            if not (xn > lo and xn < hi):
                return _refine(fl, w, lo, hi, prec)
            step, x = abs(xn - x), xn
            if step < arb(2) ** (-(work // 2)) * (abs(x) + 1):
                if work >= half:
                    break
                work = min(2 * work, half)
        else:
            return _refine(fl, w, lo, hi, prec)
        ctx.prec = prec
        gx = fl.gap(w, x)
        # X around x of about the distance to the root (Newton's correction at prec): N is then as narrow
        # as gap(x) / gap'(X) allows, 2^-prec (a wider X would widen N by e * gap'' / gap')
        ctx.prec = half
        e = 4 * abs(gx.mid() / fl.gap_rate(w, x).mid()) + arb(2) ** (-(prec - 24)) * (abs(x) + 1)
        ctx.prec = prec
        e = arb(upper_float(e)) if float(e) > 1e-300 else arb(e.upper())
        for _ in range(8):
            X = span(x - e, x + e)
            if X.lower() > lo and X.upper() < hi:
                ctx.prec = half
                dX = fl.gap_rate(w, X)
                ctx.prec = prec
                if not dX.contains(0):
                    N = x - gx / dX
                    if N.lower() > X.lower() and N.upper() < X.upper():
                        return N
            e = e * 16
    finally:
        ctx.prec = old_prec
    return _refine(fl, w, lo, hi, prec)


#: Bits a start of :func:`refine_from` must carry.
LEAN_START_PREC = 96


def mean_value_impact(
    model: Model,
    c_box: FlightCertificate,
    tau0: arb,
    s0: float,
    v0: arb,
    release: bool,
    prec: int,
    t_max: float,
    *,
    lean: bool = False,
) -> tuple[arb, arb]:
    """Tighter enclosure of the impact ``(tau1, v1)`` over the input box by the mean-value form.

    ``c_box`` certified the flight for *every* state in the box (same wall, no earlier contact,
    transversal impact), so the impact map is differentiable on the box and, componentwise,
    ``G(x) in G(m) + J(X) (x - m)`` with ``m`` the box's midpoint (its root narrowed in the box's
    certified root bracket, which holds for every state of the box) and ``J(X)`` the interval enclosure of the analytic Jacobian (``docs/model.md``)

        d tau1/d tau0 = (v0 + E1 a0)/v1,   d tau1/d v0 = -E1/v1,
        d v1/d tau0   = a1 d tau1/d tau0 - E a0,   d v1/d v0 = a1 d tau1/d v0 + E,

    evaluated with ``t`` and ``v1`` in their box enclosures.  The result is intersected with the
    direct (box) enclosure; both are rigorous.  Without it the boxes grow by the *absolute values*
    of every partial derivative of every term (a factor ~50 per impact at alpha = 3).  ``lean``: the
    midpoint's root by :func:`refine_from`, started from the box's root (``c_box`` may then come from a
    lower precision: its enclosures only bound the Jacobian; the certified track,
    :mod:`.track`).
    """
    crude_tau, crude_v = tau0 + c_box.t, c_box.v
    if release or (tau0.is_exact() and v0.is_exact()):
        # after a release only the true release time (a zero of f) leaves the wall: the midpoint of
        # its ball is not a physical state, so the direct (tiny) enclosure is used as it is
        return crude_tau, crude_v
    m_tau, m_v = arb(tau0.mid()), arb(v0.mid())
    # the midpoint lies in the box: the box certificate (no earlier contact, a unique crossing of
    # the gap in the root bracket) holds for it, so only its root needs narrowing
    fl_pt = Flight(model, m_tau, exact(s0), m_v)
    lo, hi = c_box.root_bracket
    t_pt = refine_from(fl_pt, c_box.wall, lo, hi, prec, c_box.t) if lean else _refine(fl_pt, c_box.wall, lo, hi, prec)
    v_pt = fl_pt.v(t_pt)
    full = ctx.prec
    if lean:  # the Jacobian multiplies the box's radius: a few digits of it suffice
        ctx.prec = min(full, LEAN_START_PREC)
    try:
        b = model.beta
        t, v1 = c_box.t, c_box.v
        em1 = (-b * t).expm1()
        e, e1 = em1 + 1, -em1 / b
        a0 = model.forcing(tau0) - b * v0
        a1 = model.forcing(tau0 + t) - b * v1
        dt_tau = (v0 + e1 * a0) / v1
        dt_v = -e1 / v1
        dv_tau = a1 * dt_tau - e * a0
        dv_v = a1 * dt_v + e
    finally:
        ctx.prec = full
    rt, rv = tau0.rad(), v0.rad()
    d_tau, d_v = span(-rt, rt), span(-rv, rv)
    mv_tau = m_tau + t_pt + dt_tau * d_tau + dt_v * d_v
    mv_v = v_pt + dv_tau * d_tau + dv_v * d_v
    if not (mv_tau.overlaps(crude_tau) and mv_v.overlaps(crude_v)):  # pragma: no cover - would be a bug
        raise CertificationError("mean-value and direct enclosures are disjoint")
    return mv_tau.intersection(crude_tau), mv_v.intersection(crude_v)


__all__ = [
    "T_MAX",
    "MAX_EVALS",
    "NoContactError",
    "FlightCertificate",
    "check_flight_args",
    "certified_flight",
    "NEWTON_START_PREC",
    "refine_from",
    "LEAN_START_PREC",
    "mean_value_impact",
]
