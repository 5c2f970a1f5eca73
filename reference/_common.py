"""Pieces shared by the numerical tracks: the right-hand side of Eq. (3), input validation, phase
bookkeeping and the event table (:class:`mapimpl.orbit.ImpactSequence`).

Nothing here uses the closed-form flight of Eqs. (7)-(8): the tracks integrate Eq. (3) numerically,
from its right-hand side only,

    s'' = e''(tau) + beta e'(tau) + gamma - beta s',    e(tau) = alpha sin(tau)          (Eq. 3)

so ``s'' = -alpha sin(tau) + alpha beta cos(tau) + gamma - beta s'``, and apply the impact law
Eqs. (9)-(11) (``sdot -> -r sdot`` at ``s = 0`` reached upward and at ``s = -1`` reached downward).
The only things taken from :mod:`mapimpl` are the validated :class:`~mapimpl.params.Params`, the
result type, and the *shared* sticking policy :func:`mapimpl.sticking.decide_stick` (by design
every track applies exactly the same policy).
"""

from __future__ import annotations

from typing import NamedTuple

import math
from dataclasses import dataclass, field

import numpy as np

from ..mapimpl import _jax  # noqa: F401  (float64)
import jax

from ..mapimpl.orbit import ImpactSequence
from ..mapimpl.params import Params
from ..mapimpl.sticking import STICK_TIME, decide_stick

#: Longest flight integrated before the orbit is declared ``"no_impact"`` (same value as the map's
#: :data:`mapimpl.finder.T_MAX`, restated here so the reference does not import the finder).
T_MAX = 2000.0
#: Most monotone segments (velocity reversals + 1) integrated in one flight before ``"step_cap"``.
MAX_SEGMENTS = 4000

# Cody-Waite split of 2*pi (same constants as the map's phase reduction, so phases compare exactly).
TWO_PI = 2.0 * math.pi
_TWO_PI_HI = 6.28318530717958623200e00
_TWO_PI_LO = 2.44929359829470635446e-16


def forcing_rhs(tau: float, alpha: float, beta: float, gamma: float) -> float:
    """``e'' + beta e' + gamma`` of Eq. (3) with ``e = alpha sin(tau)``: the acceleration at rest."""
    return -alpha * math.sin(tau) + alpha * beta * math.cos(tau) + gamma


def reduce_phase(theta: float, cycles: int) -> tuple[float, int]:
    """``theta`` reduced into [0, 2 pi) with the whole turns carried into ``cycles`` (Cody-Waite)."""
    m = math.floor(theta / TWO_PI)
    th = (theta - m * _TWO_PI_HI) - m * _TWO_PI_LO
    adj = 1 if th >= TWO_PI else (-1 if th < 0.0 else 0)
    th = (th - adj * _TWO_PI_HI) - adj * _TWO_PI_LO
    th = min(max(th, 0.0), math.nextafter(TWO_PI, 0.0))
    return th, cycles + int(m) + adj


def check_option(name: str, value: float, lo: float, hi: float) -> float:
    """Validate a numerical option: ``lo < value <= hi``; ``ValueError`` names it and the range."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"option {name}={value!r} is not a number: allowed {lo:g} < {name} <= {hi:g}") from None
    if not (math.isfinite(x) and lo < x <= hi):
        raise ValueError(f"option {name}={value!r} is out of range: allowed {lo:g} < {name} <= {hi:g}")
    return x


def validate_start(params: Params, tau0: float, sdot0: float, n_impacts: int, s0: float | None) -> int:
    """Validate the arguments of an ``orbit`` call (same rules and messages as :func:`mapimpl.orbit.map_orbit`)."""
    if not isinstance(params, Params):
        raise ValueError(f"params={params!r} is out of range: allowed a mapimpl.params.Params")
    try:
        n = int(n_impacts)
    except (TypeError, ValueError):
        raise ValueError(f"n_impacts={n_impacts!r} is out of range: allowed an integer >= 0") from None
    if n < 0 or n != n_impacts:
        raise ValueError(f"n_impacts={n_impacts!r} is out of range: allowed n_impacts >= 0")
    if not np.isfinite(tau0):
        raise ValueError(f"initial tau0={tau0!r} is out of range: allowed any finite real")
    if not np.isfinite(sdot0):
        raise ValueError(f"initial sdot0={sdot0!r} is out of range: allowed any finite real")
    if s0 is None:
        if sdot0 == 0.0:
            raise ValueError(f"initial sdot0={sdot0!r} is out of range: a pre-impact state needs sdot0 != 0 "
                             "(> 0 hits s = 0, < 0 hits s = -1)")
    elif not (np.isfinite(s0) and -1.0 <= s0 <= 0.0):
        raise ValueError(f"initial s0={s0!r} is out of range: allowed -1 <= s0 <= 0")
    return n


_decide_jit = jax.jit(decide_stick, static_argnames=("stick_time",))


def stick_decision(theta: float, wall: int, sdot: float, p: Params) -> tuple[bool, float, float, float]:
    """The shared sticking policy (:func:`mapimpl.sticking.decide_stick`) on Python floats.

    Returns ``(stick, t_acc, delay, phase)`` (``delay = inf``: stuck forever; ``phase``: the canonical
    release phase, where the flight after a release starts).
    """
    d = _decide_jit(theta, wall, sdot, p.alpha, p.beta, p.gamma, p.r, stick_time=STICK_TIME)
    return bool(d.stick), float(d.t_acc), float(d.delay), float(d.phase)


def release_start(theta: float, cycles: int, delay: float, phase: float) -> tuple[float, int]:
    """Start ``(theta0, cycles0)`` of the flight after a release: the canonical release ``phase`` and
    the turn counter advanced by the whole periods elapsed while stuck (as
    :func:`mapimpl.sticking.released_turns`)."""
    return phase, cycles + int(round((theta + delay - phase) / TWO_PI))


class StepJacobian(NamedTuple):
    """One impact-to-impact step by integration, with its Jacobian (both reference tracks):
    the next pre-impact state, ``jac = d(tau_{n+1}, sdot_{n+1})/d(tau_n, sdot_n)`` (0 if the step
    sticks), and the orbit status after the step."""

    tau: float
    sdot: float
    wall: int
    jac: np.ndarray
    stuck: bool
    status: str


@dataclass
class EventTable:
    """Accumulates impact / stick / release rows exactly like :func:`mapimpl.orbit.sequence_from_states`."""

    params: Params
    track: str
    n: list = field(default_factory=list)
    tau: list = field(default_factory=list)
    wall: list = field(default_factory=list)
    sdot: list = field(default_factory=list)
    kind: list = field(default_factory=list)

    def add(self, n: int, tau: float, wall: int, sdot: float, kind: str) -> None:
        self.n.append(int(n)); self.tau.append(float(tau)); self.wall.append(int(wall))
        self.sdot.append(float(sdot)); self.kind.append(kind)

    def sequence(self, status: str, meta: dict) -> ImpactSequence:
        t = np.asarray(self.tau, dtype=np.float64)
        return ImpactSequence(
            params=self.params, n=np.asarray(self.n, dtype=np.int64), tau=t, theta=np.mod(t, TWO_PI),
            wall=np.asarray(self.wall, dtype=np.int64), sdot=np.asarray(self.sdot, dtype=np.float64),
            kind=np.asarray(self.kind, dtype=str), status=status, track=self.track,
            meta=meta,
        )
