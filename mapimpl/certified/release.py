"""Certified post-release duration ``T_post`` of the canonical release orbit (Figs. 9-11 setting).

At the paper's transient setting (alpha = 1.245, beta = gamma = 0.1, r = 0.9) 17.6% of the Fig. 11
mesh chatters and sticks to the upper wall.  The sticking policy (:mod:`mapimpl.sticking`) releases
every stuck orbit at the canonical phase of the wall (a function of the parameters alone) with
``sdot = 0``, so all of them continue on **one** post-release orbit, and the transient duration of
an initial condition that first sticks at its impact ``n_s`` is ``n_s + T_post``.  That orbit is
chaotic: in float64 it loses every digit after a few tens of impacts (see
:func:`mapimpl.float64_release.float64_horizon`), so a float64 ``T_post`` is a sample,
not a value.  Here it is a value.

**Definition.**  The release flight leaves ``wall`` at the canonical release phase with
``sdot = 0``; its first impact is post-release impact 1.  ``T_post`` is the index of the first
post-release impact whose pre-impact state lies within ``delta`` of the stable 4-impact period-1
orbit: sup norm of ``(wrapped phase difference, sdot difference)`` to the nearest target point on
the same wall (:mod:`.capture`).  The orbit follows the sticking policy exactly as
:mod:`.orbit` does; if it sticks again to a wall it has already been
released from, it repeats itself from that release and is never captured (status ``periodic``).

**Certification** (:func:`certified_release_duration`): the orbit is computed with
:func:`.orbit.certified_step` in ball arithmetic (python-flint ``arb``) at a precision ``p``; at
every post-release impact ``n`` the distance ball must be certified ``>= delta`` (not captured) or
``< delta`` (captured), and every flight and sticking decision certified as in the golden suite.
An attempt that cannot decide something (the balls have grown too wide: chaos doubles their radius
about every impact) fails at that impact, and the next precision is tried; the first precision that
decides everything up to capture gives the value, and the next precision must give the same value
(the schedule: :mod:`.duration`).  This module holds one attempt at one precision
(:func:`certify_post_release_deltas`).

**What is exact and what is not.**  The parameters are balls around the *decimal* values as printed
(``arb("1.245")``) or exact float64 numbers (``rounding="float64"``); ``delta`` and
``STICK_TIME`` are the float64 numbers of the engine; the capture target is the float64 4-cycle of
:func:`mapimpl.engine.transients.periodic_target` taken as exact numbers (a certified distance to
those points, not to the true periodic orbit, which lies within ~1e-15 of them).

CLI: ``python -m gear_rattle.validation.commands.release [--rounding both] [--precisions ...]``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from flint import arb

from ...core import checks
from ...core.checks import check_array, check_int, check_real
from ...core.paper import DELTA, MAX_DELTA
from ..sticking import STICK_TIME
from .balls import CertificationError, mod_two_pi, nearest_float, precision, span
from .capture import Target, capture_decision, certified_distance
from .contact import certified_flight
from .model import Model
from .orbit import certified_step
from .sticking import certify_zero, release_phase

#: Most post-release impacts certified per attempt.
MAX_IMPACTS = 20000
#: An attempt stops once a ball radius exceeds this (its decisions would soon be undecidable).
RADIUS_LIMIT = 1e-12
#: Outcomes: definite ones (certified) and the failure of an attempt.
DEFINITE = ("captured", "periodic", "stuck_forever", "no_capture")


@dataclass
class Attempt:
    """One certified run at ``prec`` bits.

    ``status``: ``captured`` (``impacts`` = T_post), ``periodic`` (stuck again at a wall it was
    released from, at impact ``impacts``: never captured), ``stuck_forever``, ``no_capture`` (every
    impact up to ``impacts = max_impacts`` certified not captured), or ``failed`` (``reason``;
    impacts 1..``impacts`` certified not captured, impact ``impacts + 1`` undecided).
    ``radius``: largest ball radius (tau or sdot) at the last certified impact (decimal text: it
    is often below float64's range); ``growth``:
    least-squares slope of ``log2`` of that radius per impact (bits lost per impact);
    ``distance``: the certified distance at capture (decimal); ``closest``: the smallest lower bound
    of the distance over the earlier impacts (how close a miss came); ``walls_stuck``: walls stuck to
    after the release; ``seconds``: wall time; ``orbit``: with ``record``, the float64 midpoints
    ``(theta, sdot, wall)`` of the certified post-release impacts 1, 2, ...
    """

    prec: int
    status: str
    impacts: int
    reason: str
    radius: str
    growth: float
    distance: str | None
    closest: float | None
    walls_stuck: list
    seconds: float
    orbit: list = field(default_factory=list)

    @property
    def definite(self) -> bool:
        return self.status in DEFINITE


def _slope(xs: list, ys: list) -> float:
    if len(xs) < 2:
        return float("nan")
    xm, ym = sum(xs) / len(xs), sum(ys) / len(ys)
    den = sum((x - xm) ** 2 for x in xs)
    return sum((x - xm) * (y - ym) for x, y in zip(xs, ys)) / den if den > 0 else float("nan")


def _log2_radius(*balls: arb) -> float:
    """``log2`` of the largest radius of ``balls`` (``-inf`` when all are exact); computed in ``arb``
    because the radii at thousands of bits are far below float64's range."""
    r = balls[0].rad()
    for b in balls[1:]:
        r = r.max(b.rad())
    if r.is_zero():
        return -math.inf
    return float(r.log() / arb(2).log())


def _radius_text(log2r: float) -> str:
    if log2r == -math.inf:
        return "0"
    e = log2r * math.log10(2)
    k = math.floor(e)
    return f"{10 ** (e - k):.2f}e{k:d}"


def check_deltas(deltas) -> tuple:
    """The distinct capture distances of ``deltas`` (a number or a sequence), largest first."""
    d = check_array(
        "deltas",
        deltas,
        0.0,
        MAX_DELTA,
        nonzero=True,
        max_size=1000,
        allowed=f"finite capture distances 0 < delta <= {MAX_DELTA:g}",
    )
    return tuple(sorted(set(d.tolist()), reverse=True))


def certify_post_release(
    params,
    wall: int = 0,
    *,
    prec: int,
    target: Target,
    delta: float = DELTA,
    max_impacts: int = MAX_IMPACTS,
    stick_time: float = STICK_TIME,
    radius_limit: float = RADIUS_LIMIT,
    deadline: float | None = None,
    progress=None,
    record: bool = False,
) -> Attempt:
    """Certify the post-release orbit of ``wall`` at ``prec`` bits (see module docstring): the
    :class:`Attempt` for one capture distance ``delta`` (:func:`certify_post_release_deltas`).

    ``params``: :class:`Params` (exact floats) or a mapping of decimal strings (:class:`.model.Model`);
    ``deadline``: a ``time.monotonic()`` value after which the attempt stops (status ``failed``);
    ``progress(prec, n, radius)``: called every 50 impacts (``radius``: decimal text).  At most ``max_impacts`` impacts; every
    flight has the interval budget of :func:`.contact.certified_flight`: the attempt always ends.
    """
    delta = check_real("delta", delta, 0.0, MAX_DELTA, lo_open=True)
    return certify_post_release_deltas(
        params,
        wall,
        prec=prec,
        target=target,
        deltas=(delta,),
        max_impacts=max_impacts,
        stick_time=stick_time,
        radius_limit=radius_limit,
        deadline=deadline,
        progress=progress,
        record=record,
    )[float(delta)]


def _budget_end(n: int, max_impacts: int, deadline: float | None) -> tuple[str, str] | None:
    """``(status, reason)`` when the run must stop after impact ``n`` (impacts or time spent), else None."""
    if n >= max_impacts:
        return "no_capture", f"no capture within max_impacts={max_impacts}"
    if deadline is not None and time.monotonic() > deadline:
        return "failed", f"time budget exhausted after impact {n}"
    return None


def _stick_end(st, cur: int, n: int, walls_stuck: list, released_from: set) -> tuple[str, str] | None:
    """After the certified step ``st`` from impact ``n`` on wall ``cur``: ``(status, reason)`` when the orbit
    sticks forever or sticks again to a wall it was released from (it repeats: never captured), else None
    (``walls_stuck`` and ``released_from`` updated)."""
    if st.stick is None:
        return None
    walls_stuck.append(cur)
    if st.tau is None:
        return "stuck_forever", f"stuck forever to wall {cur} after impact {n}"
    if cur in released_from:
        return "periodic", (
            f"sticks again to wall {cur} after impact {n}: the orbit repeats from its release and is never captured"
        )
    released_from.add(cur)
    return None


@dataclass
class _Trace:
    """What a run at ``prec`` bits (started at ``t0``) has certified so far: ``n`` impacts, ``log2r`` (log2
    of the largest radius at impact ``n``), ``xs``/``ys`` (the impacts with a nonzero radius and log2 of
    it), the walls stuck to after the release and, with ``record``, the orbit's float64 midpoints."""

    prec: int
    t0: float
    n: int = 0
    log2r: float = -math.inf
    xs: list[int] = field(default_factory=list)
    ys: list[float] = field(default_factory=list)
    walls_stuck: list = field(default_factory=list)
    orbit: list = field(default_factory=list)

    def impact(self, lr: float) -> None:
        """Impact ``n + 1`` certified, with ``log2`` of its largest radius ``lr``."""
        self.n, self.log2r = self.n + 1, lr
        if lr > -math.inf:
            self.xs.append(self.n)
            self.ys.append(lr)

    def attempt(self, status: str, reason: str, closest: float | None, dist_text: str | None = None) -> Attempt:
        """The :class:`Attempt` of an outcome reached after the ``n`` impacts certified so far."""
        k = sum(1 for x in self.xs if x <= self.n)
        return Attempt(
            self.prec,
            status,
            self.n,
            reason,
            _radius_text(self.log2r),
            _slope(self.xs[:k], self.ys[:k]),
            dist_text,
            closest,
            list(self.walls_stuck),
            time.monotonic() - self.t0,
            list(self.orbit[: self.n]),
        )


def certify_post_release_deltas(
    params,
    wall: int = 0,
    *,
    prec: int,
    target: Target,
    deltas=(DELTA,),
    max_impacts: int = MAX_IMPACTS,
    stick_time: float = STICK_TIME,
    radius_limit: float = RADIUS_LIMIT,
    deadline: float | None = None,
    progress=None,
    record: bool = False,
) -> dict[float, Attempt]:
    """One certified run of the post-release orbit of ``wall`` at ``prec`` bits that decides every
    capture distance of ``deltas`` at once: ``{delta: Attempt}``.

    The orbit is the same for every ``delta``; each distance has its own outcome (the first impact
    certified within it, or the impact whose capture decision is undecided), and the run goes on until
    every distance has one.  An :class:`Attempt` is exactly what a run for its ``delta`` alone gives
    (its ``seconds``: when its outcome was reached).  Other arguments: :func:`certify_post_release`.
    """
    if wall not in (0, -1):
        raise ValueError(f"wall={wall!r} is out of range: allowed 0 (upper, s = 0) or -1 (lower, s = -1)")
    check_int("max_impacts", max_impacts, 1, checks.MAX_IMPACTS, strict=True)
    pending = list(check_deltas(deltas))
    trace = _Trace(prec, time.monotonic())
    closest: dict[float, float | None] = {d: None for d in pending}
    log2_limit = math.log2(radius_limit)
    out: dict[float, Attempt] = {}

    def done(ds, status, reason, dist_text=None):
        """The outcome of the distances ``ds`` after the impacts certified so far."""
        for d in ds:
            out[d] = trace.attempt(status, reason, closest[d], dist_text)
            pending.remove(d)

    with precision(prec):
        model = Model(params)
        phase = release_phase(model, wall)
        if phase is None:
            done(list(pending), "stuck_forever", "the contact force never changes sign at this wall")
            return out
        released_from = {wall}
        try:
            # post-release impact 1: the flight leaving the wall at rest at the certified zero of f
            lo, hi = certify_zero(model, phase, wall, prec)
            start = span(lo, hi)
            c = certified_flight(model, start, float(wall), arb(0), release=True, prec=prec)
            tau, sdot, cur = start + c.t, c.v, c.wall
            while True:
                lr = _log2_radius(tau, sdot)
                if lr > log2_limit:
                    done(
                        list(pending),
                        "failed",
                        f"radius {_radius_text(lr)} > radius_limit={radius_limit:g} at impact {trace.n + 1}",
                    )
                    return out
                theta = mod_two_pi(tau)
                dist = certified_distance(theta, sdot, cur, target)
                captured = {}
                for d in list(pending):  # largest first
                    try:
                        captured[d] = capture_decision(dist, d)
                    except CertificationError as e:
                        done([d], "failed", f"{e} (impact {trace.n + 1} undecided)")
                if not pending:
                    return out
                trace.impact(lr)
                n = trace.n
                if record:
                    trace.orbit.append((nearest_float(theta), nearest_float(sdot), cur))
                if progress is not None and n % 50 == 0:
                    progress(prec, n, _radius_text(lr))
                for d in list(pending):
                    if captured[d] and dist is not None:  # (capture_decision: no distance, no capture)
                        done(
                            [d],
                            "captured",
                            f"within delta={d:g} of the target at post-release impact {n}",
                            dist.str(6, radius=True),
                        )
                    elif dist is not None:
                        lb, so_far = float(dist.lower()), closest[d]
                        closest[d] = lb if so_far is None else min(so_far, lb)
                if not pending:
                    return out
                end = _budget_end(n, max_impacts, deadline)
                if end:
                    done(list(pending), *end)
                    return out
                st = certified_step(model, tau, sdot, cur, prec=prec, stick_time=stick_time)
                end = _stick_end(st, cur, n, trace.walls_stuck, released_from)
                if end:
                    done(list(pending), *end)
                    return out
                tau, sdot, cur, _ = st.landed()
        except CertificationError as e:
            done(list(pending), "failed", f"{e} (impact {trace.n + 1} undecided)")
            return out


__all__ = [
    "MAX_IMPACTS",
    "RADIUS_LIMIT",
    "DEFINITE",
    "Attempt",
    "check_deltas",
    "certify_post_release",
    "certify_post_release_deltas",
]
