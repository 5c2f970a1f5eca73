"""Certified impact sequences: every impact time and velocity enclosed by ball arithmetic (Arb).

The model is Eq. (3), ``s'' + beta s' = f(tau)``, ``f = -alpha sin tau + alpha beta cos tau + gamma``
(see ``docs/model.md``).  A flight leaving ``(tau0, s0, v0)`` is, with ``w0 = v0 - alpha cos tau0``,
``E = exp(-beta t)``, ``E1 = (1 - E)/beta`` and ``B = beta w0 - gamma``,

    s(t)    = s0 + 2 alpha cos(tau0 + t/2) sin(t/2) + w0 E1 + gamma (t - E1)/beta      (Eq. 7)
    s'(t)   = alpha cos(tau0 + t) + w0 E + gamma E1                                  (Eq. 8)
    s''(t)  = -alpha sin(tau0 + t) - B E,     s'''(t) = -alpha cos(tau0 + t) + beta B E,
    s''''(t) = alpha sin(tau0 + t) - beta^2 B E.

Every quantity is an ``arb`` ball (python-flint) at ``prec`` bits; ``tau0`` and ``v0`` are the
enclosures of the previous impact, so the error bounds propagate from impact to impact.  The
parameters are exact float64 numbers (a :class:`Params`) or exact decimals (``{"alpha": "1.245",
...}``, balls of radius ~2^-prec; :class:`Model`).

**One flight** (:func:`certified_flight`) proves, for *every* initial state in the input balls:

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

The velocity before the impact is ``s'`` evaluated on the root's ball.

**Sticking** follows the policy of :mod:`mapimpl.sticking` exactly (pressing forcing, accumulation
time ``t_acc = 2 u / ((1 - r) f_in) <= STICK_TIME``, release at the first zero of the contact force,
in closed form ``f = gamma - R sin(tau - phi)``: the canonical release phase of the wall, a
function of the parameters alone, plus whole periods, :func:`release_time`).  Each decision is
evaluated in balls and must be *definite* (else :class:`CertificationError`).  The release time is
certified as a zero of ``f`` (sign change, ``f'`` excludes 0) with ``f`` pressing on the whole stuck
interval before it.  The stick row itself (``tau_n + t_acc``) is a *policy value*, not a solution
of the ODE.  :func:`certified_step` is one map step (reset or sticking, then the certified flight).

All loops are bounded; failure to certify raises :class:`CertificationError`, never loops.
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass, field

from flint import arb, ctx

from ...mapimpl.params import Params
from ...mapimpl.sticking import STICK_TIME

#: Default working precision in bits (about 96 decimal digits).
PREC = 320
#: Longest flight searched (tau units), as the map's ``T_MAX`` order of magnitude for golden cases.
T_MAX = 400.0
#: Most interval evaluations per flight.
MAX_EVALS = 200_000
#: Highest working precision accepted (bits).
MAX_PREC = 1 << 16


class CertificationError(RuntimeError):
    """The enclosure could not be certified (ambiguous decision, grazing, budget exhausted)."""


@contextmanager
def precision(bits: int):
    """Temporarily set python-flint's working precision."""
    if not (isinstance(bits, int) and not isinstance(bits, bool) and 64 <= bits <= MAX_PREC):
        raise ValueError(f"prec={bits!r} is out of range: allowed integer 64 <= prec <= {MAX_PREC}")
    old = ctx.prec
    ctx.prec = bits
    try:
        yield
    finally:
        ctx.prec = old


def exact(x: float) -> arb:
    """The float64 ``x`` as an exact ball."""
    return arb(float(x))


def span(a: arb, b: arb) -> arb:
    """The ball enclosing ``[a, b]`` (``a``, ``b`` balls)."""
    return a.union(b)


def upper_float(x: arb) -> float:
    """A float64 ``>= `` every point of the ball ``x`` (rounded up)."""
    u = float(x.upper())
    return math.nextafter(u, math.inf)


