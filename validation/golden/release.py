"""Certified post-release duration ``T_post`` of the canonical release orbit (Figs. 9-11 setting).

At the paper's transient setting (alpha = 1.245, beta = gamma = 0.1, r = 0.9) 17.6% of the Fig. 11
mesh chatters and sticks to the upper wall.  The sticking policy (:mod:`mapimpl.sticking`) releases
every stuck orbit at the canonical phase of the wall (a function of the parameters alone) with
``sdot = 0``, so all of them continue on **one** post-release orbit, and the transient duration of
an initial condition that first sticks at its impact ``n_s`` is ``n_s + T_post``.  That orbit is
chaotic: in float64 it loses every digit after a few tens of impacts (see
:func:`float64_horizon`), so a float64 ``T_post`` is a sample, not a value.  Here it is a value.

**Definition.**  The release flight leaves ``wall`` at the canonical release phase with
``sdot = 0``; its first impact is post-release impact 1.  ``T_post`` is the index of the first
post-release impact whose pre-impact state lies within ``delta`` of the stable 4-impact period-1
orbit: sup norm of ``(wrapped phase difference, sdot difference)`` to the nearest target point on
the same wall (:func:`mapimpl.engine.kernel.distance`).  The orbit follows the sticking policy
exactly as :mod:`validation.golden.certify` does; if it sticks again to a wall it has already been
released from, it repeats itself from that release and is never captured (status ``periodic``).

**Certification** (:func:`certified_release_duration`): the orbit is computed with
:func:`certify.certified_step` in ball arithmetic (python-flint ``arb``) at a precision ``p``; at
every post-release impact ``n`` the distance ball must be certified ``>= delta`` (not captured) or
``< delta`` (captured), and every flight and sticking decision certified as in the golden suite.
An attempt that cannot decide something (the balls have grown too wide: chaos doubles their radius
about every impact) fails at that impact, and the next precision is tried; the first precision that
decides everything up to capture gives the value, and the next precision must give the same value.

**What is exact and what is not.**  The parameters are balls around the *decimal* values as printed
(``arb("1.245")``) or exact float64 numbers (``rounding="float64"``); ``delta`` and
``STICK_TIME`` are the float64 numbers of the engine; the capture target is the float64 4-cycle of
:func:`mapimpl.engine.transients.periodic_target` taken as exact numbers (a certified distance to
those points, not to the true periodic orbit, which lies within ~1e-15 of them).

CLI: ``python -m gear_rattle.validation.golden.release [--rounding both] [--precisions ...]``.
"""

from __future__ import annotations

import argparse
import json
import math
import numbers
import sys
import time
from dataclasses import asdict, dataclass, field

from flint import arb

from ...mapimpl.engine.transients import DELTA as ENGINE_DELTA
from ...mapimpl.params import Params
from ...mapimpl.sticking import STICK_TIME
from . import certify as cert

#: The printed parameters of the paper's Figs. 9-11 (exact decimals).
PAPER_DECIMAL = {"alpha": "1.245", "beta": "0.1", "gamma": "0.1", "r": "0.9"}
#: Capture distance: the engine's default.
DELTA = ENGINE_DELTA
#: Precision schedule (bits) of :func:`certified_release_duration`.
PRECISIONS = (256, 512, 1024, 2048, 4096, 8192)
#: Most post-release impacts certified per attempt.
MAX_IMPACTS = 20000
#: An attempt stops once a ball radius exceeds this (its decisions would soon be undecidable).
RADIUS_LIMIT = 1e-12
ROUNDINGS = ("decimal", "float64")
#: Outcomes: definite ones (certified) and the failure of an attempt.
DEFINITE = ("captured", "periodic", "stuck_forever", "no_capture")


# ---------------------------------------------------------------------------------------------
# capture target and distance


@dataclass(frozen=True)
class Target:
    """The capture target: pre-impact points ``(theta, sdot, wall)`` (float64, taken as exact)."""

    theta: tuple
    sdot: tuple
    wall: tuple

    def as_dict(self) -> dict:
        return {"theta": [repr(float(x)) for x in self.theta], "sdot": [repr(float(x)) for x in self.sdot],
                "wall": [int(w) for w in self.wall]}


def float64_target(params: Params) -> Target:
    """The float64 4-impact period-1 orbit of the engine (:func:`periodic_target`), as exact points."""
    from ...mapimpl.engine.transients import periodic_target

    t = periodic_target(params)
    return Target(tuple(float(x) for x in t.theta), tuple(float(x) for x in t.sdot), tuple(int(w) for w in t.wall))


