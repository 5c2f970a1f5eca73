"""The certified track on demand: any orbit, every row proven, precision raised by itself.

:func:`certified_orbit` computes the orbit the other tracks compute (a pre-impact or a free-flight
start, the sticking policy, every ending) in ball arithmetic (:mod:`.orbit`, :mod:`.contact`,
:mod:`.sticking`) and returns, per event, the float64 nearest to the certified value and outward-rounded
float64 bounds ``[lo, hi]`` that contain the exact value (:func:`.balls.float_bounds`).

**Acceptance.**  An event is *certified* when every decision of its step is proven (the wall, no earlier
contact, stick or bounce, the release) and its balls are narrow at float64's scale: each radius at most
``ulp(max(|x|, 2^-60)) / 16`` (:data:`TIGHT_ULPS`), so that ``[lo, hi]`` is one or two ulps wide and the
nearest float64 is the one of the exact value or its neighbour.  A ball wider than that is not presented.

**The schedule.**  A chaotic orbit loses about one bit of its enclosures per impact (the Lyapunov
exponent), so an orbit of ``N`` impacts needs about ``N`` bits.  An attempt at ``prec`` bits runs from the
exact start until it certifies every requested impact or fails at an impact (a decision it cannot make, a
ball too wide); the next attempt restarts *from the start* (a wider ball cannot be made narrower later)
at ``1.15 growth x N + 128`` bits, ``growth`` the bits lost per impact measured by the failed attempt,
at least ``1.25 prec`` and, where the attempt covered less than a fifth of the orbit, at most ``4 prec``
(twice ``prec`` where it failed within 32 impacts), up to ``max_prec`` (:data:`MAX_TRACK_PREC`;
``_next_prec``).  The best attempt's certified prefix is kept.
Within an attempt each step runs at a working precision just above what its inputs still carry
(:func:`working_precision`): the radius grows from ``2^-prec`` and a step whose balls carry ``b`` bits is
computed with ``b + GUARD_BITS`` (rounding adds ``2^-GUARD_BITS`` of the radius), but never with more
than the rest of the orbit needs at the growth an earlier attempt measured (after a transient ends in a
stable orbit the radius shrinks again).  The covering proof of a flight runs at :data:`COVER_PREC` bits
and the impact's root is refined by one interval Newton step at the working precision
(:func:`.contact.refine_from`).

**Endings** (``status``): ``active`` (every requested impact), ``stuck_forever`` (the policy proves the
tooth stays stuck: a ``stick`` row, no release), ``no_impact`` (the flight after the last impact, or a
free-flight start, is proven to reach no wall within the orbit horizon of every track,
:data:`core.horizons.T_MAX`; with ``gamma = 0`` also for all time, :func:`.noimpact.certify_never_lands`),
or ``uncertified`` (``first_uncertified``: the first impact no precision up to ``max_prec``
certified, ``reason`` why; ``rows`` hold the certified prefix: every event of impacts
``0 .. first_uncertified - 1``, the stick/release rows after the last one left out).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from flint import arb

from ...core.params import Params
from ...core.results import ImpactSequence
from ...core.checks import MAX_IMPACTS, check_int, check_real, check_start

# the orbit horizon of every track: a flight proven to reach no wall within it ends the orbit with no_impact
from ...core.horizons import T_MAX
from ..sticking import STICK_TIME, check_stick_time
from .balls import (
    PREC,
    check_prec,
    CertificationError,
    decimal_interval,
    exact,
    float_bounds,
    mod_two_pi,
    nearest_float,
    precision,
)
from .contact import NoContactError, certified_flight, mean_value_impact
from .model import Model
from .orbit import Event, certified_departure

#: The first precision of the schedule (bits).
START_PREC = PREC
#: Highest precision the schedule reaches by default (bits): about 30 000 impacts of a chaotic orbit
#: losing one bit per impact.
MAX_TRACK_PREC = 1 << 15
#: Bits kept beyond a step's inputs (:func:`working_precision`), and the least working precision.
GUARD_BITS, MIN_WORK_PREC = 64, 128
#: Precision of the covering proof of a flight (``_flight``).
COVER_PREC = 128
#: A ball is narrow enough when its radius is at most ``ulp / TIGHT_ULPS`` (at the scale ``max(|x|, 2^-60)``).
TIGHT_ULPS = 16
#: The smallest magnitude whose ulp scales the acceptance (values nearer 0 are held to ``ulp(2^-60)``).
TIGHT_FLOOR = 2.0**-60
#: Bits the next attempt adds beyond the estimate ``growth x impacts``, and the impacts over which an
#: attempt must have measured its growth for the estimate to be used (``_next_prec``).
MARGIN_BITS, GROWTH_IMPACTS = 128, 32
#: The reason of an attempt stopped by a ball too wide (more precision would narrow it).
WIDE = "its enclosure is wider than float64's resolution"
#: The reason of an attempt stopped by the time budget.
TIME_OUT = "the time budget is spent"
#: Significant digits of the decimal intervals of the JSON output (:meth:`CertifiedSequence.as_dict`).
DECIMAL_DIGITS = 20
#: Bits at which the ends of a ball are read for its decimal interval (far beyond ``DECIMAL_DIGITS``).
DECIMAL_PREC = 256
#: Columns of the bounds, after :data:`core.results.COLUMNS`.
BOUND_COLUMNS = ("tau_lo", "tau_hi", "tau_mod_2pi_lo", "tau_mod_2pi_hi", "sdot_lo", "sdot_hi")


@dataclass
class Attempt:
    """One run at ``prec`` bits: ``reached`` (the last impact it certified, -1 for none), ``reason`` (why it
    stopped: empty when complete), ``growth`` (bits lost per impact, NaN when unmeasured), ``seconds``."""

    prec: int
    reached: int
    complete: bool
    reason: str
    growth: float
    seconds: float


@dataclass
class CertifiedRun:
    """A certified orbit (:func:`certified_orbit`).

    ``events``: the certified events as balls (:class:`.orbit.Event`, the layout of
    :func:`.orbit.certify_orbit`: the golden generator's functions take them); ``rows``: per event ``n,
    kind, wall`` and the float64 nearest values and bounds of ``tau``, ``tau_mod_2pi`` and ``sdot`` (NaN on
    stick/release rows); ``status``: ``active``, ``stuck_forever``, ``no_impact`` or ``uncertified``;
    ``complete``: every requested impact and the ending certified; ``first_uncertified``: the first impact
    not certified (None when complete); ``reason``: how the orbit ended, or why it is incomplete;
    ``precision``: the bits of the attempt kept; ``attempts``: every attempt.
    """

    params: Params
    tau0: float
    sdot0: float
    s0: float | None
    n_impacts: int
    stick_time: float
    events: list
    status: str
    complete: bool
    first_uncertified: int | None
    reason: str
    precision: int
    attempts: list
    seconds: float
    rows: dict = field(default_factory=dict)

    @property
    def impacts_certified(self) -> int:
        """Impact rows certified (impact 0 included)."""
        return sum(1 for e in self.events if e.kind == "impact")

    def sequence(self) -> "CertifiedSequence":
        """The rows as an :class:`ImpactSequence` of track ``certified`` with the bounds columns
        (:class:`CertifiedSequence`); an incomplete run gives its certified prefix, with status
        ``active`` and ``certified["complete"] = False``."""
        r = self.rows
        status = "active" if self.status == "uncertified" else self.status
        meta = {
            "tau0": self.tau0,
            "sdot0": self.sdot0,
            "s0": self.s0,
            "n_impacts": self.n_impacts,
            "stick_time": self.stick_time,
        }
        cert = {
            "complete": self.complete,
            "first_uncertified": self.first_uncertified,
            "reason": self.reason,
            "precision_bits": self.precision,
            "attempts": [a.__dict__ | {"growth": _finite(a.growth)} for a in self.attempts],
        }
        return CertifiedSequence(
            self.params,
            r["n"],
            r["tau"],
            r["theta"],
            r["wall"],
            r["sdot"],
            r["kind"],
            status=status,
            track="certified",
            meta=meta,
            bounds={k: r[k] for k in BOUND_COLUMNS},
            certified=cert,
            balls=list(self.events),
        )


def _finite(x: float):
    return x if math.isfinite(x) else None


@dataclass
class CertifiedSequence(ImpactSequence):
    """An :class:`ImpactSequence` whose rows are certified (track ``certified``): the values are the float64
    nearest to the exact ones and ``bounds`` holds, per column of :data:`BOUND_COLUMNS`, float64 bounds that
    contain them; ``certified``: ``complete``, ``first_uncertified``, ``reason``, ``precision_bits``,
    ``attempts`` (a prefix when not complete)."""

    bounds: dict = field(default_factory=dict)
    certified: dict = field(default_factory=dict)
    #: The certified events as balls (:class:`.orbit.Event`), one per row: the decimal intervals of :meth:`as_dict`.
    balls: list = field(default_factory=list)

    def rows(self) -> list[dict]:
        """The events with the :data:`core.results.COLUMNS` keys and the bounds (None on stick/release
        rows' ``sdot``)."""
        out = super().rows()
        for i, row in enumerate(out):
            for k in BOUND_COLUMNS:
                v = float(self.bounds[k][i])
                row[k] = None if math.isnan(v) else v
        return out

    def table(self) -> tuple[list[str], list[list]]:
        """The columns (:data:`core.results.COLUMNS`, then :data:`BOUND_COLUMNS`) and the rows."""
        cols = list(super().table()[0]) + list(BOUND_COLUMNS)
        return cols, [[r[c] for c in cols] for r in self.rows()]

    def arrays(self) -> dict:
        return (
            super().arrays()
            | {k: np.asarray(v) for k, v in self.bounds.items()}
            | {"complete": self.certified.get("complete", True)}
        )

    def as_dict(self) -> dict:
        """The JSON content: the rows with their float64 bounds and, per row, decimal intervals
        ``tau_decimal``, ``tau_mod_2pi_decimal``, ``sdot_decimal`` (``[lo, hi]``, :data:`DECIMAL_DIGITS`
        significant digits, rounded outward from the ball: :func:`.balls.decimal_interval`, as the orbit
        records print theirs; None on stick/release rows' ``sdot``), and ``certified``."""
        out = super().as_dict() | {"certified": self.certified}
        with precision(DECIMAL_PREC):  # the ends of a ball are read at the context's precision
            for row, e in zip(out["events"], self.balls):
                for name, ball in (("tau", e.tau), ("tau_mod_2pi", e.theta), ("sdot", e.sdot)):
                    row[name + "_decimal"] = None if ball is None else list(decimal_interval(ball, DECIMAL_DIGITS))
        return out


class UncertifiedOrbit(CertificationError):
    """No precision up to the limit certified every requested impact; ``run`` (:class:`CertifiedRun`) and
    ``sequence`` (its certified prefix) say how far it got."""

    def __init__(self, run: CertifiedRun):
        super().__init__(f"impact {run.first_uncertified} not certified: {run.reason}")
        self.run = run
        self.sequence = run.sequence()


# ---------------------------------------------------------------------------------------------------------


def _tight(x: arb) -> bool:
    """Whether the ball ``x`` is narrow at float64's scale (see the module docstring)."""
    if not x.is_finite():
        return False
    m = abs(float(x.mid()))
    return bool(x.rad() <= arb(math.ulp(max(m, TIGHT_FLOOR)) / TIGHT_ULPS))


def _log2_upper(x: arb) -> float:
    """``log2`` of the exact nonnegative ball end ``x`` (a radius), from its mantissa and exponent: no
    logarithm at the working precision (``-inf`` for 0)."""
    man_f, exp_f = x.mid().man_exp()
    man = int(man_f)
    if man == 0:
        return -math.inf
    return int(exp_f) + man.bit_length()


def _bits_left(*balls: arb) -> float:
    """Bits of the balls still meaningful: about ``-log2(radius / max(|mid|, 1))`` of the widest (inf if
    exact); an estimate within one bit, which only chooses a working precision."""
    worst = math.inf
    for b in balls:
        lr = _log2_upper(b.rad())
        if lr == -math.inf:
            continue
        scale = max(abs(float(b.mid())), 1.0)
        worst = min(worst, math.log2(scale) - lr)
    return worst


def working_precision(prec: int, bits_left: float, cap: int | None = None) -> int:
    """The precision of a step whose inputs carry ``bits_left`` bits: ``bits_left + GUARD_BITS`` rounded up
    to a multiple of 64, at least :data:`MIN_WORK_PREC`, at most ``cap`` (the bits the rest of the orbit
    needs, where an earlier attempt measured its growth; not below :data:`MIN_WORK_PREC`) and never above
    ``prec``."""
    top = prec if cap is None else min(prec, max(cap, MIN_WORK_PREC))
    if not math.isfinite(bits_left):
        return top
    w = int(math.ceil((bits_left + GUARD_BITS) / 64.0)) * 64
    return min(top, max(MIN_WORK_PREC, w))


@dataclass
class _Run:
    """What one attempt produced."""

    events: list
    reached: int
    complete: bool
    status: str
    reason: str
    growth: float


def _attempt(
    params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None,
    prec: int,
    stick_time: float,
    t_max: float,
    tick,
    growth_hint: float | None = None,
    deadline: float | None = None,
) -> _Run:
    """One attempt at ``prec`` bits from the exact start (see the module docstring); ``growth_hint``: the
    bits lost per impact an earlier attempt measured (the working precision then stays below what the rest
    of the orbit needs at that rate, :func:`working_precision`)."""
    events: list[Event] = []
    bits0 = float(prec)
    log_bits: list[tuple[int, float]] = []

    def growth() -> float:
        if len(log_bits) < 2:
            return math.nan
        (n0, b0), (n1, b1) = log_bits[0], log_bits[-1]
        return (b0 - b1) / (n1 - n0) if n1 > n0 else math.nan

    def accept(step_events: list[Event]) -> bool:
        for e in step_events:
            if not (_tight(e.tau) and _tight(e.theta) and (e.sdot is None or _tight(e.sdot))):
                return False
        events.extend(step_events)
        return True

    def stopped(n: int, reason: str) -> _Run:
        return _Run(events, n - 1, False, "uncertified", reason, growth())

    with precision(prec):
        model = Model(params)
        try:
            zero = _impact_zero(model, tau0, sdot0, s0, prec, t_max)
            if isinstance(zero, str):
                return _Run(events, -1, True, "no_impact", zero, math.nan)
            tau, sdot, wall = zero
            if not accept([Event(0, tau, mod_two_pi(tau), wall, sdot, "impact")]):
                return stopped(0, WIDE)
        except CertificationError as e:
            return stopped(0, str(e))
        log_bits.append((0, min(bits0, _bits_left(tau, sdot))))
        tick(0, prec)
        for n in range(1, n_impacts + 1):
            if deadline is not None and time.monotonic() > deadline:
                return stopped(n, TIME_OUT)
            cap = None if growth_hint is None else _bits_for(growth_hint, n_impacts - n + 1) + GUARD_BITS
            work = working_precision(prec, _bits_left(tau, sdot), cap)
            try:
                with precision(work):
                    rows, end = _step(model, tau, sdot, wall, n, work, stick_time, t_max)
                    if end is not None:
                        status, reason, which_rows = end
                        if not accept(rows):
                            return stopped(n, WIDE + which_rows)
                        return _Run(events, n - 1, True, status, reason, growth())
            except CertificationError as e:
                return stopped(n, str(e))
            if not accept(rows):
                return stopped(n, WIDE)
            impact = rows[-1]  # impact n: the state the next step starts from
            assert impact.sdot is not None, "an impact row has a velocity"
            tau, sdot, wall = impact.tau, impact.sdot, impact.wall
            log_bits.append((n, _bits_left(tau, sdot)))
            tick(n, prec)
    return _Run(events, n_impacts, True, "active", "n_impacts reached", growth())


def _impact_zero(
    model: Model, tau0: float, sdot0: float, s0: float | None, prec: int, t_max: float
) -> tuple[arb, arb, int] | str:
    """Impact 0 ``(tau, sdot, wall)`` of an attempt, exact or certified at ``prec`` bits (the context's): the
    pre-impact start itself, a start at rest on a wall the force presses into, or the first impact of a
    free-flight start; or, where that flight is proven to reach no wall, the reason of the ``no_impact``
    ending."""
    if s0 is None:
        return exact(tau0), exact(sdot0), (0 if sdot0 > 0 else -1)
    if sdot0 == 0.0 and s0 in (0.0, -1.0) and (1 if s0 == 0.0 else -1) * model.forcing(exact(tau0)) > 0:
        # at rest on a wall that the force presses into: the contact is at once (the map track's
        # rule), impact 0 with sdot 0, and the sticking policy decides what follows
        return exact(tau0), arb(0), (0 if s0 == 0.0 else -1)
    try:
        c = certified_flight(model, exact(tau0), s0, exact(sdot0), prec=prec, t_max=t_max)
    except NoContactError:
        return _no_impact_reason(model, exact(tau0), s0, exact(sdot0), False, prec, t_max, "the free-flight start")
    return exact(tau0) + c.t, c.v, c.wall


def _step(
    model: Model, tau: arb, sdot: arb, wall: int, n: int, work: int, stick_time: float, t_max: float
) -> tuple[list[Event], tuple[str, str, str] | None]:
    """The step from impact ``n - 1`` (``tau, sdot, wall``) at the working precision ``work`` (the context's):
    its rows (a stick, a release, impact ``n``) and ``None``, or, where the orbit ends before impact ``n``
    (stuck forever, a flight proven to reach no wall), the rows before that end and ``(status, reason, the
    rows' name in the reason of an attempt that cannot accept them)``."""
    dep = certified_departure(model, tau, sdot, wall, prec=work, stick_time=stick_time, decide_prec=COVER_PREC)
    rows = []
    if dep.stick is not None:
        rows.append(Event(n - 1, dep.stick, mod_two_pi(dep.stick), wall, None, "stick"))
    if dep.start is None or dep.v0 is None:
        reason = f"stuck forever to wall {wall} after impact {n - 1} (|gamma| >= R)"
        return rows, ("stuck_forever", reason, " (a stick row)")
    if dep.rel is not None:
        rows.append(Event(n - 1, dep.rel, mod_two_pi(dep.rel), wall, None, "release"))
    try:
        c = _flight(model, dep.start, float(wall), dep.v0, dep.release, work, t_max)
    except NoContactError:
        what = f"the flight after impact {n - 1}"
        reason = _no_impact_reason(model, dep.start, float(wall), dep.v0, dep.release, work, t_max, what)
        return rows, ("no_impact", reason, " (a stick/release row)")
    if dep.release or (dep.start.is_exact() and dep.v0.is_exact()):
        new_tau, new_v = c.t + dep.start, c.v  # (_flight refined it at the working precision)
    else:
        new_tau, new_v = mean_value_impact(
            model, c, dep.start, float(wall), dep.v0, dep.release, work, t_max, lean=True
        )
    rows.append(Event(n, new_tau, mod_two_pi(new_tau), c.wall, new_v, "impact"))
    return rows, None


def _flight(model: Model, start: arb, s0: float, v0: arb, release: bool, work: int, t_max: float):
    """The certificate of a flight for the step: the covering proof (no earlier contact, the crossing) at
    :data:`COVER_PREC` bits, which the gaps of a flight away from a graze need, and at the working precision
    where that does not decide; the root is refined at the working precision where the impact's enclosure
    comes from it (a release, exact inputs), else the mean-value form refines the midpoint's root
    (:func:`.contact.mean_value_impact`) and the box's enclosure only bounds its Jacobian."""
    direct = release or (start.is_exact() and v0.is_exact())
    if work > COVER_PREC and not direct:
        try:
            with precision(COVER_PREC):
                return certified_flight(model, start, s0, v0, release=release, prec=COVER_PREC, t_max=t_max)
        except NoContactError:
            raise
        except CertificationError:
            pass  # e.g. a near-tangency that needs more bits: the working precision decides
    return certified_flight(model, start, s0, v0, release=release, prec=work, t_max=t_max)


def _no_impact_reason(
    model: Model, start: arb, s0: float, v0: arb, release: bool, prec: int, t_max: float, what: str
) -> str:
    """The reason of a certified ``no_impact`` ending: no wall within ``t_max`` (proven), and for all time
    where ``gamma = 0`` lets :func:`.noimpact.certify_never_lands` prove it."""
    text = f"{what} reaches no wall within T_MAX={t_max:g} (certified)"
    if model.gamma.is_zero():
        from .noimpact import certify_never_lands

        try:
            certify_never_lands(model, start, s0, v0, release=release, prec=prec)
            text += "; with gamma = 0 it never reaches a wall (certified for all t > 0)"
        except CertificationError:
            pass
    return text


def _next_prec(prec: int, run: _Run, n_impacts: int, max_prec: int) -> int:
    """The next precision of the schedule.  Where the attempt measured its bits lost per impact over at
    least :data:`GROWTH_IMPACTS` impacts: enough for every requested impact, ``1.15 x growth x n_impacts +
    MARGIN_BITS``, and at least ``1.25 prec``; at most 4 ``prec`` where the attempt covered less than a
    fifth of the orbit (a chaotic transient that ends in a stable orbit loses bits only until it ends: an
    estimate from its start can be far too high); else (a
    failure near the start: a tangency, a release) twice ``prec``.  Rounded up to a multiple of 64, at most
    ``max_prec``."""
    if math.isfinite(run.growth) and run.growth > 0 and run.reached >= GROWTH_IMPACTS:
        est = _bits_for(run.growth, n_impacts)
        want = max(int(1.25 * prec), est if 5 * run.reached >= n_impacts else min(4 * prec, est))
    else:
        want = 2 * prec
    return min(max_prec, int(math.ceil(want / 64.0)) * 64)


def _bits_for(growth: float, impacts: int) -> int:
    """Bits that ``impacts`` impacts losing ``growth`` bits each need: ``1.15 growth impacts + MARGIN_BITS``."""
    return int(math.ceil(growth * 1.15 * impacts)) + MARGIN_BITS


def certified_orbit(
    params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    *,
    s0: float | None = None,
    stick_time: float = STICK_TIME,
    prec: int = START_PREC,
    max_prec: int = MAX_TRACK_PREC,
    t_max: float = T_MAX,
    time_budget_s: float | None = None,
    progress=None,
) -> CertifiedRun:
    """The certified orbit: impact 0 and ``n_impacts`` further impacts, every row proven (module docstring).

    Parameters
    ----------
    params : Params or mapping
        A :class:`Params` (float64 values, exact) or a mapping of decimal strings (exact decimals,
        :class:`.model.Model`).
    tau0, sdot0 : float
        Impact 0 as a pre-impact state (``sdot0 != 0``), or with ``s0`` the free state ``(tau0, s0, sdot0)``.
    n_impacts : int
        Impacts after impact 0, ``0 <= n_impacts <= 1e7`` (:data:`core.checks.MAX_IMPACTS`).
    s0 : float, optional
        A start in free flight, ``-1 <= s0 <= 0``.
    stick_time : float, optional
        The sticking policy's threshold (:data:`mapimpl.sticking.STICK_TIME`, the other tracks' value).
    prec, max_prec : int, optional
        The first precision of the schedule and its limit (bits, ``64 .. 65536``).
    t_max : float, optional
        The flight horizon: a flight proven to reach no wall within it ends the orbit (``no_impact``).
    time_budget_s : float, optional
        Wall-time budget of the whole schedule: past it the attempt under way stops and no other starts
        (``uncertified``, the reason says so; the certified prefix is kept).
    progress : optional
        None/True: a bar of the impacts and the precision on a terminal; False: none; a callable
        ``progress(done, total)`` (:mod:`gear_rattle.core.progress`; ``done`` starts again at each
        attempt of the schedule; a :class:`~gear_rattle.core.progress.Bar` also shows the precision).

    Returns
    -------
    CertifiedRun
        The rows (float64 nearest values and bounds), the balls, ``status``, ``complete``,
        ``first_uncertified`` and the attempts.  It never raises for an orbit it cannot certify: it says so.

    Examples
    --------
    >>> import gear_rattle as gr
    >>> from gear_rattle.mapimpl.certified.track import certified_orbit
    >>> run = certified_orbit(gr.Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 10)
    >>> run.status, run.complete, len(run.rows["tau"]), run.precision
    ('active', True, 11, 320)
    >>> bool(all(run.rows["tau_lo"] <= run.rows["tau"]) and all(run.rows["tau"] <= run.rows["tau_hi"]))
    True
    """
    from ...core.params import Params as _P
    from ...core.progress import Bar, sink, wanted

    n_impacts = check_int("n_impacts", n_impacts, 0, MAX_IMPACTS)
    tau0, sdot0, s0 = check_start(tau0, sdot0, s0)
    if s0 is not None and ((s0 == 0.0 and sdot0 > 0.0) or (s0 == -1.0 and sdot0 < 0.0)):
        s0 = None  # on a wall moving into it: the pre-impact state itself (as the map track)
    stick_time = check_stick_time(stick_time)
    prec, max_prec = check_prec(prec, "prec"), check_prec(max_prec, "max_prec")
    prec = min(prec, max_prec)
    t_max = check_real("t_max", t_max, 0.0, 1e6, lo_open=True)
    if time_budget_s is not None:
        time_budget_s = check_real("time_budget_s", time_budget_s, 0.0, lo_open=True)
    p64 = params if isinstance(params, _P) else Model(params).params
    user = sink(progress)
    bar = Bar("certified orbit", total=n_impacts, enabled=wanted(progress), delay=1.0)
    t0 = time.monotonic()
    deadline = None if time_budget_s is None else t0 + float(time_budget_s)
    attempts: list[Attempt] = []
    best: _Run | None = None
    best_prec = prec
    last_tick = [0.0]
    hint: float | None = None

    def tick(done: int, bits: int) -> None:
        now = time.monotonic()
        if done < n_impacts and now - last_tick[0] < 0.1:
            return
        last_tick[0] = now
        if user is not None:
            if isinstance(user, Bar):  # the caller's bar shows the precision too
                user.postfix(f"{bits} bits")
            user(done, n_impacts)
        bar.postfix(f"{bits} bits")
        bar.update(done, n_impacts)

    with bar:
        while True:
            ta = time.monotonic()
            run = _attempt(
                params, tau0, sdot0, n_impacts, s0, prec, float(stick_time), float(t_max), tick, hint, deadline
            )
            attempts.append(
                Attempt(
                    prec,
                    run.reached,
                    run.complete,
                    "" if run.complete else run.reason,
                    run.growth,
                    time.monotonic() - ta,
                )
            )
            if best is None or run.complete or run.reached >= best.reached:
                best, best_prec = run, prec
            if run.complete or prec >= max_prec or run.reason == TIME_OUT:
                break
            prec = _next_prec(prec, run, n_impacts, max_prec)
            if math.isfinite(run.growth) and run.growth > 0 and run.reached >= GROWTH_IMPACTS:
                hint = run.growth
    assert best is not None
    first = None if best.complete else best.reached + 1
    reason = (
        best.reason if best.complete else _incomplete_reason(best, best_prec, attempts[-1], time_budget_s, max_prec)
    )
    out = CertifiedRun(
        p64,
        tau0,
        sdot0,
        s0,
        n_impacts,
        float(stick_time),
        best.events,
        best.status,
        best.complete,
        first,
        reason,
        best_prec,
        attempts,
        time.monotonic() - t0,
    )
    out.rows = rows_of(best.events)
    return out


def _incomplete_reason(best: _Run, best_prec: int, last: Attempt, time_budget_s: float | None, max_prec: int) -> str:
    """Why the schedule kept an incomplete orbit: the time budget ran out during the ``last`` attempt, or
    the best attempt (at ``best_prec`` bits) stopped and no precision up to ``max_prec`` went further."""
    if last.reason == TIME_OUT:
        return (
            f"{TIME_OUT} ({time_budget_s:g} s) at {last.prec} bits; the best attempt ({best_prec} bits) "
            f"stopped: {best.reason}"
            if best_prec != last.prec
            else f"{TIME_OUT} ({time_budget_s:g} s) at {best_prec} bits"
        )
    return (
        f"the precision limit ({max_prec} bits) is reached and {best.reason}"
        if best.reason.startswith(WIDE)
        else f"{best.reason} (at {best_prec} bits; the precision limit is {max_prec} bits)"
    )


def rows_of(events: list) -> dict:
    """Per event ``n, kind, wall`` and the float64 nearest values and bounds (:data:`BOUND_COLUMNS`) of
    ``tau``, ``tau_mod_2pi`` (``theta``) and ``sdot`` (NaN where an event has no velocity)."""
    cols: dict[str, list] = {k: [] for k in ("n", "kind", "wall", "tau", "theta", "sdot") + BOUND_COLUMNS}
    for e in events:
        cols["n"].append(e.n)
        cols["kind"].append(e.kind)
        cols["wall"].append(e.wall)
        for name, prefix, ball in (("tau", "tau", e.tau), ("theta", "tau_mod_2pi", e.theta), ("sdot", "sdot", e.sdot)):
            if ball is None:
                cols[name].append(math.nan)
                cols[prefix + "_lo"].append(math.nan)
                cols[prefix + "_hi"].append(math.nan)
                continue
            lo, hi = float_bounds(ball)
            cols[name].append(min(max(nearest_float(ball), lo), hi))
            cols[prefix + "_lo"].append(lo)
            cols[prefix + "_hi"].append(hi)
    out = {k: np.asarray(v, dtype=float) for k, v in cols.items() if k not in ("n", "kind", "wall")}
    out["n"] = np.asarray(cols["n"], dtype=int)
    out["wall"] = np.asarray(cols["wall"], dtype=int)
    out["kind"] = np.asarray(cols["kind"], dtype=str)
    return out


__all__ = [
    "START_PREC",
    "MAX_TRACK_PREC",
    "DECIMAL_DIGITS",
    "GUARD_BITS",
    "MIN_WORK_PREC",
    "TIGHT_ULPS",
    "BOUND_COLUMNS",
    "Attempt",
    "CertifiedRun",
    "CertifiedSequence",
    "UncertifiedOrbit",
    "certified_orbit",
    "working_precision",
    "rows_of",
    "TRACK_OPTIONS",
    "track_orbit",
]


#: The options of the certified track in :func:`mapimpl.tracks.orbit` (those of :func:`certified_orbit`).
TRACK_OPTIONS = ("stick_time", "prec", "max_prec", "t_max", "time_budget_s")


def track_orbit(
    params: Params, tau0: float, sdot0: float, n_impacts: int, s0: float | None = None, progress=None, **options
) -> CertifiedSequence:
    """The ``certified`` track of :func:`gear_rattle.orbit`: :func:`certified_orbit` as a
    :class:`CertifiedSequence`; :class:`UncertifiedOrbit` (with the certified prefix) when no precision up
    to ``max_prec`` certifies every requested impact.  ``options``: :data:`TRACK_OPTIONS`."""
    for name in options:
        if name not in TRACK_OPTIONS:
            raise ValueError(
                f"option {name}={options[name]!r} is out of range: the certified track takes {', '.join(TRACK_OPTIONS)}"
            )
    run = certified_orbit(params, tau0, sdot0, n_impacts, s0=s0, progress=progress, **options)
    if not run.complete:
        raise UncertifiedOrbit(run)
    return run.sequence()