def nearest_float(x: arb) -> float:
    """The float64 nearest to the ball's midpoint (40-digit decimal, then correctly rounded)."""
    return float(x.mid().str(45, radius=False))


#: Parameter names of the model, in the order of :class:`mapimpl.params.Params`.
PARAM_NAMES = ("alpha", "beta", "gamma", "r")


def parameter_ball(name: str, value) -> arb:
    """A parameter as a ball at the current precision: a float is the exact binary number it holds,
    a string is the exact *decimal* it spells (``"1.245"``: a ball of radius ~2^-prec around
    1.245, which no float holds).  Validated with the ranges of :mod:`mapimpl.params`."""
    from ...mapimpl.params import check_value

    if isinstance(value, str):
        text = value.strip()
        try:
            x = float(text)
        except ValueError:
            raise ValueError(f"parameter {name}={value!r} is not a decimal number") from None
        check_value(name, x)
        ball = arb(text)
        if not ball.is_finite():
            raise ValueError(f"parameter {name}={value!r} is not a finite decimal number")
        return ball
    return exact(check_value(name, value))


class Model:
    """Parameters as balls, with the forcing and its rate.

    ``params``: a :class:`Params` (float64 values, taken as exact binary numbers) or a mapping
    ``{"alpha": ..., "beta": ..., "gamma": ..., "r": ...}`` whose values are floats (exact) or
    decimal strings (exact decimals, e.g. ``{"alpha": "1.245", ...}``: the paper's printed values
    rather than their float64 roundings).  Build it inside :func:`precision`: string parameters
    are enclosed at the precision current at construction.  ``self.params`` holds the float64
    values (nearest) for messages and float64 code.
    """

    def __init__(self, params):
        if isinstance(params, Params):
            values = {k: getattr(params, k) for k in PARAM_NAMES}
        else:
            values = dict(params)
            missing = [k for k in PARAM_NAMES if k not in values]
            extra = [k for k in values if k not in PARAM_NAMES]
            if missing or extra:
                raise ValueError(f"params={params!r}: allowed exactly the keys {', '.join(PARAM_NAMES)}")
        balls = {k: parameter_ball(k, values[k]) for k in PARAM_NAMES}
        self.params = params if isinstance(params, Params) else Params(**{k: float(values[k]) for k in PARAM_NAMES})
        self.alpha, self.beta, self.gamma, self.r = (balls[k] for k in PARAM_NAMES)

    def forcing(self, tau: arb) -> arb:
        """f(tau) = -alpha sin tau + alpha beta cos tau + gamma."""
        s, c = tau.sin_cos()
        return -self.alpha * s + self.alpha * self.beta * c + self.gamma

    def forcing_rate(self, tau: arb) -> arb:
        """f'(tau) = -alpha cos tau - alpha beta sin tau."""
        s, c = tau.sin_cos()
        return -self.alpha * c - self.alpha * self.beta * s