def certified_distance(theta: arb, sdot: arb, wall: int, target: Target) -> arb | None:
    """Ball enclosing the sup-norm distance of the pre-impact state ``(theta, sdot)`` on ``wall`` to
    the nearest target point on the same wall (phase difference wrapped to ``[0, pi]``), as
    :func:`mapimpl.engine.kernel.distance` defines it; ``None`` (infinite) when no point is on
    ``wall``.  ``theta`` must lie in ``[0, 2 pi)``."""
    two_pi = 2 * arb.pi()
    best = None
    for th_p, v_p, w_p in zip(target.theta, target.sdot, target.wall):
        if w_p != wall:
            continue
        dth = abs(theta - arb(th_p))
        d = dth.min(two_pi - dth).max(abs(sdot - arb(v_p)))
        best = d if best is None else best.min(d)
    return best


def capture_decision(distance: arb | None, delta: float) -> bool:
    """Whether the pre-impact state at the certified ``distance`` (:func:`certified_distance`; ``None``:
    no target point on its wall) is captured: certified ``distance < delta`` (True) or ``>= delta``
    (False); raises :class:`certify.CertificationError` when the ball straddles ``delta``."""
    if distance is None:
        return False
    dl = cert.exact(delta)
    if distance < dl:
        return True
    if distance >= dl:
        return False
    raise cert.CertificationError(f"capture decision not definite: distance {distance.str(5)} straddles "
                                  f"delta={delta:g}")


# ---------------------------------------------------------------------------------------------
# one certified attempt at one precision


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


def _check_deltas(deltas) -> tuple:
    """The distinct capture distances of ``deltas`` (a number or a sequence), largest first."""
    vals = [deltas] if isinstance(deltas, numbers.Real) else list(deltas)
    if not vals:
        raise ValueError("deltas is empty: allowed one or more finite capture distances > 0")
    for d in vals:
        if not (isinstance(d, numbers.Real) and math.isfinite(d) and d > 0):
            raise ValueError(f"delta={d!r} is out of range: allowed finite delta > 0")
    return tuple(sorted({float(d) for d in vals}, reverse=True))


def certify_post_release(params, wall: int = 0, *, prec: int, target: Target, delta: float = DELTA,
                         max_impacts: int = MAX_IMPACTS, stick_time: float = STICK_TIME,
                         radius_limit: float = RADIUS_LIMIT, deadline: float | None = None,
                         progress=None, record: bool = False) -> Attempt:
    """Certify the post-release orbit of ``wall`` at ``prec`` bits (see module docstring): the
    :class:`Attempt` for one capture distance ``delta`` (:func:`certify_post_release_deltas`).

    ``params``: :class:`Params` (exact floats) or a mapping of decimal strings (:class:`certify.Model`);
    ``deadline``: a ``time.monotonic()`` value after which the attempt stops (status ``failed``);
    ``progress(prec, n, radius)``: called every 50 impacts (``radius``: decimal text).  At most ``max_impacts`` impacts; every
    flight has the interval budget of :func:`certify.certified_flight`: the attempt always ends.
    """
    if not (isinstance(delta, numbers.Real) and math.isfinite(delta) and delta > 0):
        raise ValueError(f"delta={delta!r} is out of range: allowed finite delta > 0")
    return certify_post_release_deltas(params, wall, prec=prec, target=target, deltas=(delta,),
                                       max_impacts=max_impacts, stick_time=stick_time, radius_limit=radius_limit,
                                       deadline=deadline, progress=progress, record=record)[float(delta)]


