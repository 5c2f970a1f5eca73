"""The error a correct float64 implementation makes at each impact, and how the impact map carries it
along a golden case's orbit: the *amplification rule* of the tolerances (docs/golden.md, "Tolerances from
the conditioning").

**Assumption** (per impact reached by a flight).  An implementation puts the contact where its computed gap
to the wall vanishes, and that gap is off by at most

    e_n = POSITION_STEP + FLIGHT_ERROR h_n

the rounding step of a float64 position of magnitude below 2 at the wall (2^-52: the ``e`` of the chatter
rule) plus the error of its flight solution, relative to the height of the flight
``h_n = max |s(t) - s(0)| <= 1`` (1e-12: a transversal impact across the backlash located to ~1e-12, the
``err0`` of the chaotic horizon; a chatter bounce of height 1e-14 is located to its rounding).  A contact
of speed ``v_n`` and acceleration ``a_n = s''`` found where the gap is off by ``e_n`` is off by (the
implicit-function theorem on the impact condition ``s(tau) = wall``)

    dtau_n = e_n / |v_n|,        dsdot_n = |a_n| e_n / |v_n| + FLIGHT_ERROR

(the velocity's own error ``FLIGHT_ERROR``).  At a graze (small ``v_n``) this is the graze rule's
conditioning; along a chatter, the chatter rule's.

**Propagation.**  The analytic Jacobians of the impact map (Eqs. 12-13, :func:`mapimpl.impact_map.jacobian`)
carry an error of impact ``n`` to the later rows: at impact ``m`` it is ``|P_mn| l_n`` (componentwise
absolute values) with ``P_mn = J_m ... J_{n+1}`` and ``l_n = (dtau_n, dsdot_n)``.  A step that sticks forgets
its input (the release leaves from the canonical phase, a function of the parameters alone: ``J = 0``); a
stick row ``tau_n + t_acc`` has the sensitivity ``(1 + dt_acc/dtau, dt_acc/dsdot)`` to impact ``n``.  A
pre-impact initial state is exact.  The rule: :data:`SAFETY` times the largest such error over the rows
and the impacts (the largest single source, as the chaotic horizon's ``exp(lambda1 n)``; the safety
factor covers the sum over the sources), per column, rounded up to one digit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...core import _jax  # noqa: F401  (float64)
import jax
import jax.numpy as jnp

from ...core.params import Params
from ...mapimpl.flight import flight
from ...mapimpl.impact_map import jacobian

#: Rounding step of a float64 position of magnitude below 2 at a wall (2^-53 for ``s`` at ``s = -1`` and
#: for ``s + 1`` at ``s = 0``; 2^-52 beyond): the gap error of every contact.
POSITION_STEP = 2.0**-52
#: Error of a flight solution relative to the flight's height, and of the pre-impact velocity: a
#: transversal impact located to ~1e-12 (the per-impact error of the chaotic horizon).
FLIGHT_ERROR = 1e-12
#: Safety factor of the tolerance rules (chaotic horizon, chatter, amplification).
SAFETY = 10.0
#: Samples of a flight for its height ``max |s(t) - s(0)|``.
HEIGHT_SAMPLES = 257

_jacobian = jax.jit(jacobian)
_displacement = jax.jit(lambda t, th, v0, a, b, g: flight(t, th, v0, a, b, g).ds)


def round_up_1(x: float) -> float:
    """``x > 0`` rounded up to one significant digit (2.06e-8 -> 3e-8; 2e-6 stays 2e-6); 0 stays 0 (a case
    with no impact reached by a flight has no propagated error)."""
    if x == 0:
        return 0.0
    m = 10.0 ** math.floor(math.log10(x))
    return float(f"{math.ceil(x / m - 1e-9) * m:.1g}")


def flight_height(p: Params, theta0: float, v0: float, dt: float) -> float:
    """``h = max |s(t) - s(0)|`` over a flight of duration ``dt`` from phase ``theta0`` with velocity ``v0``
    (Eqs. 7-8 sampled at :data:`HEIGHT_SAMPLES` times), capped at 1 (the backlash)."""
    t = jnp.linspace(0.0, dt, HEIGHT_SAMPLES)
    return min(1.0, float(jnp.max(jnp.abs(_displacement(t, theta0, v0, p.alpha, p.beta, p.gamma)))))


def local_error(p: Params, h: float, tau: float, sdot: float) -> np.ndarray:
    """``(dtau_n, dsdot_n)`` of a contact at ``tau`` with pre-impact velocity ``sdot`` reached by a flight of
    height ``h`` (module docstring)."""
    e = POSITION_STEP + FLIGHT_ERROR * h
    a = -p.alpha * math.sin(tau) + p.alpha * p.beta * math.cos(tau) + p.gamma - p.beta * sdot
    return np.array([e / abs(sdot), abs(a) * e / abs(sdot) + FLIGHT_ERROR])


def stick_sensitivity(p: Params, tau: float, sdot: float, t_acc: float) -> np.ndarray:
    """``|d(tau + t_acc) / d(tau, sdot)|`` of a stick row, ``t_acc = 2 r |sdot| / ((1 - r) f_in(tau))``."""
    f = -p.alpha * math.sin(tau) + p.alpha * p.beta * math.cos(tau) + p.gamma
    df = -p.alpha * math.cos(tau) - p.alpha * p.beta * math.sin(tau)
    return np.array([abs(1.0 - t_acc * df / f), t_acc / abs(sdot)])


@dataclass(frozen=True)
class PropagatedError:
    """The largest first-order error of each column (``tau``, also ``tau_mod_2pi``; ``sdot``) of a case's
    rows under the per-impact assumption, and where it arises (``"impact n -> impact m"``)."""

    tau: float
    tau_where: str
    sdot: float
    sdot_where: str

    def tolerances(self) -> dict[str, float]:
        """The rule's absolute tolerance per column: :data:`SAFETY` times the error, rounded up to one digit."""
        t = round_up_1(SAFETY * self.tau)
        return {"tau": t, "tau_mod_2pi": t, "sdot": round_up_1(SAFETY * self.sdot)}

    def note(self, sets: list[str]) -> dict:
        """``notes.amplification`` of the case's settings."""
        return {
            "tau_error": float(f"{self.tau:.3g}"),
            "tau_worst": self.tau_where,
            "sdot_error": float(f"{self.sdot:.3g}"),
            "sdot_worst": self.sdot_where,
            "tolerance": self.tolerances(),
            "sets": sets,
            "rule": f"the largest first-order error at a row of an error made at one impact (gap error "
            f"2^-52 + {FLIGHT_ERROR:g} h at a contact of speed v: dtau = e / v, dsdot = |s''| e / v + "
            f"{FLIGHT_ERROR:g}), carried by the map's Jacobians; tolerance = {SAFETY:g} x that, rounded "
            "up to one digit, where it is not smaller than the case's own (docs/golden.md, tolerances "
            "from the conditioning)",
        }


