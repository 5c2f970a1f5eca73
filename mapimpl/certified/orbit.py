"""The certified map step (Eqs. 11-13 with the sticking policy) and certified impact sequences.

:func:`certified_step` is one map step (reset or sticking, then the certified flight of
:mod:`.contact`); :func:`certify_orbit` chains steps into an impact sequence with the layout of
:class:`core.results.ImpactSequence` (the golden suite's cases).  The inputs of each step are
the enclosures of the previous impact, so the error bounds propagate from impact to impact.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from flint import arb, ctx

from ...core.checks import MAX_IMPACTS, check_int, check_real, check_start
from ..sticking import MAX_STICK_TIME, STICK_TIME
from .balls import PREC, CertificationError, check_prec, exact, mod_two_pi, precision
from .contact import T_MAX, FlightCertificate, certified_flight, mean_value_impact
from .model import Model
from .sticking import certify_release, release_time, stick_decision


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

    def landed(self) -> tuple[arb, arb, int, FlightCertificate]:
        """``(tau, sdot, wall, flight)`` of the next impact; ``ValueError`` for a step stuck forever."""
        if self.tau is None or self.sdot is None or self.wall is None or self.flight is None:
            raise ValueError("the step sticks forever: there is no next impact")
        return self.tau, self.sdot, self.wall, self.flight


@dataclass
class Departure:
    """How the flight after a pre-impact state leaves its wall under the sticking policy, certified:
    ``start, v0, release`` (the departure time and velocity balls; ``release``: from rest at a zero of
    the contact force); ``stick``: the policy stick time ``tau_n + t_acc`` (``None``: it bounced);
    ``rel``: the certified release time (``None``: bounced); ``pieces``: of the release proof.
    ``start`` is ``None`` when the tooth sticks forever."""

    start: arb | None
    v0: arb | None
    release: bool
    stick: arb | None = None
    rel: arb | None = None
    pieces: int = 0


def certified_departure(
    model: Model,
    tau: arb,
    sdot: arb,
    wall: int,
    *,
    prec: int,
    stick_time: float = STICK_TIME,
    decide_prec: int | None = None,
) -> Departure:
    """The first half of a map step from the pre-impact state ``(tau, sdot)`` on ``wall``: the reset
    ``sdot -> -r sdot`` (Eq. 11) or, under the sticking policy, the jump to the accumulation point and
    the release at the canonical phase (:func:`release_time`, certified by :func:`certify_release`)
    with ``sdot = 0``; or stuck forever (``start`` None).  ``decide_prec``: first try the policy's
    decision at that (lower) precision; a bounce proven there is a bounce (the balls enclose the
    exact values at any precision), anything else is decided again at the current precision."""
    if decide_prec is not None and decide_prec < ctx.prec:
        full = ctx.prec
        ctx.prec = decide_prec
        try:
            bounce = stick_decision(model, tau, wall, sdot, stick_time) is None
        except CertificationError:
            bounce = False
        finally:
            ctx.prec = full
        if bounce:
            return Departure(tau, -model.r * sdot, False)
    dec = stick_decision(model, tau, wall, sdot, stick_time)
    if dec is None:
        return Departure(tau, -model.r * sdot, False)
    t_acc, delay = dec
    stick = tau + t_acc
    if delay is None:
        return Departure(None, None, False, stick)
    start, pieces = certify_release(model, tau, release_time(model, tau, wall), wall, prec)
    return Departure(start, arb(0), True, stick, start, pieces)


def certified_step(
    model: Model, tau: arb, sdot: arb, wall: int, *, prec: int, stick_time: float = STICK_TIME, t_max: float = T_MAX
) -> CertifiedStep:
    """Apply the impact map to the pre-impact state ``(tau, sdot)`` on ``wall`` (balls): the departure
    (:func:`certified_departure`: the reset, or the sticking policy's stick and release), then the
    certified first impact (Eqs. 7-8) with the mean-value enclosure (:func:`mean_value_impact`)."""
    dep = certified_departure(model, tau, sdot, wall, prec=prec, stick_time=stick_time)
    if dep.start is None or dep.v0 is None:
        return CertifiedStep(None, None, None, None, dep.stick)
    c = certified_flight(model, dep.start, float(wall), dep.v0, release=dep.release, prec=prec, t_max=t_max)
    new_tau, c.v = mean_value_impact(model, c, dep.start, float(wall), dep.v0, dep.release, prec, t_max)
    return CertifiedStep(new_tau, c.v, c.wall, c, dep.stick, dep.rel, dep.pieces)


def certify_orbit(
    params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None = None,
    *,
    prec: int = PREC,
    stick_time: float = STICK_TIME,
    radius_limit: float | None = None,
    t_max: float = T_MAX,
) -> CertifiedOrbit:
    """Certified impact sequence with the layout of :class:`core.results.ImpactSequence`.

    Every event is an enclosure (balls) proven by :func:`~.contact.certified_flight` and the certified
    sticking decisions (:mod:`.sticking`), step by step (:func:`certified_step`).

    Parameters
    ----------
    params : Params or mapping
        A :class:`Params` (float64 values, exact) or a mapping of decimal strings (exact decimals, see
        :class:`Model`).
    tau0, sdot0 : float
        Impact 0: the pre-impact initial state (``s0`` None; exact), or with ``s0`` the free state
        ``(tau0, s0, sdot0)`` whose first impact is impact 0.
    n_impacts : int
        Impacts after impact 0, ``0 <= n_impacts <= 1e7``.
    s0 : float, optional
        A start in free flight, ``-1 <= s0 <= 0``.
    prec : int, optional
        Working precision in bits, ``64 <= prec <= 65536``.
    stick_time : float, optional
        The sticking policy's threshold (:data:`mapimpl.sticking.STICK_TIME`).
    radius_limit : float, optional
        Stop when a radius exceeds it (the last certified event within the limit is kept), ``0 < radius_limit <= 1``.
    t_max : float, optional
        Longest flight searched, ``0 < t_max <= 1e6``.

    Returns
    -------
    CertifiedOrbit
        ``events`` (:class:`Event`: ``n, tau, theta, wall, sdot, kind`` as balls), ``status``
        (``active`` or ``stuck_forever``), ``stop_reason``, ``prec`` and the flight certificates.

    Examples
    --------
    The first ten impacts of :func:`gear_rattle.orbit`'s example, proven; the float64 map lies in
    every ball:

    >>> import gear_rattle as gr
    >>> from gear_rattle.mapimpl.certified.orbit import certify_orbit
    >>> p = gr.Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.9)
    >>> cert = certify_orbit(p, 0.0, 0.5, 10)
    >>> cert.status, len(cert.events), cert.events[10].wall
    ('active', 11, 0)
    >>> seq = gr.orbit(p, 0.0, 0.5, 10)
    >>> all(abs(float(e.tau) - t) <= float(e.tau.rad()) + 1e-14 for e, t in zip(cert.events, seq.tau))
    True
    """
    n_impacts = check_int("n_impacts", n_impacts, 0, MAX_IMPACTS)
    tau0, sdot0, s0 = check_start(tau0, sdot0, s0)
    check_prec(prec)
    stick_time = check_real("stick_time", stick_time, 0.0, MAX_STICK_TIME)
    if radius_limit is not None:
        radius_limit = check_real("radius_limit", radius_limit, 0.0, 1.0, lo_open=True)
    t_max = check_real("t_max", t_max, 0.0, 1e6, lo_open=True)
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
                add(
                    n - 1,
                    st.release,
                    wall,
                    None,
                    "release",
                    {"source": "closed form zero of f, certified", "pieces": st.release_pieces},
                )
            tau1, sdot1, wall1, flight1 = st.landed()
            if radius_limit is not None and max(float(tau1.rad()), float(sdot1.rad())) > radius_limit:
                reason = f"radius limit {radius_limit:g} exceeded at impact {n}"
                break
            tau, sdot, wall = tau1, sdot1, wall1
            flights.append(_flight_record(n, flight1))
            add(n, tau, wall, sdot, "impact", {"source": "certified flight"})
        return CertifiedOrbit(events, status, reason, prec, flights)


def _flight_record(n: int, c: FlightCertificate) -> dict:
    return {
        "impact": n,
        "wall": c.wall,
        "bracket": list(c.bracket),
        "pieces": c.pieces,
        "evals": c.evals,
        "departure": c.departure,
    }


__all__ = [
    "Event",
    "CertifiedOrbit",
    "CertifiedStep",
    "Departure",
    "certified_departure",
    "certified_step",
    "certify_orbit",
]