def certify_post_release_deltas(params, wall: int = 0, *, prec: int, target: Target, deltas=(DELTA,),
                                max_impacts: int = MAX_IMPACTS, stick_time: float = STICK_TIME,
                                radius_limit: float = RADIUS_LIMIT, deadline: float | None = None,
                                progress=None, record: bool = False) -> dict[float, Attempt]:
    """One certified run of the post-release orbit of ``wall`` at ``prec`` bits that decides every
    capture distance of ``deltas`` at once: ``{delta: Attempt}``.

    The orbit is the same for every ``delta``; each distance has its own outcome (the first impact
    certified within it, or the impact whose capture decision is undecided), and the run goes on until
    every distance has one.  An :class:`Attempt` is exactly what a run for its ``delta`` alone gives
    (its ``seconds``: when its outcome was reached).  Other arguments: :func:`certify_post_release`.
    """
    if wall not in (0, -1):
        raise ValueError(f"wall={wall!r} is out of range: allowed 0 (upper, s = 0) or -1 (lower, s = -1)")
    if not (isinstance(max_impacts, int) and max_impacts >= 1):
        raise ValueError(f"max_impacts={max_impacts!r} is out of range: allowed integer >= 1")
    pending = list(_check_deltas(deltas))
    t0 = time.monotonic()
    xs, ys = [], []
    closest: dict[float, float | None] = {d: None for d in pending}
    walls_stuck: list = []
    n, log2r = 0, -math.inf
    log2_limit = math.log2(radius_limit)
    orbit: list = []
    out: dict[float, Attempt] = {}

    def done(ds, status, reason, dist_text=None):
        """The outcome of the distances ``ds`` after ``n`` certified impacts."""
        k = sum(1 for x in xs if x <= n)
        for d in ds:
            out[d] = Attempt(prec, status, n, reason, _radius_text(log2r), _slope(xs[:k], ys[:k]), dist_text,
                             closest[d], list(walls_stuck), time.monotonic() - t0, list(orbit[:n]))
            pending.remove(d)

    with cert.precision(prec):
        model = cert.Model(params)
        phase = cert.release_phase(model, wall)
        if phase is None:
            done(list(pending), "stuck_forever", "the contact force never changes sign at this wall")
            return out
        released_from = {wall}
        try:
            # post-release impact 1: the flight leaving the wall at rest at the certified zero of f
            lo, hi = cert.certify_zero(model, phase, wall, prec)
            start = cert.span(lo, hi)
            c = cert.certified_flight(model, start, float(wall), arb(0), release=True, prec=prec)
            tau, sdot, cur = start + c.t, c.v, c.wall
            while True:
                lr = _log2_radius(tau, sdot)
                if lr > log2_limit:
                    done(list(pending), "failed",
                         f"radius {_radius_text(lr)} > radius_limit={radius_limit:g} at impact {n + 1}")
                    return out
                theta = cert.mod_two_pi(tau)
                dist = certified_distance(theta, sdot, cur, target)
                captured = {}
                for d in list(pending):  # largest first
                    try:
                        captured[d] = capture_decision(dist, d)
                    except cert.CertificationError as e:
                        done([d], "failed", f"{e} (impact {n + 1} undecided)")
                if not pending:
                    return out
                n, log2r = n + 1, lr
                if record:
                    orbit.append((cert.nearest_float(theta), cert.nearest_float(sdot), cur))
                if lr > -math.inf:
                    xs.append(n)
                    ys.append(lr)
                if progress is not None and n % 50 == 0:
                    progress(prec, n, _radius_text(lr))
                for d in list(pending):
                    if captured[d]:
                        done([d], "captured", f"within delta={d:g} of the target at post-release impact {n}",
                             dist.str(6, radius=True))
                    elif dist is not None:
                        lb = float(dist.lower())
                        closest[d] = lb if closest[d] is None else min(closest[d], lb)
                if not pending:
                    return out
                if n >= max_impacts:
                    done(list(pending), "no_capture", f"no capture within max_impacts={max_impacts}")
                    return out
                if deadline is not None and time.monotonic() > deadline:
                    done(list(pending), "failed", f"time budget exhausted after impact {n}")
                    return out
                st = cert.certified_step(model, tau, sdot, cur, prec=prec, stick_time=stick_time)
                if st.stick is not None:
                    walls_stuck.append(cur)
                    if st.tau is None:
                        done(list(pending), "stuck_forever", f"stuck forever to wall {cur} after impact {n}")
                        return out
                    if cur in released_from:
                        done(list(pending), "periodic", f"sticks again to wall {cur} after impact {n}: the orbit "
                                                        "repeats from its release and is never captured")
                        return out
                    released_from.add(cur)
                tau, sdot, cur = st.tau, st.sdot, st.wall
        except cert.CertificationError as e:
            done(list(pending), "failed", f"{e} (impact {n + 1} undecided)")
            return out


# ---------------------------------------------------------------------------------------------
# the schedule of precisions


