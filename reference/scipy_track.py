"""Reference track 1: Eq. (3) integrated with :func:`scipy.integrate.solve_ivp` (DOP853) as a hybrid ODE.

Only the right-hand side of Eq. (3) is used (see :mod:`reference.common`); the impacts are the
events ``s = 0`` (reached upward) and ``s = -1`` (reached downward) with the reset of Eqs. (9)-(11),
``sdot -> -r sdot``, followed by a restart.  The events are those of :mod:`reference.events`, the
specification shared with the diffrax track.  After every impact the shared chatter/sticking policy
(:func:`mapimpl.sticking.decide_stick`) is applied exactly as the map does: when it says *stick*,
the orbit jumps to the release time and leaves the wall with ``sdot = 0``.

**Monotone segments (the event traps, :mod:`reference.events`).**  Every flight is integrated as a
chain of *monotone segments*: each segment has a direction ``sigma = +-1`` (the sign of ``sdot``) and
two terminal, direction-filtered events, both upcrossings of a function that is ``<= 0`` at the
segment start:

* the wall ahead: ``s`` (upper wall, ``sigma = +1``) or ``-1 - s`` (lower wall, ``sigma = -1``);
* the velocity reversal ``-sigma sdot`` (a local extremum of ``s``): the segment ends there and the
  next one starts with ``-sigma``.

Consequences:

1. *Restart on a wall never re-fires*: after an impact (or a release) the segment moves away from
   the wall it starts on and only watches the wall ahead, which is a full gap away.  The start wall
   is watched again only after a velocity reversal, i.e. after the flight has genuinely turned back.
2. *Two crossings inside one step* (scipy issue 9228: a step that starts and ends inside the gap
   while ``s`` pokes beyond a wall in between) cannot hide a crossing: ``s`` is monotone inside a
   segment, so beyond-and-back requires a velocity reversal, and the reversal event (a sign change of
   ``sdot`` at step ends) stops the segment first.  If both events fire in one step, scipy keeps the
   earlier root, which is the wall.  If only the reversal fires and the extremum lies *beyond* the
   wall, the crossing happened inside that step: ``s`` is monotone between the segment start and the
   extremum, so a second solve on exactly that interval sees the sign change and locates it
   (:data:`reference.events.MISSED_CROSSING`).  *Two* velocity reversals inside one step (``sdot``
   dips through zero and back between two step ends; 1 in ~1000 slow departures from a wall) are
   caught by a third, non-terminal event at every speed minimum (:func:`reference.events.dip_condition`):
   if ``sdot`` points backwards there, the segment is solved again up to that minimum, where the
   reversal is a sign change.
3. *A flight that returns to the wall it left* is an ordinary reversal followed by a segment that
   watches the start wall.
4. *Grazing*: an excursion beyond a wall, however shallow, is caught (item 2); a tangency that stays
   inside is a reversal.  Near grazing the impact time is ill-conditioned (``dtau ~ ds / |sdot|``),
   for every track.
5. *A segment that starts at rest* (after a release, or at a reversal) is solved from the velocity
   ``sigma * START_SPEED`` (1e-300, :func:`reference.events.start_velocity`), so its reversal condition
   starts strictly negative: started at zero, scipy located any upcrossing inside the first step at the
   start itself, and zero-length segments followed one another up to ``MAX_SEGMENTS``.  A speed minimum whose
   backward velocity is below ``atol`` is no hidden reversal (:func:`reference.events.hidden_reversal`).

**Jacobian (second route).**  :func:`step_jacobian` integrates the variational equations
``Phi' = [[0, 1], [0, -beta]] Phi`` along the flight and composes

    J = P_{n+1} . Phi . S_n . E_n,

``E_n``: perturbation of the pre-impact state (tau_n, sdot_n) as a state perturbation at fixed time,
``S_n = R + (F+ - R F-) h_x / (h_x F-)``: saltation matrix of the impact (``R = diag(1, -r)``, Eq. 11),
``P_{n+1}``: projection onto the next impact surface (hitting-time correction).  This is an
independent route to the analytic Jacobian of Eqs. (12)-(13) (:class:`mapimpl.impact_map.StepInfo`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
from scipy.integrate import solve_ivp

from ..core.checks import start_wall
from ..core.params import Params
from ..core.progress import Bar, wanted
from ..core.results import ImpactSequence, StepJacobian, TrackFunctions
from ..core.status import FlightOutcome, Status
from . import events as ev
from .common import (
    TWO_PI,
    TrajectoryRecorder,
    check_option,
    forcing_rhs,
    reduce_phase,
    release_start,
    stick_decision,
    validate_start,
)
from .events import MAX_SEGMENTS, T_MAX
from ..mapimpl.sticking import STICK_TIME, check_stick_time, stick_time_meta

# flight outcomes by label (``Flight.status``) and the orbit status code after a miss
_HIT, _NO_IMPACT, _STEP_CAP = (f.label for f in (FlightOutcome.HIT, FlightOutcome.NO_IMPACT, FlightOutcome.STEP_CAP))
_FLIGHT_FAILURE = {_NO_IMPACT: int(Status.NO_IMPACT), _STEP_CAP: int(Status.STEP_CAP)}

#: Default integrator tolerances and step bound of this track.
RTOL, ATOL, MAX_STEP = 3e-14, 1e-16, 0.1


@dataclass(frozen=True)
class Options:
    """Integrator options (validated): ``rtol``, ``atol``, ``max_step`` and the longest flight ``t_max``."""

    rtol: float = RTOL
    atol: float = ATOL
    max_step: float = MAX_STEP
    t_max: float = T_MAX

    def __post_init__(self) -> None:
        object.__setattr__(self, "rtol", check_option("rtol", self.rtol, 2.3e-14, 1e-3))
        object.__setattr__(self, "atol", check_option("atol", self.atol, 0.0, 1e-3))
        object.__setattr__(self, "max_step", check_option("max_step", self.max_step, 0.0, 10.0))
        object.__setattr__(self, "t_max", check_option("t_max", self.t_max, 0.0, 1e6))


class Flight(NamedTuple):
    """One flight from a post-impact (or release, or free) state to the next wall contact.

    ``status``: ``"hit"``, ``"no_impact"`` (no wall within ``t_max``) or ``"step_cap"``;
    ``t``: flight time; ``wall``: 0 or -1; ``v``: velocity just before the impact;
    ``phi``: 2x2 flow Jacobian ``d(s, sdot)(t) / d(s, sdot)(0)`` (variational equations) or None;
    ``segments``: monotone segments integrated; ``samples``: list of ``(t_local, s, sdot)`` arrays
    when dense sampling was requested.
    """

    status: str
    t: float
    wall: int
    v: float
    phi: np.ndarray | None
    segments: int
    samples: list | None


def _make_rhs(theta0: float, p: Params, variational: bool) -> Callable:
    a, b, g = p.alpha, p.beta, p.gamma

    if not variational:

        def rhs(t, y):
            tau = theta0 + t
            return np.array([y[1], -a * math.sin(tau) + a * b * math.cos(tau) + g - b * y[1]])

        return rhs

    def rhs_var(t, y):
        tau = theta0 + t
        # y = [s, v, Phi00, Phi01, Phi10, Phi11];  Phi' = [[0, 1], [0, -beta]] Phi
        return np.array(
            [y[1], -a * math.sin(tau) + a * b * math.cos(tau) + g - b * y[1], y[4], y[5], -b * y[4], -b * y[5]]
        )

    return rhs_var


def segment_events(sigma: float, rhs: Callable | None = None, offset: float = 0.0):
    """The event functions of a segment of direction ``sigma`` (:mod:`reference.events`) as scipy
    events: the wall ahead first, then the velocity reversal (both terminal), and, given the vector
    field ``rhs``, the speed minimum (not terminal: :func:`reference.events.dip_condition`).  The state's
    first component is the displacement ``s - offset`` (:func:`flight`)."""

    def wall_ev(t, y):
        return ev.wall_condition(y[0] + offset, sigma)

    def rev_ev(t, y):
        return ev.reversal_condition(y[1], sigma)

    if rhs is None:
        return [_event(wall_ev, ev.TERMINAL), _event(rev_ev, ev.TERMINAL)]

    def dip_ev(t, y):
        return ev.dip_condition(rhs(t, y)[1], sigma)

    return [_event(wall_ev, ev.TERMINAL), _event(rev_ev, ev.TERMINAL), _event(dip_ev, False)]


def _event(f, terminal: bool):
    """``f`` as an event of ``solve_ivp``: its ``terminal`` flag and the crossing direction set as attributes."""
    f.terminal = terminal
    f.direction = float(ev.DIRECTION)
    return f


def _hidden_dip(sol, sigma: int, atol: float) -> float | None:
    """The first speed minimum of a solve at which the velocity points against ``sigma`` by more than
    the absolute tolerance ``atol`` (two reversals inside one step, unseen by the reversal event), or
    None.  A dip below ``atol`` has no resolvable sign (:func:`reference.events.hidden_reversal`: the
    rounding-level dip just after a release from sticking)."""
    for t_d, y_d in zip(sol.t_events[2], sol.y_events[2]):
        if ev.hidden_reversal(float(y_d[1]), sigma, atol):
            return float(t_d)
    return None


def flight(
    theta0: float,
    s0: float,
    v0: float,
    p: Params,
    opts: Options = Options(),
    sigma: int | None = None,
    variational: bool = False,
    points_per_unit: float | None = None,
) -> Flight:
    """Integrate Eq. (3) from ``(theta0, s0, v0)`` (local time 0) to the first wall contact.

    ``sigma`` is the direction of the first monotone segment (default: the sign of ``v0``; for
    ``v0 = 0`` away from the wall the flight starts on, or the sign of the acceleration in the
    interior).  ``variational=True`` also integrates the flow Jacobian; ``points_per_unit`` asks for
    dense samples of ``s`` and ``sdot`` (DOP853's 7th-order interpolant).
    """
    if sigma is None:
        sigma = ev.initial_direction(s0, v0, forcing_rhs(theta0, p.alpha, p.beta, p.gamma))
    rhs = _make_rhs(theta0, p, variational)
    # the state is the displacement s - s0 (and sdot): the solver's error control is then relative to
    # the flight's own motion, not to the wall's coordinate (|s| ~ 1 at s = -1)
    offset = float(s0)
    y = np.array([0.0, v0, 1.0, 0.0, 0.0, 1.0]) if variational else np.array([0.0, v0])
    t = 0.0
    ppu = points_per_unit or 0.0
    samples: list | None = [] if ppu else None
    for seg in range(1, MAX_SEGMENTS + 1):
        # solved from a velocity along sigma (0 after a release, ~0 after a reversal: the reversal
        # condition then starts strictly negative, reference.events.start_velocity)
        y_s = y.copy()
        y_s[1] = ev.start_velocity(float(y[1]), sigma)
        sol = solve_ivp(
            rhs,
            (t, opts.t_max),
            y_s,
            method="DOP853",
            rtol=opts.rtol,
            atol=opts.atol,
            max_step=opts.max_step,
            events=segment_events(sigma, rhs, offset),
            dense_output=samples is not None,
        )
        t_dip = _hidden_dip(sol, sigma, opts.atol) if sol.status >= 0 else None
        if t_dip is not None:
            # sdot reversed and reversed back inside one step before t_dip: solve again up to the speed
            # minimum, where sdot has the opposite sign, so the reversal (or a wall before it) is found
            redo = solve_ivp(
                rhs,
                (t, t_dip),
                y_s,
                method="DOP853",
                rtol=opts.rtol,
                atol=opts.atol,
                max_step=opts.max_step,
                events=segment_events(sigma, offset=offset),
                dense_output=samples is not None,
            )
            if redo.status == 1:  # else the dip was a rounding-level tangency: keep the first solve
                sol = redo
        if sol.status < 0:
            return Flight(_STEP_CAP, math.inf, 0, math.nan, None, seg, samples)
        if sol.status == 0:  # reached t_max without an event (OPEN_END)
            if samples is not None:
                _sample(sol, t, opts.t_max, ppu, samples, offset, y)
            return Flight(_NO_IMPACT, math.inf, 0, math.nan, None, seg, samples)
        hit = len(sol.t_events[0]) > 0
        k = 0 if hit else 1
        t_e = float(sol.t_events[k][-1])
        y_e = np.array(sol.y_events[k][-1], dtype=np.float64)
        t_e, y_e = _land(rhs, sol, t_e, y_e, sigma, hit, opts, offset)
        if ev.segment_end(hit, not hit, y_e[0] + offset, sigma) == ev.MISSED_CROSSING:
            # the extremum lies beyond the wall ahead: s crossed it and came back inside one step
            # (scipy issue 9228).  s is monotone on [t, t_e], so a solve that ends at t_e sees the
            # crossing as a sign change and locates it; without one, the extremum is a reversal.
            sol2 = solve_ivp(
                rhs,
                (t, t_e),
                y_s,
                method="DOP853",
                rtol=opts.rtol,
                atol=opts.atol,
                max_step=opts.max_step,
                events=segment_events(sigma, offset=offset)[:1],
            )
            if sol2.status == 1 and len(sol2.t_events[0]):
                hit = True
                t_e, y_e = _land(
                    rhs,
                    sol2,
                    float(sol2.t_events[0][-1]),
                    np.array(sol2.y_events[0][-1], dtype=np.float64),
                    sigma,
                    True,
                    opts,
                    offset,
                )
        if samples is not None:
            _sample(sol, t, t_e, ppu, samples, offset, y, y_e)
        if hit:
            phi = y_e[2:].reshape(2, 2) if variational else None
            return Flight(_HIT, t_e, ev.wall_ahead(sigma), float(y_e[1]), phi, seg, samples)
        # velocity reversal: continue in the other direction from the extremum
        t, y, sigma = t_e, y_e, -sigma
    return Flight(_STEP_CAP, math.inf, 0, math.nan, None, MAX_SEGMENTS, samples)


def _land(rhs, sol, t_e: float, y_e: np.ndarray, sigma: int, wall: bool, opts: Options, offset: float = 0.0):
    """Refine an event located on the dense interpolant: integrate from the last node exactly to
    ``t_e`` (a node value, no interpolation error) and take one Newton step on the event condition
    (``dt = -g / g'``, with ``g'`` from the vector field; ``s = y[0] + offset``).  Returns the refined
    ``(t_e, y_e)``."""
    t_prev, y_prev = float(sol.t[-2]), sol.y[:, -2]
    if not t_e > t_prev:
        return t_e, y_e
    land = solve_ivp(
        rhs, (t_prev, t_e), y_prev, method="DOP853", rtol=opts.rtol, atol=opts.atol, max_step=opts.max_step
    )
    if land.status != 0:
        return t_e, y_e
    y_n = land.y[:, -1]
    f = rhs(t_e, y_n)
    g = ev.condition(np.array([y_n[0] + offset, y_n[1]]), sigma, wall)
    dt = ev.newton_step(g, ev.condition_rate(f, sigma, wall))
    return t_e + dt, y_n + f * dt


def _sample(
    sol, t0: float, t1: float, ppu: float, out: list, offset: float, y0: np.ndarray, y1: np.ndarray | None = None
) -> None:
    """Dense samples of one segment on ``[t0, t1]``: the first is the segment's start state ``y0`` (not
    the solver's start, whose velocity may be :func:`reference.events.start_velocity`), the last the
    refined event state ``y1`` when given; ``s`` is the displacement ``y[0]`` plus ``offset``."""
    m = max(2, int(math.ceil((t1 - t0) * ppu)) + 1)
    ts = np.linspace(t0, t1, m)
    ys = sol.sol(ts)
    ys[:, 0] = y0[: ys.shape[0]]
    if y1 is not None:
        ys[:, -1] = y1[: ys.shape[0]]
    out.append((ts, ys[0] + offset, ys[1].copy()))


class DenseTrajectory(NamedTuple):
    """Samples of the numerically integrated trajectory: elapsed time, ``s`` and ``sdot``.

    Interior samples come from the integrator's dense output; stuck intervals are sampled at the
    wall with ``sdot = 0``.  ``segment`` numbers the flights (samples of one flight share it).
    """

    tau: np.ndarray
    s: np.ndarray
    sdot: np.ndarray
    segment: np.ndarray


def _run(
    params: Params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None,
    opts: Options,
    points_per_unit: float | None,
    progress=None,
    stick_time: float = STICK_TIME,
):
    n = validate_start(params, tau0, sdot0, n_impacts, s0)
    stick_time = check_stick_time(stick_time)
    p = params
    s0 = None if s0 is None else float(s0)
    meta = {**_meta(tau0, sdot0, s0, n, opts), **stick_time_meta(stick_time)}
    dense: list = []
    theta, cycles = reduce_phase(float(tau0), 0)
    flights = 0

    def record(fl: Flight, theta_start: float, cycles_start: int) -> None:
        if fl.samples is not None:
            base = cycles_start * TWO_PI + theta_start
            for ts, ss, vs in fl.samples:
                dense.append((base + ts, ss, vs, np.full(len(ts), flights)))
            if fl.status == _HIT:  # end exactly on the recorded impact time (same phase bookkeeping)
                th1, cyc1 = reduce_phase(theta_start + fl.t, cycles_start)
                dense[-1][0][-1] = cyc1 * TWO_PI + th1

    if s0 is None:
        sdot, wall = float(sdot0), (ev.UPPER_WALL if sdot0 > 0 else ev.LOWER_WALL)
    else:
        w0 = ev.pre_impact_wall(s0, sdot0, forcing_rhs(theta, p.alpha, p.beta, p.gamma))
        if w0 is not None:  # already a pre-impact state
            sdot, wall = float(sdot0), w0
        else:
            fl = flight(theta, s0, float(sdot0), p, opts, points_per_unit=points_per_unit)
            record(fl, theta, cycles)
            flights += 1
            if fl.status != _HIT:
                rec = TrajectoryRecorder(theta, cycles, float(sdot0), 0, _FLIGHT_FAILURE[fl.status])
                return rec.sequence(params, "scipy", meta), dense
            theta, cycles = reduce_phase(theta + fl.t, cycles)
            sdot, wall = fl.v, fl.wall
    rec = TrajectoryRecorder(theta, cycles, sdot, wall, Status.ACTIVE)
    bar = Bar("scipy orbit", total=n, enabled=wanted(progress), delay=1.0)
    for i in range(n):
        bar.update(i)
        tau_n = cycles * TWO_PI + theta
        stick, t_acc, delay, phase = stick_decision(theta, wall, sdot, p, stick_time)
        stick_tau = release_tau = math.nan
        if stick:
            stick_tau = tau_n + t_acc
            if not math.isfinite(delay):
                rec.step(theta, cycles, sdot, wall, Status.STUCK_FOREVER, True, stick_tau)
                if points_per_unit:
                    dense.append((np.array([stick_tau]), np.array([float(wall)]), np.zeros(1), np.full(1, flights)))
                break
            release_tau = tau_n + delay
            th0, cyc0 = release_start(theta, cycles, delay, phase)
            if points_per_unit:
                # the stuck interval ends where the dense flight after the release starts: at the canonical
                # release phase, cyc0 2 pi + th0, which equals release_tau only to rounding (ending at
                # release_tau put the first flight sample an ulp before the last stuck one)
                t_leave = max(stick_tau, cyc0 * TWO_PI + th0)
                ts = np.linspace(stick_tau, t_leave, max(2, int(delay * points_per_unit)))
                dense.append((ts, np.full(len(ts), float(wall)), np.zeros(len(ts)), np.full(len(ts), -1)))
            v0 = 0.0
        else:
            th0, cyc0 = theta, cycles
            v0 = -p.r * sdot
        fl = flight(
            th0, float(wall), v0, p, opts, sigma=ev.restart_direction(wall, v0), points_per_unit=points_per_unit
        )
        record(fl, th0, cyc0)
        flights += 1
        if fl.status != _HIT:
            rec.step(theta, cycles, sdot, wall, _FLIGHT_FAILURE[fl.status], stick, stick_tau, release_tau, fl.segments)
            break
        theta, cycles = reduce_phase(th0 + fl.t, cyc0)
        sdot, wall = fl.v, fl.wall
        rec.step(theta, cycles, sdot, wall, Status.ACTIVE, stick, stick_tau, release_tau, fl.segments)
    bar.close()
    return rec.sequence(params, "scipy", meta), dense


def _meta(tau0, sdot0, s0, n, opts: Options) -> dict:
    return {
        "tau0": tau0,
        "sdot0": sdot0,
        "s0": s0,
        "n_impacts": n,
        "method": "DOP853",
        "rtol": opts.rtol,
        "atol": opts.atol,
        "max_step": opts.max_step,
        "t_max": opts.t_max,
    }


def orbit(
    params: Params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None = None,
    *,
    rtol: float = RTOL,
    atol: float = ATOL,
    max_step: float = MAX_STEP,
    t_max: float = T_MAX,
    progress=None,
    stick_time: float = STICK_TIME,
) -> ImpactSequence:
    """Orbit of Eq. (3) integrated numerically: impact 0 plus ``n_impacts`` impacts (track ``"scipy"``).

    Same signature, conventions and result type as :func:`mapimpl.orbit.map_orbit`: with ``s0`` None,
    ``(tau0, sdot0)`` is the state just before impact 0 (``sdot0 > 0`` hits ``s = 0``); with
    ``-1 <= s0 <= 0`` it is a free-flight state; ``stick_time`` is the sticking policy's threshold
    (``0 <= stick_time <= 1e-2``).  Raises ``ValueError`` naming a bad argument.
    """
    opts = Options(rtol, atol, max_step, t_max)
    seq, _ = _run(params, tau0, sdot0, n_impacts, s0, opts, None, progress, stick_time)
    return seq


def dense_orbit(
    params: Params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None = None,
    *,
    points_per_unit: float = 40.0,
    rtol: float = RTOL,
    atol: float = ATOL,
    max_step: float = MAX_STEP,
    t_max: float = T_MAX,
    stick_time: float = STICK_TIME,
) -> tuple[ImpactSequence, DenseTrajectory]:
    """Like :func:`orbit`, plus the dense trajectory ``s(tau)`` between the impacts (for plots, invariants)."""
    ppu = check_option("points_per_unit", points_per_unit, 0.0, 1e6)
    seq, parts = _run(
        params, tau0, sdot0, n_impacts, s0, Options(rtol, atol, max_step, t_max), ppu, stick_time=stick_time
    )
    if not parts:
        e = np.empty(0)
        return seq, DenseTrajectory(e, e, e, np.empty(0, dtype=np.int64))
    tau, s, v, g = (np.concatenate(x) for x in zip(*parts))
    return seq, DenseTrajectory(tau, s, v, g.astype(np.int64))


def step_jacobian(
    params: Params,
    tau_n: float,
    sdot_n: float,
    wall: int | None = None,
    *,
    rtol: float = RTOL,
    atol: float = ATOL,
    max_step: float = MAX_STEP,
    t_max: float = T_MAX,
) -> StepJacobian:
    """One impact-to-impact step from the pre-impact state ``(tau_n, sdot_n)`` with its Jacobian.

    ``J = d(tau_{n+1}, sdot_{n+1}) / d(tau_n, sdot_n) = P_{n+1} Phi S_n E_n`` (module docstring):
    variational flow Jacobian ``Phi`` times the saltation matrix of impact n.  A step that sticks
    forgets its input (``J = 0``, as in the map).
    """
    opts = Options(rtol, atol, max_step, t_max)
    validate_start(params, tau_n, sdot_n, 1, None, ("tau_n", "sdot_n"))
    p = params
    wall = start_wall(wall, sdot_n)
    theta, cycles = reduce_phase(float(tau_n), 0)
    sdot_n = float(sdot_n)
    stick, _, delay, phase = stick_decision(theta, wall, sdot_n, p)
    if stick:
        if not math.isfinite(delay):
            return StepJacobian(math.nan, math.nan, wall, np.zeros((2, 2)), True, Status.STUCK_FOREVER.label)
        th0, cyc0 = release_start(theta, cycles, delay, phase)
        v0 = 0.0
    else:
        th0, cyc0, v0 = theta, cycles, -p.r * sdot_n
    fl = flight(th0, float(wall), v0, p, opts, sigma=ev.restart_direction(wall, v0), variational=True)
    if fl.status != _HIT:
        jac = np.zeros((2, 2)) if stick else np.full((2, 2), np.nan)
        return StepJacobian(math.nan, math.nan, wall, jac, stick, fl.status)
    th1, cyc1 = reduce_phase(th0 + fl.t, cyc0)
    tau1 = float(cyc1 * TWO_PI + th1)
    if stick:
        return StepJacobian(tau1, fl.v, fl.wall, np.zeros((2, 2)), True, Status.ACTIVE.label)
    f_n = forcing_rhs(theta, p.alpha, p.beta, p.gamma)
    a_pre = f_n - p.beta * sdot_n  # acceleration just before impact n
    a_post = f_n - p.beta * v0  # ... just after it
    # E: (dtau_n, dsdot_n) -> state perturbation at fixed time just before impact n
    E = np.array([[-sdot_n, 0.0], [-a_pre, 1.0]])
    # S: saltation matrix of the impact s = wall, reset R = diag(1, -r) (Eq. 11)
    R = np.diag([1.0, -p.r])
    F_minus = np.array([sdot_n, a_pre])
    F_plus = np.array([v0, a_post])
    S = R + np.outer(F_plus - R @ F_minus, np.array([1.0, 0.0])) / sdot_n
    # P: state perturbation at fixed time just before impact n+1 -> (dtau_{n+1}, dsdot_{n+1})
    v1 = fl.v
    a1 = forcing_rhs(th1, p.alpha, p.beta, p.gamma) - p.beta * v1
    P = np.array([[-1.0 / v1, 0.0], [-a1 / v1, 1.0]])
    J = P @ fl.phi @ S @ E
    return StepJacobian(tau1, v1, fl.wall, J, False, Status.ACTIVE.label)


#: This track as a :class:`core.results.Track` (``orbit`` and ``step_jacobian`` take the options
#: ``rtol``, ``atol``, ``max_step``, ``t_max``).
TRACK = TrackFunctions("scipy", orbit, step_jacobian)

__all__ = [
    "Options",
    "Flight",
    "flight",
    "orbit",
    "dense_orbit",
    "DenseTrajectory",
    "step_jacobian",
    "TRACK",
    "RTOL",
    "ATOL",
    "MAX_STEP",
]