class Flight:
    """Closed-form flight leaving ``(tau0, s0, v0)`` in balls; ``t`` is the elapsed flight time."""

    def __init__(self, model: Model, tau0: arb, s0: arb, v0: arb):
        self.m = model
        self.tau0, self.s0, self.v0 = tau0, s0, v0
        self.w0 = v0 - model.alpha * tau0.cos()
        self.B = model.beta * self.w0 - model.gamma

    def _e(self, t: arb):
        bt = self.m.beta * t
        em1 = (-bt).expm1()
        return em1 + 1, -em1 / self.m.beta  # E, E1

    def s(self, t: arb) -> arb:
        """Position (for a point ``t``: no cancellation trouble at high precision)."""
        m = self.m
        bt = m.beta * t
        em1 = (-bt).expm1()
        e1 = -em1 / m.beta
        half = t / 2
        trig = 2 * m.alpha * (self.tau0 + half).cos() * half.sin()
        t_minus_e1 = (bt + em1) / m.beta
        return self.s0 + trig + self.w0 * e1 + m.gamma * t_minus_e1 / m.beta

    def v(self, t: arb) -> arb:
        e, e1 = self._e(t)
        return self.m.alpha * (self.tau0 + t).cos() + self.w0 * e + self.m.gamma * e1

    def a(self, t: arb) -> arb:
        e, _ = self._e(t)
        return -self.m.alpha * (self.tau0 + t).sin() - self.B * e

    def j(self, t: arb) -> arb:
        e, _ = self._e(t)
        return -self.m.alpha * (self.tau0 + t).cos() + self.m.beta * self.B * e

    def snap(self, t: arb) -> arb:
        e, _ = self._e(t)
        return self.m.alpha * (self.tau0 + t).sin() - self.m.beta ** 2 * self.B * e

    # gaps: wall 0 (upper, s = 0): -s ; wall -1 (lower, s = -1): s + 1
    def gap(self, wall: int, t: arb) -> arb:
        s = self.s(t)
        return -s if wall == 0 else s + 1

    def gap_rate(self, wall: int, t: arb) -> arb:
        v = self.v(t)
        return -v if wall == 0 else v

    def gap_enclosure(self, wall: int, ta: arb, tb: arb) -> arb:
        """Enclosure of the gap to ``wall`` over ``[ta, tb]``: second-order Taylor form about the exact
        midpoint ``m``, ``s(m) + s'(m) d + s''([ta, tb]) [0, |d|^2]/2`` with ``d`` enclosing ``t - m``."""
        m = ((ta + tb) / 2).mid()  # an exact point; d encloses t - m for every t in [ta, tb]
        d = span(ta, tb) - m
        q = span(arb(0), arb(d.abs_upper()) ** 2) / 2
        sign = -1 if wall == 0 else 1
        s_enc = self.s(m) + self.v(m) * d + self.a(span(ta, tb)) * q
        return sign * s_enc + (0 if wall == 0 else 1)


@dataclass
class FlightCertificate:
    """What one certified flight proved."""

    wall: int
    t: arb                 # enclosure of the flight time
    v: arb                 # enclosure of the pre-impact velocity
    bracket: tuple         # (t_lo, t_hi) as floats: interval with the unique root
    pieces: int            # subintervals covering [0, t_lo] with both gaps > 0
    evals: int             # interval evaluations used
    departure: float       # length of the departure certificate on the start wall (0 if none)
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
        else:
            fac = sign * (fl.v0 + fl.a(I) * I / 2)
        if fac > 0 and fl.gap_enclosure(far, zero, h0) > 0:
            return h0
        h0 = h0 / 2
    raise CertificationError("cannot certify the departure from the start wall "
                             "(moving into the wall, or pressed into it at rest)")


def certified_flight(model: Model, tau0: arb, s0: float, v0: arb, *, release: bool = False,
                     prec: int = PREC, t_max: float = T_MAX, max_evals: int = MAX_EVALS) -> FlightCertificate:
    """First wall contact of the flight leaving ``(tau0, s0, v0)``, certified (see module docstring).

    ``s0`` is exact (a wall 0 / -1 or an interior float); ``release`` marks a departure from sticking
    (``v0 = 0`` at a zero of the contact force).
    """
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
            raise CertificationError(f"no wall contact within t_max={t_max}")
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
            raise CertificationError(f"cannot separate the flight from the walls near t={float(t):.17g} "
                                     "(tangential contact?)")


#: Working precision of the first Newton iterations of :func:`_refine` (doubled as they converge).
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


# ---------------------------------------------------------------------------------------------
# orbits


@dataclass
class Event:
    """One certified row: ``n, tau, theta, wall, sdot (None for stick/release), kind``."""

    n: int
    tau: arb
    theta: arb
    wall: int
    sdot: arb | None
    kind: str
    note: dict = field(default_factory=dict)