@dataclass
class ReleaseDuration:
    """The certified post-release duration of one wall's canonical release orbit.

    ``value``: ``T_post`` (``None`` unless ``status == "captured"``); ``status``: the certified
    outcome (``captured``, ``periodic``, ``stuck_forever``, ``no_capture`` within ``max_impacts``) or
    ``undecided`` (no precision decided it; ``lower_bound`` still holds); ``precision``: the first
    precision (bits) that decided it; ``confirmed``: the next precision gave the same outcome;
    ``lower_bound``: certified ``T_post > lower_bound`` (impacts certified not captured);
    ``attempts``: every run; ``seconds``: total wall time.
    """

    params: dict
    rounding: str
    wall: int
    delta: float
    max_impacts: int
    target: dict
    release_phase: str
    status: str
    value: int | None
    precision: int | None
    confirmed: bool
    lower_bound: int
    attempts: list
    seconds: float

    def to_dict(self) -> dict:
        d = asdict(self)
        d["attempts"] = [asdict(a) for a in self.attempts]
        return d

    def summary(self) -> str:
        what = {"captured": f"T_post = {self.value}", "periodic": "never captured (periodic)",
                "stuck_forever": "stuck forever", "no_capture": f"T_post > {self.max_impacts}",
                "undecided": f"undecided (T_post > {self.lower_bound} certified)"}[self.status]
        conf = "confirmed" if self.confirmed else "NOT confirmed"
        at = f" at {self.precision} bits, {conf} at the next precision" if self.precision else ""
        kind = "exact decimal" if self.rounding == "decimal" else "float64-rounded"
        return (f"wall {self.wall}, {kind} parameters "
                f"(alpha={self.params['alpha']}, beta={self.params['beta']}, gamma={self.params['gamma']}, "
                f"r={self.params['r']}): {what}{at} ({self.seconds:.1f} s)")


def model_params(params_decimal: dict, rounding: str):
    """The parameters for :class:`certify.Model`: the decimal strings themselves (``"decimal"``) or
    the float64 numbers they round to (``"float64"``, exact binary values)."""
    if rounding not in ROUNDINGS:
        raise ValueError(f"rounding={rounding!r} is out of range: allowed one of {', '.join(ROUNDINGS)}")
    missing = [k for k in cert.PARAM_NAMES if k not in params_decimal]
    if missing or len(params_decimal) != len(cert.PARAM_NAMES):
        raise ValueError(f"params_decimal={params_decimal!r}: allowed exactly the keys {', '.join(cert.PARAM_NAMES)}")
    from ...mapimpl.params import check_value

    text = {k: str(params_decimal[k]).strip() for k in cert.PARAM_NAMES}
    floats = Params(**{k: check_value(k, v) for k, v in text.items()})  # ValueError names the parameter
    return dict(text) if rounding == "decimal" else floats


def certified_release_duration(params_decimal: dict = PAPER_DECIMAL, wall: int = 0, delta: float = DELTA, *,
                               rounding: str = "decimal", max_impacts: int = MAX_IMPACTS,
                               precisions=PRECISIONS, confirm: bool = True, target: Target | None = None,
                               stick_time: float = STICK_TIME, radius_limit: float = RADIUS_LIMIT,
                               time_budget_s: float | None = None, progress=None) -> ReleaseDuration:
    """``T_post`` of ``wall``'s canonical release orbit for one capture distance ``delta``, certified
    (see module docstring): :func:`certified_release_durations` for ``(delta,)``."""
    if not (isinstance(delta, numbers.Real) and math.isfinite(delta) and delta > 0):
        raise ValueError(f"delta={delta!r} is out of range: allowed finite delta > 0")
    return certified_release_durations(params_decimal, wall, (delta,), rounding=rounding, max_impacts=max_impacts,
                                       precisions=precisions, confirm=confirm, target=target, stick_time=stick_time,
                                       radius_limit=radius_limit, time_budget_s=time_budget_s,
                                       progress=progress)[float(delta)]


