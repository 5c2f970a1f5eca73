"""Certified periodic orbits, Floquet multipliers and bifurcation points of the impact map.

**An orbit** (:func:`certify_periodic_orbit`) is proven in two parts:

1. *the equations*: the Krawczyk operator (:mod:`.krawczyk`) on the multiple-shooting system of
   :mod:`.shooting` (the pre-impact states of one period, Eqs. 7-8 and 11 in closed form) proves a
   box ``X`` that holds exactly one zero, enclosed by ``K(X)``;
2. *the dynamics*: for **every** state in the enclosure, each flight of the orbit is certified as
   the golden impact sequences are (:func:`.contact.certified_flight` on the box of initial states:
   both gaps positive on ``[0, t_lo]``, the gap to the next wall strictly monotone on
   ``[t_lo, t_hi]``, the other gap positive there), and the enclosed duration ``t_i`` lies in
   ``(0, t_hi]``: so the zero of the equations is the *first* wall contact of the flight, on the
   right wall, transversal -- an orbit of the map, with no impact skipped.  The sticking policy is
   proven to bounce at every impact (:func:`.sticking.stick_decision`).

The Floquet multipliers are the eigenvalues of the monodromy matrix enclosed over the box,
``tr/2 +- sqrt(tr^2/4 - det)``: a real pair where the discriminant is proven positive, a complex
pair (``acb``) where it is proven negative.  The determinant is checked against its closed form
``r^(2p) exp(-2 pi m beta)`` (:func:`closed_form_det`).

**A bifurcation point** (:func:`certify_bifurcation`): the same operator on the extended system
(orbit equations plus ``det(M - I) = 0`` for a fold, ``det(M + I) = 0`` for a period doubling),
the parameter (``r`` or ``alpha``) the last unknown.  At a fold the orbit equations alone are
singular; the extended system is regular at a quadratic, transversal fold (and at a period
doubling whose multiplier crosses -1 with nonzero speed), and the Krawczyk inclusion *proves* that
regularity (every matrix of ``DF(X)`` is invertible) together with existence and uniqueness of the
point in the box.  The flights are then proven with the parameter as a ball (the enclosure).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from flint import acb, arb

from ...core.checks import MAX_PERIOD, TAU0_MAX, InputTypeError, check_array, check_choice, check_int
from ...core.deprecation import UNSET, renamed_argument
from ...core.params import check_param, check_value
from ..sticking import STICK_TIME
from .balls import PREC, CertificationError, check_prec, mod_two_pi, precision
from .contact import FlightCertificate, certified_flight
from .krawczyk import KrawczykResult, krawczyk
from .model import Model
from .shooting import MU_NAMES, SIGMA, Numbers, Shape, extended_residual, monodromy, orbit_residual
from .sticking import stick_decision


@dataclass
class CertifiedPeriodicOrbit:
    """A proven periodic orbit: ``tau`` (unwrapped pre-impact times) and ``sdot`` (pre-impact
    velocities), ``durations`` of the flights, ``monodromy`` (2x2 balls), ``multipliers`` (``acb``),
    the Krawczyk result and the flight certificates; ``model`` holds the parameter balls (a
    bifurcation parameter enclosed)."""

    model: Model
    shape: Shape
    tau: list
    sdot: list
    durations: list
    monodromy: list
    multipliers: list
    krawczyk: KrawczykResult
    flights: list = field(repr=False)

    @property
    def theta(self) -> list:
        """The phases ``tau mod 2 pi`` (balls)."""
        return [mod_two_pi(t) for t in self.tau]

    @property
    def walls(self) -> tuple:
        return self.shape.walls

    @property
    def max_radius(self) -> float:
        return max(float(b.rad()) for b in self.tau + self.sdot)


@dataclass
class CertifiedBifurcation:
    """A proven fold or period-doubling point: the parameter ``name`` and its enclosure ``value``,
    and the orbit at it (its multipliers include ``+1`` or ``-1``)."""

    kind: str
    name: str
    value: arb
    orbit: CertifiedPeriodicOrbit


def unwrap(theta, turns: int = 1) -> list[float]:
    """Unwrapped times from the phases ``theta`` (each flight shorter than ``2 pi``); increasing input is
    kept."""
    theta = [float(t) for t in theta]
    two_pi = 2 * math.pi
    out = [theta[0]]
    for t in theta[1:]:
        out.append(t if t > out[-1] else out[-1] + ((t - out[-1]) % two_pi))
    if not out[-1] < out[0] + two_pi * turns:
        raise ValueError(f"theta={theta!r}: the times do not fit in {turns} driving period(s) after theta[0]")
    return out


def closed_form_det(model_or_numbers, shape: Shape) -> arb:
    """``det M = r^(2p) exp(-2 pi m beta)`` on a periodic orbit (the velocities telescope)."""
    m = model_or_numbers
    return m.r ** (2 * shape.impacts) * (-2 * shape.turns * arb.pi() * m.beta).exp()


def floquet(M) -> list:
    """The eigenvalues of the 2x2 ball matrix ``M`` as ``acb``: a real pair (ascending) or a complex
    pair (negative imaginary part first); raises where the discriminant's sign is not proven."""
    half = (M[0][0] + M[1][1]) / 2
    det = M[0][0] * M[1][1] - M[0][1] * M[1][0]
    disc = half * half - det
    if disc > 0:
        q = disc.sqrt()
        return [acb(half - q), acb(half + q)]
    if disc < 0:
        q = (-disc).sqrt()
        return [acb(half, -q), acb(half, q)]
    raise CertificationError("Floquet multipliers: real or complex not decided (a double multiplier?)")


