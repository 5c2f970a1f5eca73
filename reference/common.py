"""Pieces shared by the numerical tracks: the right-hand side of Eq. (3), input validation, phase
bookkeeping, the sticking policy on host floats and the trajectory record from which the event
table (:class:`core.results.ImpactSequence`) is built.  The hybrid-ODE events are in
:mod:`reference.events`.

Nothing here uses the closed-form flight of Eqs. (7)-(8): the tracks integrate Eq. (3) numerically,
from its right-hand side only,

    s'' = e''(tau) + beta e'(tau) + gamma - beta s',    e(tau) = alpha sin(tau)          (Eq. 3)

so ``s'' = -alpha sin(tau) + alpha beta cos(tau) + gamma - beta s'``, and apply the impact law
Eqs. (9)-(11) (``sdot -> -r sdot`` at ``s = 0`` reached upward and at ``s = -1`` reached downward).
The only things taken from :mod:`mapimpl` are the validated :class:`~core.params.Params`, the
result types and the event-table builder, and the *shared* sticking policy
:func:`mapimpl.sticking.decide_stick` (by design every track applies exactly the same policy).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..core import jax_config  # noqa: F401  (float64)
import jax

from ..core.state import Array, MapState
from ..core.state import sequence_from_states
from ..core.phase import TWO_PI_HI, TWO_PI_LO, TWO_PI_MID
from ..core.checks import MAX_IMPACTS, check_int, check_real, check_start
from ..core.params import Params, check_params
from ..core.results import ImpactSequence
from ..mapimpl.sticking import STICK_TIME, decide_stick

# Cody-Waite split of 2*pi: the map's constants (mapimpl.flight), so phases compare exactly.
TWO_PI = 2.0 * math.pi


def forcing_rhs(tau: float, alpha: float, beta: float, gamma: float) -> float:
    """``e'' + beta e' + gamma`` of Eq. (3) with ``e = alpha sin(tau)``: the acceleration at rest."""
    return -alpha * math.sin(tau) + alpha * beta * math.cos(tau) + gamma


def reduce_phase(theta: float, cycles: int) -> tuple[float, int]:
    """``theta`` reduced into [0, 2 pi) with the whole turns carried into ``cycles`` (the three-term
    Cody-Waite reduction of :func:`gear_rattle.core.phase.reduce_phase`, in Python floats)."""
    m = math.floor(theta / TWO_PI)
    th = ((theta - m * TWO_PI_HI) - m * TWO_PI_MID) - m * TWO_PI_LO
    adj = 1 if th >= TWO_PI else (-1 if th < 0.0 else 0)
    th = ((th - adj * TWO_PI_HI) - adj * TWO_PI_MID) - adj * TWO_PI_LO
    th = min(max(th, 0.0), math.nextafter(TWO_PI, 0.0))
    return th, cycles + int(m) + adj


def check_option(name: str, value: float, lo: float, hi: float) -> float:
    """A numerical solver option: a finite float with ``lo < value <= hi`` (:func:`core.checks.check_real`)."""
    return check_real(name, value, lo, hi, lo_open=True)


def validate_start(
    params: Params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None,
    names: tuple[str, str] = ("tau0", "sdot0"),
) -> int:
    """Validate the arguments of an ``orbit`` call (the rules and messages of :func:`mapimpl.orbit.map_orbit`:
    :mod:`core.checks`; ``names`` of tau0 and sdot0 as in :func:`core.checks.check_start`); returns
    ``n_impacts`` as an int."""
    check_params(params)
    n = check_int("n_impacts", n_impacts, 0, MAX_IMPACTS)
    check_start(tau0, sdot0, s0, names)
    return n


# ``stick_time`` traced: one compilation serves every threshold
_decide_jit = jax.jit(decide_stick)