def certified_release_durations(params_decimal: dict = PAPER_DECIMAL, wall: int = 0, deltas=(DELTA,), *,
                                rounding: str = "decimal", max_impacts: int = MAX_IMPACTS,
                                precisions=PRECISIONS, confirm: bool = True, target: Target | None = None,
                                stick_time: float = STICK_TIME, radius_limit: float = RADIUS_LIMIT,
                                time_budget_s: float | None = None, progress=None) -> dict[float, ReleaseDuration]:
    """``T_post`` of ``wall``'s canonical release orbit for every capture distance of ``deltas``,
    certified (see module docstring): ``{delta: ReleaseDuration}``.

    Runs the orbit at each precision of ``precisions`` (increasing), every run deciding all the
    distances still open (:func:`certify_post_release_deltas`: one orbit serves them all); a distance
    is decided by the first precision that decides every step up to its outcome, and with ``confirm``
    the next precision of the list (or twice the last one) must give it the same outcome, else
    :class:`certify.CertificationError` (a bug).  Each distance gets exactly the attempts, value,
    precision and confirmation that a schedule for it alone would give; their runs are shared
    (``seconds``: the whole schedule).  ``params_decimal``: decimal strings ``{"alpha": "1.245", ...}``;
    ``rounding``: ``"decimal"`` (exact decimals, balls) or ``"float64"`` (their float64 roundings, exact).
    ``target``: the capture target (default: :func:`float64_target` of the float64 parameters).
    ``time_budget_s``: wall-time budget of the whole schedule (an attempt past it fails, later ones are
    skipped).  ``progress(prec, n, radius)``: see :func:`certify_post_release`.
    """
    pm = model_params(params_decimal, rounding)
    p64 = model_params(params_decimal, "float64")
    ds = _check_deltas(deltas)
    precs = [int(p) for p in precisions]
    if not precs or any(b <= a for a, b in zip(precs, precs[1:])):
        raise ValueError(f"precisions={precisions!r} is out of range: allowed a non-empty increasing list of bits")
    for p in precs:
        if not 64 <= p <= cert.MAX_PREC:
            raise ValueError(f"precisions: {p} is out of range: allowed 64 <= prec <= {cert.MAX_PREC}")
    if time_budget_s is not None and not time_budget_s > 0:
        raise ValueError(f"time_budget_s={time_budget_s!r} is out of range: allowed > 0")
    if target is None:
        target = float64_target(p64)
    t0 = time.monotonic()
    deadline = None if time_budget_s is None else t0 + float(time_budget_s)
    with cert.precision(128):
        ph = cert.release_phase(cert.Model(pm), wall)
    phase_text = "never" if ph is None else ph.str(30, radius=False)
    attempts: dict[float, list[Attempt]] = {d: [] for d in ds}
    decided: dict[float, Attempt | None] = {d: None for d in ds}
    confirmed = {d: False for d in ds}

    def confirm_with(d, b):
        a = decided[d]
        if b.definite:
            if (b.status, b.impacts) != (a.status, a.impacts):
                raise cert.CertificationError(
                    f"precisions {a.prec} and {b.prec} certify different outcomes at delta={d:g}: "
                    f"{a.status} at {a.impacts} vs {b.status} at {b.impacts} (a bug)")
            confirmed[d] = True

    to_confirm: list[float] = []  # decided by the last run: confirmed (or not) by the next one
    for i, prec in enumerate(precs):
        open_ = [d for d in ds if decided[d] is None]
        if not (open_ or to_confirm) or (deadline is not None and time.monotonic() > deadline):
            break
        run = certify_post_release_deltas(pm, wall, prec=prec, target=target, deltas=open_ + to_confirm,
                                          max_impacts=max_impacts, stick_time=stick_time,
                                          radius_limit=radius_limit, deadline=deadline, progress=progress)
        for d in to_confirm:
            attempts[d].append(run[d])
            confirm_with(d, run[d])
        to_confirm = []
        for d in open_:
            attempts[d].append(run[d])
            if run[d].definite:
                decided[d] = run[d]
                if confirm:
                    to_confirm.append(d)
    # decided at the last precision of the list: confirmed at twice it
    nxt = min(2 * precs[-1], cert.MAX_PREC)
    if to_confirm and nxt > precs[-1] and (deadline is None or time.monotonic() <= deadline):
        run = certify_post_release_deltas(pm, wall, prec=nxt, target=target, deltas=to_confirm,
                                          max_impacts=max_impacts, stick_time=stick_time,
                                          radius_limit=radius_limit, deadline=deadline, progress=progress)
        for d in to_confirm:
            attempts[d].append(run[d])
            confirm_with(d, run[d])
    seconds = time.monotonic() - t0
    out = {}
    for d in ds:
        a = decided[d]
        lower = max([b.impacts - (1 if b.status == "captured" else 0) for b in attempts[d]] or [0])
        status = a.status if a is not None else "undecided"
        out[d] = ReleaseDuration(
            params={k: str(params_decimal[k]).strip() for k in cert.PARAM_NAMES}, rounding=rounding, wall=wall,
            delta=d, max_impacts=int(max_impacts), target=target.as_dict(), release_phase=phase_text,
            status=status, value=a.impacts if status == "captured" else None,
            precision=a.prec if a is not None else None, confirmed=confirmed[d], lower_bound=lower,
            attempts=attempts[d], seconds=seconds)
    return out


