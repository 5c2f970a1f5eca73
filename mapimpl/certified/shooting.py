"""Periodic orbits of the impact map as zeros of an analytic multiple-shooting system.

A p-impact, m-turn periodic orbit (Section 3 of the paper) visits the pre-impact states
``(tau_i, v_i)``, ``i = 0..p-1``, on the walls ``w_i`` (``v_i > 0`` on the upper wall ``s = 0``,
``v_i < 0`` on the lower wall ``s = -1``), with the times unwrapped: ``tau_0 < tau_1 < ... <
tau_{p-1} < tau_p := tau_0 + 2 pi m``.  After the reset ``u_i = -r v_i`` (Eq. 11) the closed-form
flight (Eqs. 7-8) leaving ``(tau_i, w_i, u_i)`` lasts ``t_i = tau_{i+1} - tau_i`` and must land on
the next wall with the next pre-impact velocity (``j = i + 1 mod p``):

    w_i + [s(t_i) - s_0] - w_j = 0,        s'(t_i) - v_j = 0,

with ``s(t) - s_0 = 2 alpha cos(tau_i + t/2) sin(t/2) + W E1 + gamma (beta t + E - 1)/beta^2`` and
``s'(t) = alpha cos(tau_i + t) + W E + gamma E1`` (``W = u_i - alpha cos tau_i``, ``E = exp(-beta t)``,
``E1 = (1 - E)/beta``).  These ``2p`` equations in the ``2p`` unknowns
``x = (tau_0, v_0, ..., tau_{p-1}, v_{p-1})`` (:func:`orbit_residual`) are analytic: the durations
are differences of the unknowns, so no root of a flight has to be found to evaluate them.  They say
nothing about *earlier* wall contacts: that is proven separately (:mod:`.periodic`).

The step Jacobian of the map (docs/model.md), pre-impact to pre-impact, with ``a_0 = f(tau_i) - beta u_i``
and ``a_1 = f(tau_i + t_i) - beta s'(t_i)`` the accelerations at departure and landing:

    d tau'/d tau = (u + E1 a_0)/s',  d tau'/d v = r E1/s',
    d v'/d tau = a_1 d tau'/d tau - E a_0,  d v'/d v = r (a_1 E1/s' - E),

and the monodromy matrix ``M = J_{p-1} ... J_0`` (:func:`monodromy`) has the Floquet multipliers as
eigenvalues.  A fold of the orbit's branch has a multiplier +1, a period doubling -1:
:func:`extended_residual` appends ``det(M - sigma I)`` (``sigma = +1`` or ``-1``) to the orbit
equations, with the parameter ``mu`` (``r`` or ``alpha``) as the last unknown.

Every function here is written over "numbers": ``arb`` balls or the jets of :mod:`.jets` (whose
derivatives then give the Jacobian of the system, the determinant row included).
"""

from __future__ import annotations

from dataclasses import dataclass

from flint import arb

from ...core.checks import MAX_PERIOD, check_int

from .jets import cos, expm1, sin
from .model import Model

#: Parameters that can be the unknown of a bifurcation point.
MU_NAMES = ("r", "alpha")
#: The multiplier of each kind of bifurcation point.
SIGMA = {"fold": 1, "period-doubling": -1}


@dataclass(frozen=True)
class Shape:
    """The combinatorics of a periodic orbit: the wall of each pre-impact state and the number of
    driving periods (``turns``) it takes."""

    walls: tuple
    turns: int = 1

    def __post_init__(self):
        if not self.walls or any(w not in (0, -1) for w in self.walls):
            raise ValueError(f"walls={self.walls!r} is out of range: allowed a non-empty sequence of 0 and -1")
        check_int("turns", self.turns, 1, MAX_PERIOD, strict=True)

    @property
    def impacts(self) -> int:
        return len(self.walls)