def stick_decision(
    theta: float, wall: int, sdot: float, p: Params, stick_time: float = STICK_TIME
) -> tuple[bool, float, float, float]:
    """The shared sticking policy (:func:`mapimpl.sticking.decide_stick`) on Python floats, with the
    threshold ``stick_time`` (checked by the track's entry point, :func:`mapimpl.sticking.check_stick_time`).

    Returns ``(stick, t_acc, delay, phase)`` (``delay = inf``: stuck forever; ``phase``: the canonical
    release phase, where the flight after a release starts).
    """
    d = _decide_jit(theta, wall, sdot, p.alpha, p.beta, p.gamma, p.r, stick_time)
    return bool(d.stick), float(d.t_acc), float(d.delay), float(d.phase)


def release_start(theta: float, cycles: int, delay: float, phase: float) -> tuple[float, int]:
    """Start ``(theta0, cycles0)`` of the flight after a release: the canonical release ``phase`` and
    the turn counter advanced by the whole periods elapsed while stuck (as
    :func:`mapimpl.sticking.released_turns`)."""
    return phase, cycles + int(round((theta + delay - phase) / TWO_PI))


class StepInfo(NamedTuple):
    """Sticking bookkeeping of one integrated step (both tracks; the fields
    :func:`mapimpl.orbit.sequence_from_states` reads): the step ``stuck`` to the wall, the elapsed
    times of sticking and release (NaN if none), and the monotone ``segments`` of its flight."""

    stuck: Array
    stick_tau: Array
    release_tau: Array
    segments: Array


class Trajectory(NamedTuple):
    """Stacked pre-impact states and step records of a track's orbit (leading axis: impact 1..n)."""

    states: MapState
    infos: StepInfo


class TrajectoryRecorder:
    """Collects the pre-impact states and step infos of an orbit computed step by step on the host
    (the scipy track) in the layout of :class:`mapimpl.impact_map.Trajectory`, so that every track
    builds its :class:`~core.results.ImpactSequence` with the same
    :func:`mapimpl.orbit.sequence_from_states`."""

    def __init__(self, theta: float, cycles: int, sdot: float, wall: int, status: int) -> None:
        self.first = self._state([theta], [cycles], [sdot], [wall], [status], scalar=True)
        self._states: list[tuple] = []
        self._infos: list[tuple] = []

    @staticmethod
    def _state(theta, cycles, sdot, wall, status, scalar=False) -> MapState:
        st = MapState(
            np.asarray(theta, np.float64),
            np.asarray(cycles, np.int64),
            np.asarray(sdot, np.float64),
            np.asarray(wall, np.int32),
            np.asarray(status, np.int32),
        )
        return MapState(*(x[0] for x in st)) if scalar else st

    def step(
        self,
        theta: float,
        cycles: int,
        sdot: float,
        wall: int,
        status: int,
        stuck: bool = False,
        stick_tau: float = math.nan,
        release_tau: float = math.nan,
        segments: int = 0,
    ) -> None:
        """Record the state after one step and what happened during it."""
        self._states.append((theta, cycles, sdot, wall, status))
        self._infos.append((stuck, stick_tau, release_tau, segments))

    def sequence(self, params: Params, track: str, meta: dict) -> ImpactSequence:
        """The event table of the recorded orbit."""
        cols: list = list(zip(*self._states)) or [[]] * 5
        info: list = list(zip(*self._infos)) or [[]] * 4
        traj = Trajectory(
            self._state(*cols),
            StepInfo(
                np.asarray(info[0], bool),
                np.asarray(info[1], np.float64),
                np.asarray(info[2], np.float64),
                np.asarray(info[3], np.int64),
            ),
        )
        return sequence_from_states(params, self.first, traj, track=track, meta=meta)


__all__ = [
    "TWO_PI",
    "forcing_rhs",
    "reduce_phase",
    "check_option",
    "validate_start",
    "stick_decision",
    "release_start",
    "StepInfo",
    "Trajectory",
    "TrajectoryRecorder",
]