# ---------------------------------------------------------------------------------------------
# float64 counterparts


def stick_at_once_state(params: Params, wall: int = 0, tau0: float | None = None) -> tuple[float, float]:
    """A pre-impact state that sticks at once to ``wall`` (rule): at phase ``tau0`` (default: where
    the contact force presses hardest, ``phi -+ pi/2``) with speed half the largest one that sticks
    at once, ``|sdot0| = STICK_TIME (1 - r) f_in / (4 r)``, rounded to 3 significant digits."""
    if wall not in (0, -1):
        raise ValueError(f"wall={wall!r} is out of range: allowed 0 or -1")
    d = 1.0 if wall == 0 else -1.0
    if tau0 is None:
        tau0 = math.atan(params.beta) - d * math.pi / 2
        tau0 = tau0 % (2 * math.pi)
    f = -params.alpha * math.sin(tau0) + params.alpha * params.beta * math.cos(tau0) + params.gamma
    f_in = d * f
    if not (f_in > 0 and params.r < 1.0):
        raise ValueError(f"tau0={tau0!r}: the contact force does not press into wall {wall} there "
                         "(or r = 1): no state sticks at once")
    speed = float(f"{STICK_TIME * (1 - params.r) * f_in / (4 * params.r):.3g}")
    return float(tau0), d * speed


def float64_release_duration(params: Params, wall: int = 0, delta: float = DELTA, cap: int = 200_000) -> dict:
    """The float64 engine's own ``T_post`` (:func:`mapimpl.engine.transients.transient_times`) from a
    state that sticks at once (:func:`stick_at_once_state`; iteration 0 sticks, so the capture
    iteration is ``T_post``).  Returns ``{"value", "status", "tau0", "sdot0", "nstick"}`` (``value``
    None when the orbit is not captured within ``cap``)."""
    from ...mapimpl.engine.transients import transient_times
    from ...mapimpl.status import ORBIT_NAMES

    tau0, sdot0 = stick_at_once_state(params, wall)
    res = transient_times([tau0], [sdot0], params, delta=delta, cap=cap, lanes=1, devices=1, progress=False)
    hit = int(res.hit[0, res.column(delta)])
    return {"value": hit if hit >= 0 else None, "status": ORBIT_NAMES[int(res.status[0])],
            "tau0": tau0, "sdot0": sdot0, "nstick": int(res.nstick[0]), "cap": int(cap)}


def float64_horizon(lam: float, distance: float = 1.0) -> float:
    """Impacts after which a float64 orbit's rounding error (unit roundoff ``u = 2^-53``) has grown
    to ``distance`` at the Lyapunov rate ``lam`` (per impact): ``ln(distance / u) / lam``.  With
    ``distance = 1`` the float64 orbit has no digit left in common with the true one."""
    if not lam > 0:
        raise ValueError(f"lam={lam!r} is out of range: allowed lam > 0 (a chaotic orbit)")
    return math.log(distance / 2.0 ** -53) / lam


def float64_departure(params: Params, wall: int = 0, n: int = 300, prec: int = 1024,
                      thresholds=(1e-12, 1e-8, 1e-3, 1e-1), target: Target | None = None) -> dict:
    """Where the float64 map's post-release orbit leaves the true one: the map track
    (:func:`mapimpl.orbit.map_orbit`) from a state that sticks at once to ``wall``, compared with the
    certified orbit (``prec`` bits, midpoints) impact by impact; for each threshold, the first
    post-release impact whose error (sup of the wrapped phase error and the sdot error, or a different
    wall) exceeds it.  ``params``: float64 (the map's own numbers, exact in the certification)."""
    from ...mapimpl.orbit import map_orbit

    if target is None:
        target = Target((), (), ())
    a = certify_post_release(params, wall, prec=prec, target=target, max_impacts=n, record=True)
    tau0, sdot0 = stick_at_once_state(params, wall)
    seq = map_orbit(params, tau0, sdot0, len(a.orbit))
    _, th, sd, wl = seq.impact_arrays()
    err = []
    for k, (th_c, sd_c, w_c) in enumerate(a.orbit, start=1):
        if k >= len(th) or wl[k] != w_c:
            err.append(math.inf)
            continue
        dth = abs(th[k] - th_c) % (2 * math.pi)
        err.append(max(min(dth, 2 * math.pi - dth), abs(sd[k] - sd_c)))
    first = {f"{t:g}": next((k for k, e in enumerate(err, start=1) if e > t), None) for t in thresholds}
    return {"first_impact_above": first, "certified_impacts": len(a.orbit), "certified_status": a.status,
            "errors": err}