def propagated_error(p: Params, seq, free_start: tuple[float, float, float] | None = None) -> PropagatedError:
    """The :class:`PropagatedError` of a case's rows ``seq`` (columns ``n, tau, tau_mod_2pi, wall, sdot,
    kind`` as arrays: a :class:`suite.Sequence`); ``free_start = (tau0, s0, sdot0)`` for a free-flight start
    (its impact 0 is reached by a flight), ``None`` for a pre-impact initial state (exact)."""
    sources: list[tuple[int, np.ndarray, np.ndarray]] = []  # (impact n, P_mn, l_n)
    worst = {"tau": (0.0, ""), "sdot": (0.0, "")}
    prev, start = None, None  # previous impact row; the flight to the next impact (theta0, v0, tau0, s0)
    if free_start is not None:
        start = (free_start[0] % (2 * math.pi), free_start[2], free_start[0])

    def record(row: str, errors) -> None:
        for n, err in errors:
            for k, c in enumerate(("tau", "sdot")[: len(err)]):
                if err[k] > worst[c][0]:
                    worst[c] = (float(err[k]), f"impact {n} -> {row}")

    for i, kind in enumerate(seq.kind):
        tau, sdot = float(seq.tau[i]), float(seq.sdot[i])
        if kind == "stick":
            sens = stick_sensitivity(p, float(seq.tau[prev]), float(seq.sdot[prev]), tau - float(seq.tau[prev]))
            record(f"stick row of impact {int(seq.n[i])}", [(n, [sens @ (np.abs(P) @ loc)]) for n, P, loc in sources])
            continue
        if kind == "release":
            sources, start = [], (float(seq.tau_mod_2pi[i]), 0.0, tau)
            continue
        if prev is None and start is None:  # a pre-impact initial state: exact
            prev = i
            continue
        if start is None:  # a free step from the previous impact (Eq. 11, then Eqs. 7-8)
            j = prev
            th0, v0, t0 = float(seq.tau_mod_2pi[j]), -p.r * float(seq.sdot[j]), float(seq.tau[j])
            jac = np.asarray(
                _jacobian(th0, v0, tau - t0, float(seq.tau_mod_2pi[i]), sdot, (p.alpha, p.beta, p.gamma, p.r))
            )
            sources = [(n, jac @ P, loc) for n, P, loc in sources]
            start = (th0, v0, t0)
        h = flight_height(p, start[0], start[1], tau - start[2])
        sources.append((int(seq.n[i]), np.eye(2), local_error(p, h, tau, sdot)))
        record(f"impact {int(seq.n[i])}", [(n, np.abs(P) @ loc) for n, P, loc in sources])
        prev, start = i, None
    return PropagatedError(worst["tau"][0], worst["tau"][1], worst["sdot"][0], worst["sdot"][1])


__all__ = [
    "POSITION_STEP",
    "FLIGHT_ERROR",
    "SAFETY",
    "PropagatedError",
    "propagated_error",
    "local_error",
    "flight_height",
    "stick_sensitivity",
    "round_up_1",
]