@dataclass
class CertifiedOrbit:
    events: list
    status: str
    stop_reason: str
    prec: int
    flights: list


def mod_two_pi(tau: arb) -> arb:
    """``tau mod 2 pi`` as a ball; raises if the ball straddles a multiple of ``2 pi``."""
    two_pi = 2 * arb.pi()
    k = (tau / two_pi).floor()
    if not k.is_exact():
        raise CertificationError("tau mod 2 pi: the ball straddles a multiple of 2 pi")
    return tau - k * two_pi


def _stick_decision(model: Model, tau: arb, wall: int, sdot: arb, stick_time: float):
    """The sticking policy in balls; every comparison must be definite.

    Returns ``None`` (bounce) or ``(t_acc, delay or None)`` (``None`` delay: stuck forever).
    """
    d = 1 if wall == 0 else -1
    f_in = d * model.forcing(tau)
    if f_in > 0:
        pressing = True
    elif f_in < 0:
        pressing = False
    else:
        raise CertificationError(f"contact force sign at tau={float(tau.mid()):.17g} not definite")
    if not pressing or model.r == 1:
        return None
    u = model.r * abs(sdot)
    t_acc = 2 * u / ((1 - model.r) * f_in)
    st = exact(stick_time)
    if t_acc > st:
        return None
    if not t_acc <= st:
        raise CertificationError("sticking decision t_acc <= STICK_TIME not definite")
    delay = release_delay(model, tau, wall)
    if delay is None:
        return t_acc, None
    if not delay > t_acc:
        if delay < t_acc:
            return None
        raise CertificationError("release-after-accumulation decision not definite")
    return t_acc, delay


def release_phase(model: Model, wall: int) -> arb | None:
    """The canonical release phase at ``wall``, in ``[0, 2 pi)``, as a ball (``None``: never released).

    The contact force ``f = gamma - R sin(tau - phi)``, ``R = alpha sqrt(1 + beta^2)``,
    ``phi = atan beta``, stops pressing into the upper wall where it falls through zero,
    ``phi + asin(gamma/R)``, and into the lower wall where it rises through zero,
    ``phi + pi - asin(gamma/R)`` (mod ``2 pi``): a function of the parameters alone, the ball
    counterpart of :func:`mapimpl.sticking.release_phase`.  ``None`` when ``|gamma| >= R`` on the
    pressing side (or ``alpha = 0``): the force never changes sign.  ``ValueError`` when the force
    never presses into ``wall`` (``|gamma| >= R`` on the other side): nothing sticks there.
    """
    if model.alpha.is_zero():
        return None
    R = model.alpha * (1 + model.beta ** 2).sqrt()
    phi = model.beta.atan()
    c = model.gamma / R
    cd = c if wall == 0 else -c
    if cd >= 1:
        return None
    if not cd < 1:
        raise CertificationError("never-release decision |gamma| >= R not definite")
    if cd <= -1:
        raise ValueError(f"wall={wall}: the contact force never presses into this wall (|gamma| >= R on the "
                         "other side): nothing sticks there, there is no release phase")
    if not cd > -1:
        raise CertificationError("never-pressing decision |gamma| >= R not definite")
    x = phi + (c.asin() if wall == 0 else arb.pi() - c.asin())
    two_pi = 2 * arb.pi()
    k = (x / two_pi).floor()
    if not k.is_exact():
        raise CertificationError("release phase straddles a multiple of 2 pi")
    return x - k * two_pi


def release_delay(model: Model, tau: arb, wall: int):
    """Time from ``tau`` to the first zero of the contact force (``None``: never), i.e. to the next
    canonical release phase (:func:`release_phase`)."""
    phase = release_phase(model, wall)
    if phase is None:
        return None
    x = phase - tau
    two_pi = 2 * arb.pi()
    k = (x / two_pi).floor()
    if not k.is_exact():
        raise CertificationError("release phase straddles a multiple of 2 pi")
    return x - k * two_pi