def transient_lyapunov(params: Params, n_side: int = 16, impacts: int = 3000, delta_far: float = 1e-2,
                       box=None) -> dict:
    """Largest Lyapunov exponent of the *transient* (the chaotic saddle), per impact: QR method
    (:mod:`validation.dynamics.lyapunov`) along the orbits of an ``n_side`` x ``n_side`` cell-centred
    grid of the Fig. 11 box, counting only the impacts before the orbit first comes within
    ``delta_far`` of the 4-impact target and no sticking step (Q restarts there).

    Returns ``{"lambda1", "impacts_used", "orbits", "orbits_reaching_target"}``."""
    import numpy as np

    from ...mapimpl import _jax  # noqa: F401
    import jax
    import jax.numpy as jnp

    from ...mapimpl.engine.observers import orbit_distance
    from ...mapimpl.engine.transients import PAPER_BOX, grid, periodic_target
    from ...mapimpl.impact_map import ACTIVE, make_state, step

    tg = periodic_target(params)
    po_th, po_v, po_w = jnp.asarray(tg.theta), jnp.asarray(tg.sdot), jnp.asarray(tg.wall)
    TAU, SD = grid(PAPER_BOX if box is None else box, n_side, n_side)
    st = make_state(jnp.asarray(TAU.ravel()), jnp.asarray(SD.ravel()))
    p = params.arrays()

    def one(s):
        def body(c, _):
            s, Q, acc, cnt, live = c
            s1, info = step(s, p)
            J = jnp.where(info.stuck, jnp.eye(2), info.jac)
            Qn, R = jnp.linalg.qr(J @ Q)
            dg = jnp.diagonal(R)
            far = orbit_distance(s1.theta, s1.sdot, s1.wall, po_th, po_v, po_w) >= delta_far
            live1 = live & (s1.status == ACTIVE) & far
            use = live1 & ~info.stuck
            acc = acc + jnp.where(use, jnp.log(jnp.abs(dg[0])), 0.0)
            Qn = jnp.where(use, Qn * jnp.sign(dg)[None, :], jnp.eye(2))
            return (s1, Qn, acc, cnt + use, live1), None

        c0 = (s, jnp.eye(2), jnp.asarray(0.0), jnp.asarray(0), jnp.asarray(True))
        (_, _, acc, cnt, live), _ = jax.lax.scan(body, c0, None, length=impacts)
        return acc, cnt, live

    acc, cnt, live = jax.jit(jax.vmap(one))(st)
    acc, cnt, live = np.asarray(acc), np.asarray(cnt), np.asarray(live)
    used = int(cnt.sum())
    if used == 0:
        raise RuntimeError("no transient impacts to measure")
    return {"lambda1": float(acc.sum() / used), "impacts_used": used, "orbits": int(acc.size),
            "orbits_reaching_target": int((~live).sum())}


def sticking_walls(tau0, sdot0, params: Params, *, cap: int = 200_000, lanes: int | None = None,
                   delta: float = DELTA, progress=None) -> dict:
    """Which wall every pre-impact initial condition first sticks to within ``cap`` iterations (before a
    capture within ``delta``): the transient engine itself (``release="compose"``, which stops each orbit
    at its first sticking).

    Returns numpy arrays ``{"first_wall" (0, -1, or 1 = never stuck), "first_stick" (impact index,
    -1: never), "status", "n"}``.
    """
    import numpy as np

    from ...mapimpl.engine.transients import transient_times

    res = transient_times(np.atleast_1d(np.asarray(tau0, float)), np.atleast_1d(np.asarray(sdot0, float)), params,
                          delta=delta, deltas=(delta,), cap=int(cap), release="compose", lanes=lanes,
                          progress=progress, label="sticking walls")
    stuck = res.first_stick >= 0
    return {"first_wall": np.where(stuck, res.stick_wall, 1), "first_stick": np.asarray(res.first_stick),
            "status": np.asarray(res.status), "n": np.asarray(res.n)}


# ---------------------------------------------------------------------------------------------
# command line


