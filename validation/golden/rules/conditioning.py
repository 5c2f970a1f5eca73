"""The error a correct float64 implementation can make at each row of a golden case, and the tolerance of
that row (docs/golden_tolerances.md, "Tolerances from the conditioning").

**The per-contact error** (the gap-error model).  An implementation puts a contact where its computed gap
to the wall vanishes, and that gap is off by at most

    e_n = GAP_ULPS 2^-52 + FLIGHT_ERROR h_n max(1, dt_n / 2 pi)

a few roundings of a float64 position of magnitude below 2 at the wall (:data:`GAP_ULPS` steps of
:data:`POSITION_STEP`) plus the error of its flight solution relative to the height of the flight,
``h_n = max |s(t) - s(0)| <= 1``, per forcing period of the flight's duration ``dt_n`` (an ODE solver's
steps, and its errors, grow with the length; :data:`FLIGHT_ERROR`, measured on our three tracks:
benchmarks/results/per_contact_error_*.json).
A contact of speed ``v_n`` and acceleration ``a_n = s''`` found where the gap is off by ``e_n`` is off by
(the implicit-function theorem on ``s(tau) = wall``)::

    dtau_n = e_n / |v_n|,        dsdot_n = |a_n| dtau_n + FLIGHT_ERROR V_n

with the velocity's own error relative to the flight's velocity scale ``V_n = max(|v_start|, |v_n|, F)``
(``F = alpha sqrt(1 + beta^2) + |gamma|``, the largest force).  **The graze rule**: where the acceleration
points away from the wall (the flight was turning back: a graze) the impact condition is quadratic, and
the root moves by ``2 e_n / (|v_n| + sqrt(v_n^2 - 2 |a_n| e_n))`` (between ``e_n / v_n`` and
``2 e_n / v_n``); a graze with ``v_n^2 < 2 |a_n| SAFETY e_n`` (its excursion beyond the wall within
``SAFETY e_n``) may be missed by a correct implementation: :attr:`RowErrors.fragile`.

**Representation** (float64 numbers an implementation necessarily rounds).  The phase an implementation
flies from is ``tau_n`` rounded (half an ulp of ``max(|tau_n|, 2 pi)``) and, where it reduces a large
``tau`` with the float64 ``2 pi``, off by ``k_n (2 pi - fl(2 pi))`` (``k_n`` whole turns): both are added to
the time error of the contact (and carried on by the Jacobians).  The ``tau`` column adds the rounding an
implementation accumulates when it sums the flight times into ``tau`` (half an ulp per row up to this one,
:data:`ACCUMULATED`) and ``k (2 pi - fl(2 pi))`` (``tau`` written as ``cycles 2 pi + theta``); the
``tau_mod_2pi`` column ``k (2 pi - fl(2 pi))`` and half an ulp of ``2 pi``; ``sdot`` half an ulp.

**Propagation.**  The analytic Jacobians of the impact map (Eqs. 12-13, :func:`mapimpl.impact_map.jacobian`)
carry the error of impact ``n`` to the later rows: at impact ``m`` it is ``|P_mn| l_n`` (componentwise
absolute values) with ``P_mn = J_m ... J_{n+1}`` and ``l_n = (dtau_n, dsdot_n)``.  The error of a row is the
**sum** over its sources, ``sum_n |P_mn| l_n``: the first-order bound of ``|sum_n P_mn eps_n|`` for any
per-contact errors ``|eps_n| <= l_n`` (the largest single source underestimates it by up to the number of
sources: a chatter, or a regular orbit whose tau errors add up).  Where an orbit has more than
:data:`MAX_SOURCES` sources, the smaller half of them (by what they give now) becomes one source whose ``l``
is their sum ``sum_k |P_mk| l_k`` and whose ``P`` starts again from the identity: ``|Q P| <= |Q| |P|``, so it
never gives less than they would.  The absolute value is taken once per such fold, not at every step: a
bound carried as ``|J| D`` step by step grows like the spectral radius of ``|J|``, which exceeds the true
growth wherever the Jacobians' signs cancel (on a stable orbit of 700 impacts it grew from 1e-10 to 1e-6
in 30 impacts).
A step that sticks forgets its input (the release leaves from the canonical phase, a function of the
parameters alone: ``J = 0``; the release row's own phase error, :func:`release_phase_error`, starts the
next sources); a stick row ``tau_n + t_acc`` has the sensitivity ``(1 + dt_acc/dtau, dt_acc/dsdot)`` to
impact ``n``.  A pre-impact initial state is exact but for its phase's representation.

**The tolerance of a row** (:func:`tolerances`): ``SAFETY`` times the row's error plus the golden value's own
printed radius, rounded up to :data:`TOLERANCE_DIGITS` significant digits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ....core import jax_config  # noqa: F401  (float64)
import jax
import jax.numpy as jnp

from ....core.params import Params
from ....mapimpl.flight import flight
from ....mapimpl.impact_map import jacobian

#: Rounding step of a float64 position of magnitude below 2 at a wall (2^-53 for ``s`` at ``s = -1`` and
#: for ``s + 1`` at ``s = 0``; 2^-52 beyond).
POSITION_STEP = 2.0**-52
#: Roundings of the position in the gap of a correct implementation (the coordinate's and the evaluation's).
GAP_ULPS = 2
#: Error of a flight solution relative to the flight's height (per forcing period), and of the velocity relative
#: to the flight's velocity scale (measured on our three tracks: benchmarks/results/per_contact_error_*.json).
FLIGHT_ERROR = 3e-14
#: Safety factor of the tolerances.
SAFETY = 10.0
#: Significant digits of a printed tolerance (rounded up: at most 10 % above SAFETY x the error).
TOLERANCE_DIGITS = 2
#: Samples of a flight for its height ``max |s(t) - s(0)|``.
HEIGHT_SAMPLES = 257
#: ``2 pi - fl(2 pi)``: the error of the float64 ``2 pi`` (a phase reduced by ``k`` turns is off by ``k`` times it).
TWO_PI_GAP = 2.4492935982947064e-16
TWO_PI = 2.0 * math.pi
#: Half an ulp per row: the rounding of ``tau = tau + dt`` accumulated over the rows (``tau`` column).
ACCUMULATED = 0.5
#: The most sources carried one by one: beyond, the smaller half becomes one source (module docstring).
MAX_SOURCES = 256
#: The columns whose values have a tolerance.
COLUMNS = ("tau", "tau_mod_2pi", "sdot")

_jacobian = jax.jit(jacobian)
_displacement = jax.jit(lambda t, th, v0, a, b, g: flight(t, th, v0, a, b, g).ds)


def round_up(x: float, digits: int = TOLERANCE_DIGITS) -> float:
    """``x >= 0`` rounded up to ``digits`` significant digits (the float64 of that decimal, never below ``x``;
    ``round_up(2.01e-14) = 2.1e-14``, ``round_up(2e-14) = 2e-14``); 0 stays 0."""
    if not x > 0:
        return 0.0
    if math.isinf(x):  # the row after a contact a correct implementation may miss (RowErrors.fragile)
        return x
    e = math.floor(math.log10(x)) - digits + 1
    m = math.ceil(x / 10.0**e * (1 - 1e-12))
    y = float(f"{m}e{e}")
    while y < x:
        m += 1
        y = float(f"{m}e{e}")
    return y


def round_up_1(x: float) -> float:
    """``x`` rounded up to one significant digit (:func:`round_up`)."""
    return round_up(x, 1)


def gap_error(h: float, dt: float) -> float:
    """``e = GAP_ULPS 2^-52 + FLIGHT_ERROR h max(1, dt / 2 pi)``: the gap error at the end of a flight of
    height ``h`` and duration ``dt``."""
    return GAP_ULPS * POSITION_STEP + FLIGHT_ERROR * h * max(1.0, dt / TWO_PI)


def flight_height(p: Params, theta0: float, v0: float, dt: float) -> float:
    """``h = max |s(t) - s(0)|`` over a flight of duration ``dt`` from phase ``theta0`` with velocity ``v0``
    (Eqs. 7-8 sampled at :data:`HEIGHT_SAMPLES` times), capped at 1 (the backlash)."""
    t = jnp.linspace(0.0, dt, HEIGHT_SAMPLES)
    return min(1.0, float(jnp.max(jnp.abs(_displacement(t, theta0, v0, p.alpha, p.beta, p.gamma)))))


def forcing(p: Params, tau: float) -> float:
    """``f(tau) = -alpha sin tau + alpha beta cos tau + gamma`` (Eq. 3)."""
    return -p.alpha * math.sin(tau) + p.alpha * p.beta * math.cos(tau) + p.gamma


def largest_force(p: Params) -> float:
    """``F = alpha sqrt(1 + beta^2) + |gamma|``: the largest ``|f|``."""
    return p.alpha * math.sqrt(1 + p.beta**2) + abs(p.gamma)


def contact_time_error(e: float, v: float, a: float, wall: int) -> float | None:
    """The time error of a contact of speed ``v`` and acceleration ``a`` on ``wall`` found with a gap error
    ``e``: ``e / |v|``, or at a graze (``a`` points away from the wall) the root shift of the quadratic
    ``|v| d - |a| d^2 / 2 = e``; ``None`` where that has no root (the contact may vanish)."""
    away = a < 0 if wall == 0 else a > 0
    if not away:
        return e / abs(v)
    disc = v * v - 2.0 * abs(a) * e
    return None if disc < 0 else 2.0 * e / (abs(v) + math.sqrt(disc))


def phase_representation(tau: float) -> float:
    """The phase error of ``tau`` as a float64 implementation holds it: half an ulp of ``max(|tau|, 2 pi)``,
    plus ``k (2 pi - fl(2 pi))`` for a reduction by ``k`` whole turns with the float64 ``2 pi``."""
    return 0.5 * math.ulp(max(abs(tau), TWO_PI)) + math.floor(abs(tau) / TWO_PI) * TWO_PI_GAP


def local_error(p: Params, e: float, tau: float, sdot: float, wall: int, v_start: float) -> np.ndarray | None:
    """``(dtau_n, dsdot_n)`` of a contact at ``tau`` on ``wall`` with pre-impact velocity ``sdot`` found with the
    gap error ``e`` (:func:`gap_error`) at the end of a flight from the velocity ``v_start`` (module docstring;
    the phase's representation included); ``None`` where a correct implementation may miss the contact (its
    excursion beyond the wall within ``SAFETY e``: :func:`contact_time_error`)."""
    a = forcing(p, tau) - p.beta * sdot
    robust, dt = contact_time_error(SAFETY * e, sdot, a, wall), contact_time_error(e, sdot, a, wall)
    if robust is None or dt is None:
        return None
    scale = max(abs(v_start), abs(sdot), largest_force(p))
    return np.array([dt + phase_representation(tau), abs(a) * dt + FLIGHT_ERROR * scale])


def stick_sensitivity(p: Params, tau: float, sdot: float, t_acc: float) -> np.ndarray:
    """``d(tau + t_acc) / d(tau, sdot)`` of a stick row, ``t_acc = 2 r |sdot| / ((1 - r) f_in(tau))`` (signed: the
    row's error is ``|sens^T P| l`` over the sources)."""
    f = forcing(p, tau)
    df = -p.alpha * math.cos(tau) - p.alpha * p.beta * math.sin(tau)
    return np.array([1.0 - t_acc * df / f, t_acc / sdot])


def release_phase_error(p: Params) -> float:
    """The error of a float64 canonical release phase ``atan(beta) + asin(gamma / R)`` (or its lower wall
    branch): a few ulps of ``2 pi``, and the conditioning of ``asin`` at ``c = gamma / R``."""
    c = min(1.0, abs(p.gamma) / (p.alpha * math.sqrt(1 + p.beta**2))) if p.alpha > 0 else 1.0
    cond = 2.0 * POSITION_STEP * c / math.sqrt(1 - c * c) if c < 1 else math.inf
    return 4 * math.ulp(TWO_PI) + cond


@dataclass(frozen=True)
class RowErrors:
    """The error bound of a correct float64 implementation at each row of a case (columns ``tau``,
    ``tau_mod_2pi``, ``sdot``; NaN where a row has no such value), the impact whose error contributes most
    to each row's ``tau`` (``-1``: the row's own representation), and ``fragile``: the index of the first row
    whose contact a correct implementation may miss (``None``: none)."""

    tau: np.ndarray
    tau_mod_2pi: np.ndarray
    sdot: np.ndarray
    source: np.ndarray
    fragile: int | None = None

    def column(self, c: str) -> np.ndarray:
        return getattr(self, c)


class _Sources:
    """The errors carried along the orbit: each source's ``P`` (2x2) and ``l`` (2), at most
    :data:`MAX_SOURCES` of them (module docstring)."""

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        """No source (after a release: the orbit has forgotten its past)."""
        self.P = np.zeros((0, 2, 2))
        self.L = np.zeros((0, 2))
        self.n = np.zeros(0, dtype=np.int64)

    def step(self, jac: np.ndarray) -> None:
        self.P = np.einsum("ij,kjl->kil", jac, self.P)

    def add(self, n: int, loc: np.ndarray) -> None:
        self.P = np.concatenate([self.P, np.eye(2)[None]])
        self.L = np.concatenate([self.L, loc[None]])
        self.n = np.concatenate([self.n, [n]])

    def error(self, row: np.ndarray | None = None) -> tuple[np.ndarray, int]:
        """``(sum |P| l, the largest source's impact)`` (``row``: a linear functional, a stick row's
        sensitivity); beyond :data:`MAX_SOURCES` sources, folds the smaller half into one."""
        P = self.P if row is None else np.einsum("i,kij->kj", row, self.P)[:, None, :]
        parts = np.einsum("kij,kj->ki", np.abs(P), self.L)
        total = parts.sum(axis=0)
        who = int(self.n[int(np.argmax(parts[:, 0]))]) if len(self.n) else -1
        if row is None and len(self.n) > MAX_SOURCES:
            share = (parts / np.where(total > 0, total, 1.0)).max(axis=1)
            fold = np.zeros(len(self.n), dtype=bool)
            fold[np.argsort(share, kind="stable")[: len(self.n) // 2]] = True
            last = int(self.n[fold].max())
            keep = ~fold
            self.P = np.concatenate([self.P[keep], np.eye(2)[None]])
            self.L = np.concatenate([self.L[keep], parts[fold].sum(axis=0)[None]])
            self.n = np.concatenate([self.n[keep], [last]])
        return total, who


def row_errors(p: Params, seq, free_start: tuple[float, float, float] | None = None) -> RowErrors:
    """The :class:`RowErrors` of a case's rows ``seq`` (columns ``n, tau, tau_mod_2pi, wall, sdot, kind`` as
    arrays: a :class:`..formats.cases.Sequence`); ``free_start = (tau0, s0, sdot0)`` for a free-flight start (its
    impact 0 is reached by a flight), ``None`` for a pre-impact initial state (exact)."""
    rows = len(seq.kind)
    out = {c: np.full(rows, math.nan) for c in COLUMNS}
    source = np.full(rows, -1, dtype=np.int64)
    src, acc = _Sources(), 0.0
    fragile: int | None = None
    prev: int | None = None  # the previous impact row
    start: tuple[float, float, float] | None = None  # the flight to the next impact (theta0, v0, tau0)
    if free_start is not None:
        start = (free_start[0] % TWO_PI, free_start[2], free_start[0])
    for i, kind in enumerate(seq.kind):
        tau, sdot = float(seq.tau[i]), float(seq.sdot[i])
        rep = math.floor(abs(tau) / TWO_PI) * TWO_PI_GAP
        acc += ACCUMULATED * math.ulp(max(abs(tau), TWO_PI))
        if kind == "stick":
            assert prev is not None, "a stick row follows its impact"
            j = prev
            sens = stick_sensitivity(p, float(seq.tau[j]), float(seq.sdot[j]), tau - float(seq.tau[j]))
            err, source[i] = src.error(sens)
            prop = float(err[0]) + 4 * POSITION_STEP * (tau - float(seq.tau[j]))
        elif kind == "release":
            src.reset()
            prop = release_phase_error(p)
            src.add(int(seq.n[i]), np.array([prop + phase_representation(tau), 0.0]))
            start = (float(seq.tau_mod_2pi[i]), 0.0, tau)
        else:
            if start is None and prev is not None:  # a free step from the previous impact (Eq. 11, then Eqs. 7-8)
                j = prev
                th0, v0, t0 = float(seq.tau_mod_2pi[j]), -p.r * float(seq.sdot[j]), float(seq.tau[j])
                src.step(
                    np.asarray(
                        _jacobian(th0, v0, tau - t0, float(seq.tau_mod_2pi[i]), sdot, (p.alpha, p.beta, p.gamma, p.r))
                    )
                )
                start = (th0, v0, t0)
            elif start is not None and prev is not None:  # the flight from a release: J (its phase error) as well
                src.step(
                    np.asarray(
                        _jacobian(
                            start[0],
                            0.0,
                            tau - start[2],
                            float(seq.tau_mod_2pi[i]),
                            sdot,
                            (p.alpha, p.beta, p.gamma, p.r),
                        )
                    )
                )
            if start is None:  # a pre-impact initial state: exact but for its phase
                loc = np.array([phase_representation(tau), 0.0])
            else:
                dt = tau - start[2]
                e = gap_error(flight_height(p, start[0], start[1], dt), dt)
                contact = local_error(p, e, tau, sdot, int(seq.wall[i]), start[1])
                if contact is None:
                    fragile = i if fragile is None else fragile
                loc = np.array([math.inf, math.inf]) if contact is None else contact
            src.add(int(seq.n[i]), loc)
            err, source[i] = src.error()
            prop = float(err[0])
            out["sdot"][i] = float(err[1]) + 0.5 * math.ulp(sdot)
            prev, start = i, None
        out["tau"][i] = prop + acc + rep
        out["tau_mod_2pi"][i] = prop + rep + 0.5 * math.ulp(TWO_PI)
    return RowErrors(out["tau"], out["tau_mod_2pi"], out["sdot"], source, fragile)


def tolerances(errors: RowErrors, radii: dict[str, np.ndarray] | None = None) -> dict[str, np.ndarray]:
    """The absolute tolerance of every row and column: ``SAFETY`` times the row's error plus the golden
    value's printed radius (``radii``: per column, NaN or absent read as 0), rounded up to
    :data:`TOLERANCE_DIGITS` digits; NaN where the row has no value (``sdot`` of a stick or release row)."""
    out = {}
    for c in COLUMNS:
        err = errors.column(c)
        rad = np.zeros(err.shape) if radii is None else np.nan_to_num(np.asarray(radii[c], dtype=float))
        out[c] = np.array([math.nan if math.isnan(x) else round_up(SAFETY * x + r) for x, r in zip(err, rad)])
    return out


__all__ = [
    "POSITION_STEP",
    "GAP_ULPS",
    "FLIGHT_ERROR",
    "SAFETY",
    "TOLERANCE_DIGITS",
    "TWO_PI_GAP",
    "RowErrors",
    "row_errors",
    "tolerances",
    "local_error",
    "gap_error",
    "contact_time_error",
    "phase_representation",
    "release_phase_error",
    "flight_height",
    "stick_sensitivity",
    "round_up",
    "round_up_1",
]