def release_time(model: Model, tau: arb, wall: int) -> arb:
    """The release after sticking at ``tau``: the canonical phase plus a whole number of periods,
    ``release_phase + 2 pi m`` with ``m`` the certified integer that makes it the first one after
    ``tau``.  Its ball is that of the phase (it does not inherit the radius of ``tau``): every orbit
    that sticks to ``wall`` leaves it from the same state, as in :mod:`mapimpl.sticking`."""
    phase = release_phase(model, wall)
    if phase is None:
        raise CertificationError("release_time: the force never changes sign at this wall")
    two_pi = 2 * arb.pi()
    k = ((phase - tau) / two_pi).floor()
    if not k.is_exact():
        raise CertificationError("release phase straddles a multiple of 2 pi")
    return phase - k * two_pi


def certify_zero(model: Model, tau_rel: arb, wall: int, prec: int) -> tuple[arb, arb]:
    """``(lo, hi)`` around the ball ``tau_rel`` with ``d f(lo) > 0 > d f(hi)`` and ``d f' < 0`` on
    ``[lo, hi]`` (``d = +1`` upper wall, ``-1`` lower): a certified simple zero of the contact force
    where it stops pressing, unique in ``[lo, hi]``."""
    d = 1 if wall == 0 else -1
    lo0, hi0 = arb(tau_rel.lower()), arb(tau_rel.upper())
    delta = arb(2) ** (-(prec - 8)) * (abs(tau_rel).upper() + 1)
    for _ in range(200):
        lo, hi = lo0 - delta, hi0 + delta
        if d * model.forcing(lo) > 0 and d * model.forcing(hi) < 0:
            break
        delta = delta * 4
    else:
        raise CertificationError("release time: no certified sign change of the contact force")
    if not d * model.forcing_rate(span(lo, hi)) < 0:
        raise CertificationError("release time is not a certified simple zero of the contact force")
    return lo, hi


def certify_release(model: Model, tau_impact: arb, tau_rel: arb, wall: int, prec: int, max_evals: int = 100_000):
    """Prove that ``tau_rel`` encloses the first zero of the contact force after ``tau_impact``.

    (i) ``d f`` changes sign across the ball and ``f'`` excludes 0 on it (:func:`certify_zero`);
    (ii) ``d f > 0`` on ``[tau_impact, tau_rel.lower]``: pieces with the Taylor form
    ``f(m) + f'(T)[-h, h]`` (adaptive subdivision) until a rest ``[t, lo]`` on which ``d f'`` is
    certified negative (``d f`` falls monotonically to ``d f(lo) > 0``).
    Returns ``(ball, pieces)``: the certified enclosure (the closed-form ball, widened until the
    signs are definite) and the number of pieces of (ii), the monotone rest included.
    """
    d = 1 if wall == 0 else -1
    lo, hi = certify_zero(model, tau_rel, wall, prec)
    t = arb(tau_impact.upper())
    if not d * model.forcing(span(tau_impact, t)) > 0:
        raise CertificationError("not pressing at the impact")
    h = arb(1) / 4
    pieces, evals = 0, 0
    while t < lo:
        evals += 1
        if evals > max_evals:
            raise CertificationError("release certification budget exhausted")
        if d * model.forcing_rate(span(t, lo)) < 0:  # d f > d f(lo) > 0 on the whole rest
            pieces += 1
            break
        tb = t + h if t + h < lo else lo
        m = (t + tb) / 2
        hw = (tb - t) / 2
        enc = d * (model.forcing(m) + model.forcing_rate(span(t, tb)) * span(-hw, hw))
        if enc > 0:
            t, pieces = tb, pieces + 1
            h = h * 2 if h < 1 else h
            continue
        h = h / 2
        if h < arb(2) ** (-(prec - 40)):
            raise CertificationError("cannot prove the contact force keeps pressing before the release")
    return span(lo, hi), pieces