def _precisions(text: str) -> tuple:
    try:
        vals = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"--precisions={text!r}: allowed a comma-separated list of integers") from None
    if not vals or any(not 64 <= v <= cert.MAX_PREC for v in vals) or any(b <= a for a, b in zip(vals, vals[1:])):
        raise argparse.ArgumentTypeError(f"--precisions={text!r} is out of range: allowed increasing integers "
                                         f"in [64, {cert.MAX_PREC}]")
    return vals


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"{v} is out of range: allowed >= 1")
    return v


def _positive_float(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"{v} is out of range: allowed finite > 0")
    return v


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit status 2
        self.exit(2, f"{self.prog}: error: {message}\n")


def main(argv: list[str] | None = None) -> int:
    ap = _Parser(prog="python -m gear_rattle.validation.golden.release",
                 description="Certified post-release duration T_post of the canonical release orbit "
                             "(ball arithmetic at increasing precision; docs/release.md).")
    g = ap.add_argument_group("parameters (exact decimals as printed; default: the paper's Figs. 9-11)")
    for k in cert.PARAM_NAMES:
        g.add_argument(f"--{k}", default=PAPER_DECIMAL[k], help=f"decimal (default {PAPER_DECIMAL[k]})")
    ap.add_argument("--wall", choices=("0", "-1", "both"), default="0", help="wall released from (default 0: s = 0)")
    ap.add_argument("--rounding", choices=ROUNDINGS + ("both",), default="both",
                    help="exact decimal parameters, their float64 roundings, or both (default)")
    ap.add_argument("--delta", type=_positive_float, default=DELTA, help=f"capture distance (default {DELTA:g})")
    ap.add_argument("--max-impacts", type=_positive_int, default=MAX_IMPACTS,
                    help=f"most post-release impacts certified (default {MAX_IMPACTS})")
    ap.add_argument("--precisions", type=_precisions, default=PRECISIONS,
                    help="increasing precisions in bits (default " + ",".join(map(str, PRECISIONS)) + ")")
    ap.add_argument("--no-confirm", action="store_true", help="skip the confirmation at the next precision")
    ap.add_argument("--time-budget", type=_positive_float, default=None, help="seconds for each schedule")
    ap.add_argument("--float64", action="store_true", help="also run the float64 engine's own T_post")
    ap.add_argument("--json", default=None, help="write the results as JSON to this file")
    ap.add_argument("--quiet", action="store_true", help="no progress on stderr")
    args = ap.parse_args(argv)
    params = {k: getattr(args, k) for k in cert.PARAM_NAMES}
    try:
        model_params(params, "float64")
        for k in cert.PARAM_NAMES:
            with cert.precision(64):
                cert.parameter_ball(k, params[k])
    except ValueError as e:
        ap.error(str(e))
    walls = (0, -1) if args.wall == "both" else (int(args.wall),)
    roundings = ROUNDINGS if args.rounding == "both" else (args.rounding,)

    def prog(prec, n, rad):
        if not args.quiet:
            sys.stderr.write(f"\r  {prec} bits: impact {n}, radius {rad}   ")
            sys.stderr.flush()

    out = {"command": "python -m gear_rattle.validation.golden.release " + " ".join(argv or sys.argv[1:]),
           "results": [], "float64_engine": []}
    try:
        for wall in walls:
            for rounding in roundings:
                d = certified_release_duration(params, wall, args.delta, rounding=rounding,
                                               max_impacts=args.max_impacts, precisions=args.precisions,
                                               confirm=not args.no_confirm, time_budget_s=args.time_budget,
                                               progress=prog)
                if not args.quiet:
                    sys.stderr.write("\r" + " " * 60 + "\r")
                print(d.summary())
                for a in d.attempts:
                    print(f"    {a.prec:5d} bits: {a.status:13s} impacts {a.impacts:6d}  radius {a.radius:>9s}  "
                          f"growth {a.growth:.3f} bits/impact  {a.seconds:7.1f} s  {a.reason}")
                out["results"].append(d.to_dict())
            if args.float64:
                f = float64_release_duration(model_params(params, "float64"), wall, args.delta)
                print(f"wall {wall}, float64 engine (a sample, not a value): T_post = {f['value']} ({f['status']})")
                out["float64_engine"].append(dict(f, wall=wall))
    except ValueError as e:
        ap.error(str(e))
    except cert.CertificationError as e:  # pragma: no cover - two precisions disagree: a bug
        print(f"error: {e}", file=sys.stderr)
        return 1
    if args.json:
        from pathlib import Path

        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(out, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
