"""The sticking policy in balls: every decision certified definite.

**Sticking** follows the policy of :mod:`mapimpl.sticking` exactly (pressing forcing, accumulation
time ``t_acc = 2 u / ((1 - r) f_in) <= STICK_TIME``, release at the first zero of the contact force,
in closed form ``f = gamma - R sin(tau - phi)``: the canonical release phase of the wall, a
function of the parameters alone, plus whole periods, :func:`release_time`).  Each decision is
evaluated in balls and must be *definite* (else :class:`CertificationError`).  The release time is
certified as a zero of ``f`` (sign change, ``f'`` excludes 0) with ``f`` pressing on the whole stuck
interval before it (:func:`certify_release`).  The stick row itself (``tau_n + t_acc``) is a
*policy value*, not a solution of the ODE.
"""

from __future__ import annotations

from flint import arb

from .balls import CertificationError, exact, span
from .model import Model


def stick_decision(model: Model, tau: arb, wall: int, sdot: arb, stick_time: float):
    """The sticking policy in balls; every comparison must be definite.

    Returns ``None`` (bounce) or ``(t_acc, delay or None)`` (``None`` delay: stuck forever).
    """
    d = 1 if wall == 0 else -1
    f_in = d * model.forcing(tau)
    if f_in.is_zero():
        # exactly zero (e.g. alpha = gamma = 0): not pressing, or pressing with t_acc = 2 u / 0 = inf
        # (mapimpl.sticking's rule): it bounces either way
        return None
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
    R = model.alpha * (1 + model.beta**2).sqrt()
    phi = model.beta.atan()
    c = model.gamma / R
    cd = c if wall == 0 else -c
    if cd >= 1:
        return None
    if not cd < 1:
        raise CertificationError("never-release decision |gamma| >= R not definite")
    if cd <= -1:
        raise ValueError(
            f"wall={wall}: the contact force never presses into this wall (|gamma| >= R on the "
            "other side): nothing sticks there, there is no release phase"
        )
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


__all__ = [
    "stick_decision",
    "release_phase",
    "release_delay",
    "release_time",
    "certify_zero",
    "certify_release",
]