def prove_flights(model: Model, shape: Shape, tau: list, sdot: list, prec: int) -> list[FlightCertificate]:
    """For every state in the balls ``(tau_i, sdot_i)``: the impact bounces (sticking policy), the
    flight's first wall contact is the next wall, and the enclosed duration is that contact (module
    docstring).  Returns the flight certificates; raises :class:`CertificationError` otherwise."""
    p = shape.impacts
    two_pi_m = 2 * shape.turns * arb.pi()
    certs = []
    for i in range(p):
        j = (i + 1) % p
        w, v = shape.walls[i], sdot[i]
        if not ((w == 0 and v > 0) or (w == -1 and v < 0)):
            raise CertificationError(f"impact {i}: the velocity's sign does not match wall {w}")
        if stick_decision(model, tau[i], w, v, STICK_TIME) is not None:
            raise CertificationError(f"impact {i}: the sticking policy does not provably bounce")
        c = certified_flight(model, tau[i], float(w), -model.r * v, prec=prec)
        t = (tau[j] + two_pi_m if j == 0 else tau[j]) - tau[i]
        if c.wall != shape.walls[j]:
            raise CertificationError(f"flight {i}: the first contact is wall {c.wall}, not {shape.walls[j]}")
        if not (t > 0 and t <= c.root_bracket[1]):
            raise CertificationError(f"flight {i}: the duration is not proven to be the first contact")
        certs.append(c)
    return certs


def _orbit(model: Model, P: Numbers, shape: Shape, x: list, res: KrawczykResult, prec: int) -> CertifiedPeriodicOrbit:
    tau, sdot = x[0::2], x[1::2]
    flights = prove_flights(model, shape, tau, sdot, prec)
    p = shape.impacts
    dur = [(tau[(i + 1) % p] + (2 * shape.turns * arb.pi() if i == p - 1 else 0)) - tau[i] for i in range(p)]
    M = monodromy(x, P, shape)
    det = M[0][0] * M[1][1] - M[0][1] * M[1][0]
    if not det.overlaps(closed_form_det(P, shape)):  # pragma: no cover - would be a bug
        raise CertificationError("det of the monodromy disagrees with its closed form")
    return CertifiedPeriodicOrbit(model, shape, tau, sdot, dur, M, floquet(M), res, flights)


def _start(theta, sdot, turns: int, prec: int):
    """The guess checked (given: :data:`~gear_rattle.core.deprecation.UNSET` marks one missing;
    :mod:`core.checks`: 1-D sequences of at most ``MAX_PERIOD`` phases ``|theta| <= 1e6`` and velocities
    ``sdot != 0`` of equal length, ``1 <= turns <= MAX_PERIOD``, the precision) as ``(shape, x0)``."""
    for name, value in (("theta", theta), ("sdot", sdot)):
        if value is UNSET:
            raise InputTypeError(f"{name} is missing: the guess is p pre-impact phases theta and velocities sdot")
    theta = check_array("theta", theta, -TAU0_MAX, TAU0_MAX, max_size=MAX_PERIOD).tolist()
    sdot = check_array(
        "sdot", sdot, nonzero=True, max_size=MAX_PERIOD, allowed="finite, nonzero pre-impact velocities"
    ).tolist()
    if len(theta) != len(sdot):
        raise ValueError(f"theta and sdot must be non-empty and of equal length (got {len(theta)}, {len(sdot)})")
    check_prec(prec)
    shape = Shape(tuple(0 if float(v) > 0 else -1 for v in sdot), check_int("turns", turns, 1, MAX_PERIOD))
    x0 = []
    for t, v in zip(unwrap(theta, shape.turns), sdot):
        x0 += [t, float(v)]
    return shape, x0