@dataclass
class CertifiedStep:
    """One certified map step from a pre-impact state (Eqs. 11-13 with the sticking policy).

    ``tau, sdot, wall``: the next pre-impact state (``None`` when stuck forever); ``flight``: its
    certificate; ``stick``: the policy stick time ``tau_n + t_acc`` (``None``: the impact bounced);
    ``release``: the certified release time (``None``: bounced, or stuck forever) and
    ``release_pieces`` the pieces that proved the force pressing before it.
    """

    tau: arb | None
    sdot: arb | None
    wall: int | None
    flight: FlightCertificate | None
    stick: arb | None = None
    release: arb | None = None
    release_pieces: int = 0


def certified_step(model: Model, tau: arb, sdot: arb, wall: int, *, prec: int, stick_time: float = STICK_TIME,
                   t_max: float = T_MAX) -> CertifiedStep:
    """Apply the impact map to the pre-impact state ``(tau, sdot)`` on ``wall`` (balls): the reset
    ``sdot -> -r sdot`` (Eq. 11) or, under the sticking policy, the jump to the accumulation point
    and the release at the canonical phase (:func:`release_time`, certified by
    :func:`certify_release`) with ``sdot = 0``; then the certified first impact (Eqs. 7-8) with the
    mean-value enclosure (:func:`mean_value_impact`)."""
    dec = _stick_decision(model, tau, wall, sdot, stick_time)
    stick = rel = None
    pieces = 0
    if dec is None:
        start, v0, release = tau, -model.r * sdot, False
    else:
        t_acc, delay = dec
        stick = tau + t_acc
        if delay is None:
            return CertifiedStep(None, None, None, None, stick)
        start, pieces = certify_release(model, tau, release_time(model, tau, wall), wall, prec)
        rel, v0, release = start, arb(0), True
    c = certified_flight(model, start, float(wall), v0, release=release, prec=prec, t_max=t_max)
    new_tau, c.v = mean_value_impact(model, c, start, float(wall), v0, release, prec, t_max)
    return CertifiedStep(new_tau, c.v, c.wall, c, stick, rel, pieces)