class Numbers:
    """The parameters as numbers (balls or jets): those of a :class:`Model`, one of them (``mu_name``)
    replaced by ``mu`` when given."""

    def __init__(self, model: Model, mu_name: str | None = None, mu=None):
        self.alpha, self.beta, self.gamma, self.r = model.alpha, model.beta, model.gamma, model.r
        if mu_name is not None:
            if mu_name not in MU_NAMES:
                raise ValueError(f"parameter {mu_name!r} is out of range: allowed one of {MU_NAMES}")
            setattr(self, mu_name, mu)

    def forcing(self, tau):
        """f(tau) = -alpha sin tau + alpha beta cos tau + gamma (Eq. 3)."""
        return -self.alpha * sin(tau) + self.alpha * self.beta * cos(tau) + self.gamma


def _flight(P: Numbers, tau0, u, t):
    """``(s(t) - s_0, s'(t), E, E1)`` of the flight leaving ``(tau0, ., u)`` (Eqs. 7-8)."""
    bt = P.beta * t
    em1 = expm1(-bt)
    e, e1 = em1 + 1, -em1 / P.beta
    w = u - P.alpha * cos(tau0)
    half = t / 2
    ds = 2 * P.alpha * cos(tau0 + half) * sin(half) + w * e1 + P.gamma * (bt + em1) / (P.beta * P.beta)
    v = P.alpha * cos(tau0 + t) + w * e + P.gamma * e1
    return ds, v, e, e1


def _legs(x, shape: Shape):
    """``(tau_i, v_i, w_i, t_i, v_j, w_j)`` for each flight of the orbit."""
    p = shape.impacts
    two_pi_m = 2 * shape.turns * arb.pi()
    for i in range(p):
        j = (i + 1) % p
        tau_j = x[2 * j] + two_pi_m if j == 0 else x[2 * j]
        yield x[2 * i], x[2 * i + 1], shape.walls[i], tau_j - x[2 * i], x[2 * j + 1], shape.walls[j]


def orbit_residual(x, P: Numbers, shape: Shape) -> list:
    """The ``2p`` orbit equations at ``x = (tau_0, v_0, ..., tau_{p-1}, v_{p-1})`` (module docstring)."""
    out = []
    for tau, v, w, t, v_next, w_next in _legs(x, shape):
        ds, v1, _, _ = _flight(P, tau, -P.r * v, t)
        out += [ds + (w - w_next), v1 - v_next]
    return out


def monodromy(x, P: Numbers, shape: Shape) -> list:
    """``M = J_{p-1} ... J_0`` (2x2, a list of rows) from the step Jacobians (module docstring)."""
    M: list | None = None
    for tau, v, _w, t, _vn, _wn in _legs(x, shape):
        u = -P.r * v
        _, v1, e, e1 = _flight(P, tau, u, t)
        a0 = P.forcing(tau) - P.beta * u
        a1 = P.forcing(tau + t) - P.beta * v1
        j11 = (u + e1 * a0) / v1
        j12 = P.r * e1 / v1
        J = [[j11, j12], [a1 * j11 - e * a0, P.r * (a1 * e1 / v1 - e)]]
        M = J if M is None else [[J[i][0] * M[0][k] + J[i][1] * M[1][k] for k in range(2)] for i in range(2)]
    if M is None:
        raise ValueError(f"shape={shape!r} has no impact: allowed an orbit of one impact or more")
    return M


def det_shift(M, sigma: int):
    """``det(M - sigma I)`` of a 2x2 matrix."""
    return (M[0][0] - sigma) * (M[1][1] - sigma) - M[0][1] * M[1][0]


def extended_residual(y, model: Model, shape: Shape, mu_name: str, kind: str) -> list:
    """The orbit equations plus ``det(M - sigma I)`` (``kind`` ``"fold"``: sigma = +1; ``"period-doubling"``:
    sigma = -1) at ``y = (x, mu)``, ``mu`` the value of the parameter ``mu_name``."""
    if kind not in SIGMA:
        raise ValueError(f"kind={kind!r} is out of range: allowed one of {tuple(SIGMA)}")
    x, mu = y[:-1], y[-1]
    P = Numbers(model, mu_name, mu)
    return orbit_residual(x, P, shape) + [det_shift(monodromy(x, P, shape), SIGMA[kind])]


__all__ = [
    "MU_NAMES",
    "SIGMA",
    "Shape",
    "Numbers",
    "orbit_residual",
    "monodromy",
    "det_shift",
    "extended_residual",
]