def certify_periodic_orbit(
    params, theta=UNSET, sdot=UNSET, turns: int = 1, *, prec: int = PREC, tau=UNSET
) -> CertifiedPeriodicOrbit:
    """Prove the periodic orbit near the guess by the Krawczyk operator on the periodic-orbit equations,
    with every flight proven (no earlier wall contact).

    Parameters
    ----------
    params : Params or mapping
        A :class:`Params` or a mapping of decimal strings (see :class:`.model.Model`).
    theta, sdot : sequence of float
        The guess (both required): the p pre-impact phases and velocities of one period (e.g. from the
        float64 :func:`mapimpl.periodic.find_periodic`); the signs of ``sdot`` give the walls.
    turns : int, optional
        Driving periods per period, ``1 <= turns <= 100000``.
    prec : int, optional
        Working precision in bits, ``64 <= prec <= 65536``.
    tau : sequence of float, optional
        The old name of ``theta`` (a DeprecationWarning).

    Returns
    -------
    CertifiedPeriodicOrbit
        The orbit's enclosures, flight durations, monodromy matrix and Floquet multipliers (balls).

    Raises
    ------
    CertificationError
        When no orbit is proven near the guess.

    Examples
    --------
    Fig. 2's orbit (:func:`mapimpl.periodic.find_periodic`'s example), proven from a 4-digit guess:

    >>> from gear_rattle.core.params import Params
    >>> from gear_rattle.mapimpl.certified.periodic import certify_periodic_orbit
    >>> o = certify_periodic_orbit(Params(0.5, 0.1, 0.1, 0.9), [2.034, 4.110, 6.087], [-0.7343, 0.6229, 0.4421])
    >>> o.walls, o.max_radius < 1e-80
    ((-1, 0, 0), True)
    >>> all(abs(z) < 1 for z in o.multipliers)  # stable
    True
    """
    theta = renamed_argument("tau", "theta", theta, tau, UNSET)
    shape, x0 = _start(theta, sdot, turns, prec)
    with precision(prec):
        model = Model(params)
        P = Numbers(model)
        res = krawczyk(lambda x: orbit_residual(x, P, shape), x0)
        return _orbit(model, P, shape, res.box, res, prec)


def certify_bifurcation(
    kind: str,
    params,
    name: str,
    theta=UNSET,
    sdot=UNSET,
    mu=UNSET,
    turns: int = 1,
    *,
    prec: int = PREC,
    tau=UNSET,
) -> CertifiedBifurcation:
    """Prove the fold (``kind="fold"``) or period doubling (``"period-doubling"``) near the guess, by the
    Krawczyk operator on the extended system (the orbit equations and ``det(M -/+ I) = 0``).

    Parameters
    ----------
    kind : {"fold", "period-doubling"}
        The bifurcation.
    params : Params or mapping
        The other parameters (a :class:`Params` or a mapping of decimal strings).
    name : str
        The bifurcation parameter (:data:`MU_NAMES`).
    theta, sdot : sequence of float
        The guess of the orbit at the bifurcation (p pre-impact phases and velocities; required).
    mu : float
        The guess of the parameter's value (required).
    turns : int, optional
        Driving periods per period, ``1 <= turns <= 100000``.
    prec : int, optional
        Working precision in bits, ``64 <= prec <= 65536``.
    tau : sequence of float, optional
        The old name of ``theta`` (a DeprecationWarning).

    Returns
    -------
    CertifiedBifurcation
        The enclosure ``value`` of the parameter and the orbit at it.

    Examples
    --------
    Figs. 4-5: r2, the fold of the 6-impact orbit at alpha = 3, proven from a 4-digit guess
    (:func:`validation.dynamics.crises.r2.certified_r2` does this for the report):

    >>> from gear_rattle.core.params import Params
    >>> from gear_rattle.mapimpl.certified.periodic import certify_bifurcation
    >>> b = certify_bifurcation(
    ...     "fold",
    ...     Params(3.0, 0.1, 0.1, 0.8),
    ...     "r",
    ...     [1.055, 2.017, 3.013, 4.172, 5.141, 6.102],
    ...     [-1.614, -1.343, -0.709, 1.734, 1.448, 0.829],
    ...     0.8214,
    ... )
    >>> print(f"r2 = {float(b.value):.14f}", bool(b.value.rad() < 1e-80))
    r2 = 0.82144044758015 True
    """
    check_choice("kind", kind, tuple(SIGMA))
    check_choice("name", name, MU_NAMES)
    theta = renamed_argument("tau", "theta", theta, tau, UNSET)
    shape, x0 = _start(theta, sdot, turns, prec)
    if mu is UNSET:
        raise InputTypeError(f"mu is missing: the guess of the bifurcation parameter {name}")
    try:
        mu = check_param(name, mu)
    except ValueError as e:  # InputTypeError too: named as the argument it is
        raise type(e)(f"mu: {e}") from None
    with precision(prec):
        base = Model(params)
        res = krawczyk(lambda y: extended_residual(y, base, shape, name, kind), x0 + [float(mu)])
        value = res.box[-1]
        try:
            for end in (value.lower(), value.upper()):
                check_value(name, float(end))
        except ValueError as e:
            raise CertificationError(f"the {kind} found from the guess is outside the parameter range: {e}") from None
        balls = base.balls()
        balls[name] = value
        model = Model.from_balls(**balls)
        orbit = _orbit(model, Numbers(model), shape, res.box[:-1], res, prec)
        sigma = SIGMA[kind]
        if not any(z.contains(acb(sigma)) for z in orbit.multipliers):  # pragma: no cover - would be a bug
            raise CertificationError(f"no multiplier encloses {sigma:+d} at the {kind}")
        return CertifiedBifurcation(kind, name, value, orbit)


__all__ = [
    "CertifiedPeriodicOrbit",
    "CertifiedBifurcation",
    "unwrap",
    "closed_form_det",
    "floquet",
    "prove_flights",
    "certify_periodic_orbit",
    "certify_bifurcation",
]
