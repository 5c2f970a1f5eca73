"""Certified ``no_impact`` endings: a flight proven never to reach a wall, for all ``t > 0``.

With ``gamma = 0`` the flight of Eqs. (7)-(8) from ``(tau0, s0, v0)`` is

    s(t) = s0 + alpha (sin(tau0 + t) - sin tau0) + w0 E1(t),   w0 = v0 - alpha cos tau0,
    E1(t) = (1 - exp(-beta t)) / beta  (increasing, from 0 to 1/beta):

bounded, so it can stay inside the backlash for ever (with ``gamma != 0`` the drift
``gamma (t - E1)/beta`` reaches a wall).  :func:`certify_never_lands` proves it in three parts: the
departure from the start wall on ``(0, h0]`` (the certificate of :func:`.contact.certified_flight`),
both gaps positive on pieces covering ``[h0, T]``, and for ``t >= T`` the enclosure

    s(t) in s0 - alpha sin tau0 + alpha [-1, 1] + w0 [E1(T), 1/beta]

strictly inside ``(-1, 0)``.  :func:`certify_no_impact_orbit` certifies an orbit up to its last
impact (:func:`.orbit.certify_orbit`) and then that impact's map step: the sticking policy (its stick
and release rows happen before the flight that never lands, so they are part of the sequence) and
the never-landing flight (no row).
"""

from __future__ import annotations

from flint import arb

from ..sticking import STICK_TIME
from .balls import PREC, CertificationError, exact, mod_two_pi, precision, span
from .contact import T_MAX, _departure
from .model import Flight, Model
from .orbit import CertifiedOrbit, Event, certify_orbit
from .sticking import certify_release, release_time, stick_decision

#: Longest flight covered by pieces before the tail bound must hold (time units).
T_TAIL_MAX = 4096.0
#: Most piece evaluations of one proof.
MAX_EVALS = 200_000


def _tail_inside(fl: Flight, t: arb) -> bool:
    """Both gaps positive for every flight time ``>= t`` (the bound of the module docstring)."""
    m = fl.m
    e1_t = -(-m.beta * t).expm1() / m.beta
    s = fl.s0 - m.alpha * fl.tau0.sin() + m.alpha * arb(0, 1) + fl.w0 * span(e1_t, 1 / m.beta)
    return bool(-s > 0 and s + 1 > 0)


def certify_never_lands(
    model: Model, tau0: arb, s0: float, v0: arb, *, release: bool = False, prec: int = PREC
) -> dict:
    """Prove that the flight from ``(tau0, s0, v0)`` reaches no wall for any ``t > 0`` (``gamma = 0``);
    ``s0`` a wall (0 or -1) or an interior float.  Returns what was proved (``tail_from``, pieces)."""
    if not model.gamma.is_zero():
        raise CertificationError("a flight with gamma != 0 drifts into a wall: no never-landing proof")
    fl = Flight(model, tau0, exact(s0), v0)
    start_wall = 0 if s0 == 0.0 else (-1 if s0 == -1.0 else None)
    if start_wall is not None:
        t = _departure(fl, start_wall, release, prec)
    else:
        t = arb(0)
        if not (fl.gap(0, t) > 0 and fl.gap(-1, t) > 0):
            raise CertificationError(f"free-flight start s0={s0!r} is not strictly inside (-1, 0)")
    h, pieces, evals, target = arb(1) / 4, 1, 0, arb(8)
    while not (t >= target and _tail_inside(fl, t)):
        if t >= target:
            target = 2 * target
            if target > T_TAIL_MAX:
                raise CertificationError(f"the tail bound does not hold by t={T_TAIL_MAX:g}")
        if evals >= MAX_EVALS:
            raise CertificationError("interval budget exhausted")
        tb = t + h
        evals += 2
        if fl.gap_enclosure(0, t, tb) > 0 and fl.gap_enclosure(-1, t, tb) > 0:
            t, pieces, h = tb, pieces + 1, (h * 2 if h < 1 else h)
            continue
        h = h / 2
        if h < arb(2) ** (-(prec - 40)):
            raise CertificationError(f"the flight comes to a wall near t={float(t.mid()):.17g}: it lands")
    return {"tail_from": float(t.mid()), "pieces": pieces, "evals": evals}


def certify_no_impact_orbit(
    params,
    tau0: float,
    sdot0: float,
    last_impact: int,
    s0: float | None = None,
    *,
    prec: int = PREC,
    stick_time: float = STICK_TIME,
    radius_limit: float | None = None,
    t_max: float = T_MAX,
) -> CertifiedOrbit:
    """A certified orbit whose impact ``last_impact`` is its last: impacts ``0..last_impact`` by
    :func:`.orbit.certify_orbit` (its flights searched up to ``t_max``), then the map step of that impact,
    the policy in balls (stick and release rows if it sticks) and :func:`certify_never_lands`.  Status
    ``no_impact``; raises :class:`CertificationError` where the orbit does not end so (e.g. a wrong
    ``last_impact``)."""
    orb = certify_orbit(
        params,
        tau0,
        sdot0,
        last_impact,
        s0=s0,
        prec=prec,
        stick_time=stick_time,
        radius_limit=radius_limit,
        t_max=t_max,
    )
    if orb.status != "active" or orb.events[-1].n != last_impact:
        raise CertificationError(f"the certified orbit ends before impact {last_impact}: {orb.stop_reason}")
    last = orb.events[-1]
    with precision(prec):
        model = Model(params)
        dec = stick_decision(model, last.tau, last.wall, last.sdot, stick_time)
        if dec is None:
            start, v0, release = last.tau, -model.r * last.sdot, False
        else:
            t_acc, delay = dec
            if delay is None:
                raise CertificationError("the last impact sticks for ever: status stuck_forever, not no_impact")
            tau_stick = last.tau + t_acc
            orb.events.append(
                Event(
                    last_impact,
                    tau_stick,
                    mod_two_pi(tau_stick),
                    last.wall,
                    None,
                    "stick",
                    {"source": "policy: tau_n + t_acc"},
                )
            )
            start, pieces = certify_release(model, last.tau, release_time(model, last.tau, last.wall), last.wall, prec)
            orb.events.append(
                Event(
                    last_impact,
                    start,
                    mod_two_pi(start),
                    last.wall,
                    None,
                    "release",
                    {"source": "closed form zero of f, certified", "pieces": pieces},
                )
            )
            v0, release = arb(0), True
        proof = certify_never_lands(model, start, float(last.wall), v0, release=release, prec=prec)
    orb.status = "no_impact"
    orb.stop_reason = (
        f"no impact after impact {last_impact}: the flight reaches no wall for any t > 0 (certified: "
        f"{proof['pieces']} positive pieces, then the gamma = 0 tail bound from "
        f"t = {proof['tail_from']:.3g})"
    )
    return orb


__all__ = [
    "T_TAIL_MAX",
    "MAX_EVALS",
    "certify_never_lands",
    "certify_no_impact_orbit",
]