def certify_orbit(params, tau0: float, sdot0: float, n_impacts: int, s0: float | None = None, *,
                  prec: int = PREC, stick_time: float = STICK_TIME, radius_limit: float | None = None,
                  t_max: float = T_MAX) -> CertifiedOrbit:
    """Certified impact sequence with the layout of :class:`mapimpl.results.ImpactSequence`.

    ``params``: a :class:`Params` or a mapping of decimal strings (see :class:`Model`).  Impact 0
    is the pre-impact initial state (``s0`` None; exact) or the first impact of the flight leaving
    the free state ``(tau0, s0, sdot0)``.  Stops early when the orbit sticks forever, or when a
    radius exceeds ``radius_limit`` (the last certified event within the limit is kept).
    """
    if int(n_impacts) < 0:
        raise ValueError(f"n_impacts={n_impacts!r} is out of range: allowed n_impacts >= 0")
    if not (math.isfinite(tau0) and math.isfinite(sdot0)):
        raise ValueError("initial tau0 and sdot0 must be finite")
    if radius_limit is not None and not radius_limit > 0:
        raise ValueError(f"radius_limit={radius_limit!r} is out of range: allowed > 0")
    with precision(prec):
        model = Model(params)
        events: list[Event] = []
        flights: list[dict] = []

        def add(n, tau, wall, sdot, kind, note=None):
            events.append(Event(n, tau, mod_two_pi(tau), wall, sdot, kind, dict(note or {})))

        if s0 is None:
            if sdot0 == 0.0:
                raise ValueError("initial sdot0=0.0 is out of range: a pre-impact state needs sdot0 != 0")
            tau, sdot = exact(tau0), exact(sdot0)
            wall = 0 if sdot0 > 0 else -1
            add(0, tau, wall, sdot, "impact", {"source": "initial state (exact)"})
        else:
            if not (-1.0 <= s0 <= 0.0):
                raise ValueError(f"initial s0={s0!r} is out of range: allowed -1 <= s0 <= 0")
            c = certified_flight(model, exact(tau0), s0, exact(sdot0), prec=prec, t_max=t_max)
            tau, sdot, wall = exact(tau0) + c.t, c.v, c.wall
            flights.append(_flight_record(0, c))
            add(0, tau, wall, sdot, "impact", {"source": "certified flight"})
        status, reason = "active", "n_impacts reached"
        for n in range(1, int(n_impacts) + 1):
            st = certified_step(model, tau, sdot, wall, prec=prec, stick_time=stick_time, t_max=t_max)
            if st.stick is not None:
                add(n - 1, st.stick, wall, None, "stick", {"source": "policy: tau_n + t_acc"})
                if st.tau is None:
                    status, reason = "stuck_forever", "stuck forever (|gamma| >= R)"
                    break
                add(n - 1, st.release, wall, None, "release",
                    {"source": "closed form zero of f, certified", "pieces": st.release_pieces})
            if radius_limit is not None and max(float(st.tau.rad()), float(st.sdot.rad())) > radius_limit:
                reason = f"radius limit {radius_limit:g} exceeded at impact {n}"
                break
            tau, sdot, wall = st.tau, st.sdot, st.wall
            flights.append(_flight_record(n, st.flight))
            add(n, tau, wall, sdot, "impact", {"source": "certified flight"})
        return CertifiedOrbit(events, status, reason, prec, flights)


def mean_value_impact(model: Model, c_box: FlightCertificate, tau0: arb, s0: float, v0: arb, release: bool,
                      prec: int, t_max: float) -> tuple[arb, arb]:
    """Tighter enclosure of the impact ``(tau1, v1)`` over the input box by the mean-value form.

    ``c_box`` certified the flight for *every* state in the box (same wall, no earlier contact,
    transversal impact), so the impact map is differentiable on the box and, componentwise,
    ``G(x) in G(m) + J(X) (x - m)`` with ``m`` the box's midpoint (its root narrowed in the box's
    certified root bracket, which holds for every state of the box) and ``J(X)`` the interval enclosure of the analytic Jacobian (``docs/model.md``)

        d tau1/d tau0 = (v0 + E1 a0)/v1,   d tau1/d v0 = -E1/v1,
        d v1/d tau0   = a1 d tau1/d tau0 - E a0,   d v1/d v0 = a1 d tau1/d v0 + E,

    evaluated with ``t`` and ``v1`` in their box enclosures.  The result is intersected with the
    direct (box) enclosure; both are rigorous.  Without it the boxes grow by the *absolute values*
    of every partial derivative of every term (a factor ~50 per impact at alpha = 3).
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
    t_pt = _refine(fl_pt, c_box.wall, lo, hi, prec)
    v_pt = fl_pt.v(t_pt)
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
    rt, rv = tau0.rad(), v0.rad()
    d_tau, d_v = span(-rt, rt), span(-rv, rv)
    mv_tau = m_tau + t_pt + dt_tau * d_tau + dt_v * d_v
    mv_v = v_pt + dv_tau * d_tau + dv_v * d_v
    if not (mv_tau.overlaps(crude_tau) and mv_v.overlaps(crude_v)):  # pragma: no cover - would be a bug
        raise CertificationError("mean-value and direct enclosures are disjoint")
    return mv_tau.intersection(crude_tau), mv_v.intersection(crude_v)


def _flight_record(n: int, c: FlightCertificate) -> dict:
    return {"impact": n, "wall": c.wall, "bracket": list(c.bracket), "pieces": c.pieces, "evals": c.evals,
            "departure": c.departure}
