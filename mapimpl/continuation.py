"""Periodic orbits of the impact map: Floquet multipliers, pseudo-arclength continuation in ``r`` or
``alpha``, and fold (multiplier +1) / flip (multiplier -1) points by Newton on the extended system.

"Period-m with p impacts" means that p map steps (Eqs. 12-13) advance the time by exactly
``2 pi m`` and return the velocity.  The orbit is a zero of

    G(tau, sdot; mu) = (tau_p - tau - 2 pi m,  sdot_p - sdot),

with ``(tau_p, sdot_p)`` the p-fold map (:func:`mapimpl.periodic.pfold`, which also gives the exact
Jacobian ``M = DF^p`` as the product of the analytic step Jacobians).  The Floquet multipliers are the
eigenvalues of ``M``; their product is ``prod_n r^2 exp(-beta dt_n) sdot_n / sdot_{n+1}``
= ``r^(2p) exp(-2 pi m beta)`` on a periodic orbit (the velocities telescope), which
:func:`closed_form_det` returns as an independent check.

Continuation (``mu`` = ``r`` or ``alpha``): unknowns ``y = (tau, sdot, mu)``; the 2x3 Jacobian
``[M - I | dG/dmu]`` (``dG/dmu`` by forward-mode autodiff of the p-fold map, central differences as
the fallback) gives the tangent (its null
vector); predictor ``y + h t``, corrector Newton on ``(G(y), t . (y - y_pred)) = 0``.

Bifurcation points: a fold of the branch has ``det(M - I) = 0`` (a multiplier +1), a flip has
``det(M + I) = 0`` (a multiplier -1).  Both are located by Newton on the 3x3 extended system
``(G, det(M -/+ I)) = 0`` in ``(tau, sdot, mu)``, with the analytic ``M`` in the residual and the
3x3 Jacobian by forward-mode autodiff (``jax.jacfwd``, float64) of the same system written in
``jax.numpy`` (``_extended_residual``: the p-fold map, its step Jacobians and the 2x2 determinant,
differentiated through the impact finder's loops).  The Jacobian affects only the convergence rate, not
the root; forward differences remain as the fallback where the autodiff Jacobian is not finite.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from ..core.phase import TWO_PI
from .impact_map import step
from ..core.state import make_state
from ..core.params import ParamArrays, Params, check_value
from ..core.checks import MAX_PERIOD, check_int
from ..core.deprecation import renamed_attribute
from .periodic import find_periodic, pfold
from .newton import newton

#: Parameters that can be continued.
CONTINUATION_PARAMS = ("r", "alpha")
_TWO_PI = float(TWO_PI)


def _check_mu_name(name: str) -> str:
    if name not in CONTINUATION_PARAMS:
        raise ValueError(f"continuation parameter {name!r} is out of range: allowed one of {CONTINUATION_PARAMS}")
    return name


def _check_counts(impacts: int, turns: int) -> tuple[int, int]:
    return check_int("impacts", impacts, 1, MAX_PERIOD), check_int("turns", turns, 1, MAX_PERIOD)


#: Position of each continued parameter in :class:`ParamArrays`.
_MU_INDEX = {"alpha": 0, "r": 3}


def _arrays(params: Params, name: str, mu: float) -> ParamArrays:
    d = {**params.as_dict(), name: mu}
    return ParamArrays(*(jnp.asarray(v, jnp.float64) for v in d.values()))


def closed_form_det(params: Params, impacts: int, turns: int = 1) -> float:
    """Product of the Floquet multipliers from the closed-form step determinants:
    ``r^(2 p) exp(-2 pi m beta)`` for a p-impact, m-turn periodic orbit without sticking."""
    impacts, turns = _check_counts(impacts, turns)
    return float(params.r ** (2 * impacts) * np.exp(-_TWO_PI * turns * params.beta))


class OrbitResidual:
    """The periodic-orbit residual for one base parameter set, one continued parameter, p, m."""

    def __init__(self, params: Params, name: str, impacts: int, turns: int, wall: int):
        self.params, self.name = params, _check_mu_name(name)
        self.impacts, self.turns = _check_counts(impacts, turns)
        self.wall = int(wall)
        self.nfev = 0

    def eval(self, y):
        """``(G, M, ok)`` at ``y = (tau, sdot, mu)``."""
        tau, sdot, mu = float(y[0]), float(y[1]), float(y[2])
        if not np.isfinite(mu) or (self.name == "r" and not 0.0 < mu <= 1.0) or (self.name == "alpha" and mu < 0):
            return np.full(2, np.nan), np.full((2, 2), np.nan), False
        self.nfev += 1
        tp, sp, J, _walls, stuck, ok = pfold(tau, sdot, _arrays(self.params, self.name, mu), self.impacts, self.wall)
        good = bool(ok) and not bool(stuck) and np.sign(sdot) == (1.0 if self.wall == 0 else -1.0)
        G = np.array([float(tp) - tau - _TWO_PI * self.turns, float(sp) - sdot])
        return G, np.asarray(J, dtype=np.float64), good

    def dG_dmu(self, y, G0=None):
        """``dG/dmu`` at ``y``: forward-mode autodiff of the p-fold map (``_extended_jacobian``, the
        Jacobian :func:`locate` compiles for the same number of impacts), central differences where it
        is not finite or the step is not valid (one-sided at ``r = 1``)."""
        base = np.array([self.params.alpha, self.params.beta, self.params.gamma, self.params.r], dtype=np.float64)
        Jm, ok = _extended_jacobian(
            jnp.asarray(y, jnp.float64), base, _MU_INDEX[self.name], float(self.turns), self.wall, -1.0, self.impacts
        )
        col = np.asarray(Jm, dtype=np.float64)[:2, 2]
        if bool(ok) and np.all(np.isfinite(col)):
            return col
        return self._dG_dmu_fd(y, G0)

    def _dG_dmu_fd(self, y, G0=None):
        h = 1e-7 * max(1.0, abs(y[2]))
        if self.name == "r" and y[2] + h > 1.0:
            Gm, _, okm = self.eval(y - np.array([0, 0, h]))
            return (G0 - Gm) / h if G0 is not None else None
        Gp, _, okp = self.eval(y + np.array([0, 0, h]))
        Gm, _, okm = self.eval(y - np.array([0, 0, h]))
        return (Gp - Gm) / (2 * h)

    def test_fn(self, y, kind: str):
        G, M, ok = self.eval(y)
        sign = -1.0 if kind == "fold" else 1.0
        return G, float(np.linalg.det(M + sign * np.eye(2))), ok


@dataclass
class OrbitPoint:
    """One point of a branch: the pre-impact state ``(theta, sdot)`` (the phase ``theta = tau mod 2 pi``),
    the parameter value ``mu`` and the Floquet multipliers.  The old name ``tau`` of ``theta`` still
    works, with a DeprecationWarning (:func:`~gear_rattle.core.deprecation.renamed_attribute`)."""

    theta: float
    sdot: float
    mu: float
    multipliers: np.ndarray
    residual: float

    tau = renamed_attribute("tau", "theta")

    @property
    def stable(self) -> bool:
        return bool(np.all(np.abs(self.multipliers) < 1.0))


@dataclass
class BifurcationPoint:
    """A fold (``kind = "fold"``, a multiplier +1) or flip (``"flip"``, a multiplier -1) point: the
    parameter value ``mu``, the pre-impact state ``(theta, sdot)`` of the orbit there (the phase
    ``theta = tau mod 2 pi``) and its multipliers.  The old name ``tau`` of ``theta`` still works, with a
    DeprecationWarning."""

    kind: str
    mu: float
    theta: float
    sdot: float
    multipliers: np.ndarray
    residual: float
    converged: bool
    iterations: int
    param: str = "r"

    tau = renamed_attribute("tau", "theta")

    def describe(self) -> str:
        m = ", ".join(
            f"{complex(z).real:+.10f}" if abs(complex(z).imag) < 1e-12 else f"{complex(z):.6f}"
            for z in self.multipliers
        )
        return (
            f"{self.kind} at {self.param} = {self.mu:.12f} (theta = {self.theta:.10f}, sdot = {self.sdot:.10f}; "
            f"multipliers {m}; residual {self.residual:.1e}, {'converged' if self.converged else 'NOT converged'})"
        )


@dataclass
class Branch:
    """A continued branch of p-impact, m-turn periodic orbits and the bifurcation points found on it."""

    params: Params
    param: str
    impacts: int
    turns: int
    points: list[OrbitPoint] = field(default_factory=list)
    folds: list[BifurcationPoint] = field(default_factory=list)
    flips: list[BifurcationPoint] = field(default_factory=list)
    stop_reason: str = ""

    def arrays(self) -> dict[str, np.ndarray]:
        """The branch as arrays: ``mu``, ``tau`` (the phases ``theta`` of the points: the key is the file
        format's, kept), ``sdot``, ``mult_re``/``mult_im`` (n, 2), ``stable``."""
        mult = np.array([np.sort_complex(np.asarray(p.multipliers, complex)) for p in self.points]).reshape(-1, 2)
        return {
            "mu": np.array([p.mu for p in self.points]),
            "tau": np.array([p.theta for p in self.points]),
            "sdot": np.array([p.sdot for p in self.points]),
            "mult_re": mult.real,
            "mult_im": mult.imag,
            "stable": np.array([p.stable for p in self.points]),
        }

    def table(self) -> tuple[list, list]:
        """``(header, rows)``: one row per point (parameter, the phase theta in the column ``tau``, sdot, the
        two multipliers, stable)."""
        a = self.arrays()
        return [self.param, "tau", "sdot", "mult1_re", "mult1_im", "mult2_re", "mult2_im", "stable"], [
            [
                float(a["mu"][i]),
                float(a["tau"][i]),
                float(a["sdot"][i]),
                float(a["mult_re"][i, 0]),
                float(a["mult_im"][i, 0]),
                float(a["mult_re"][i, 1]),
                float(a["mult_im"][i, 1]),
                bool(a["stable"][i]),
            ]
            for i in range(a["mu"].size)
        ]


#: Newton steps taken by :func:`locate` after the tolerance is met, each kept only if it lowers the residual: the
#: result does not depend on how far inside the tolerance the last regular step happened to land.
POLISH_STEPS = 2


def _extended_residual(y, base, mu_index, turns, wall, sign, impacts):
    """The extended system of :func:`locate` in ``jax.numpy``: ``(G, det(M + sign I))`` at
    ``y = (tau, sdot, mu)``, with ``mu`` at position ``mu_index`` of ``base = (alpha, beta, gamma, r)``;
    aux output: the p-fold map is valid (active, no sticking).  Used for its Jacobian only: the residual
    of :func:`locate` stays the NumPy one of :meth:`OrbitResidual.test_fn` (the two agree to rounding)."""
    tau, sdot, mu = y[0], y[1], y[2]
    pa = ParamArrays(*jnp.asarray(base, jnp.float64).at[mu_index].set(mu))
    tp, sp, M, _walls, stuck, ok = pfold(tau, sdot, pa, impacts, wall)
    A = M + sign * jnp.eye(2)
    F = jnp.stack([tp - tau - _TWO_PI * turns, sp - sdot, A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]])
    return F, ok & ~stuck


#: ``d F / d y`` of ``_extended_residual`` (forward mode, float64); compiled once per number of impacts.
_extended_jacobian = jax.jit(jax.jacfwd(_extended_residual, has_aux=True), static_argnums=(6,))


def locate(
    params: Params,
    param: str,
    kind: str,
    tau: float,
    sdot: float,
    mu: float,
    impacts: int,
    turns: int = 1,
    tol: float = 1e-11,
    max_iter: int = 40,
) -> BifurcationPoint:
    """Newton on the extended system ``(G, det(M - I)) = 0`` (``kind="fold"``) or ``(G, det(M + I)) = 0``
    (``kind="flip"``) from a guess ``(tau, sdot, mu)`` near the bifurcation point.  The Jacobian is
    ``jax.jacfwd`` of ``_extended_residual`` (forward differences where it is not finite); the
    first call for a number of impacts compiles it (measured: 15-19 s of CPU for p = 6, against
    ~2 ms per Jacobian afterwards)."""
    if kind not in ("fold", "flip"):
        raise ValueError(f"kind={kind!r} is out of range: allowed 'fold' or 'flip'")
    prob = OrbitResidual(params, param, impacts, turns, 0 if sdot > 0 else -1)

    def fun(y):
        G, d, ok = prob.test_fn(y, kind)
        return np.array([G[0], G[1], d]) if ok else None

    base = np.array([params.alpha, params.beta, params.gamma, params.r], dtype=np.float64)
    sign = -1.0 if kind == "fold" else 1.0

    def jac(y):
        Jm, ok = _extended_jacobian(
            jnp.asarray(y, jnp.float64), base, _MU_INDEX[prob.name], float(prob.turns), prob.wall, sign, prob.impacts
        )
        Jm = np.asarray(Jm, dtype=np.float64)
        return Jm if bool(ok) and np.all(np.isfinite(Jm)) else None

    y, res, it, conv = newton(fun, [tau, sdot, mu], max_iter=max_iter, tol=tol, polish_steps=POLISH_STEPS, jac=jac)
    _, M, _ = prob.eval(y)
    return BifurcationPoint(
        kind, float(y[2]), float(y[0] % _TWO_PI), float(y[1]), np.linalg.eigvals(M), res, bool(conv), it, param
    )


def _tangent(A: np.ndarray, prev: np.ndarray | None) -> np.ndarray:
    # null vector of the 2x3 matrix A (last right-singular vector)
    _, _, vt = np.linalg.svd(A)
    t = vt[-1]
    if prev is not None and float(t @ prev) < 0:
        t = -t
    return t / np.linalg.norm(t)


def _check_continuation(
    params: Params,
    name: str,
    direction: int,
    ds: float,
    ds_max: float,
    max_points: int,
    mu_range: tuple[float, float] | None,
) -> tuple[float, float]:
    """Check the arguments of :func:`continue_orbit`; returns the bounds ``(lo, hi)`` of the continued
    parameter (``mu_range``, or the whole line)."""
    if direction not in (1, -1):
        raise ValueError(f"direction={direction!r} is out of range: allowed +1 or -1")
    if not (np.isfinite(ds) and 0 < ds <= ds_max):
        raise ValueError(f"ds={ds!r} is out of range: allowed 0 < ds <= ds_max={ds_max!r}")
    if int(max_points) < 2:
        raise ValueError(f"max_points={max_points!r} is out of range: allowed max_points >= 2")
    if mu_range is None:
        return -np.inf, np.inf
    mu0 = getattr(params, name)
    lo, hi = (check_value(name, v) for v in mu_range)
    if not lo < hi:
        raise ValueError(f"mu_range={mu_range!r} is out of range: allowed lo < hi")
    if not lo <= mu0 <= hi:
        raise ValueError(f"{name}={mu0!r} is out of range: allowed inside mu_range={mu_range!r}")
    return lo, hi


def _correct(prob: OrbitResidual, y: np.ndarray, yp: np.ndarray, t: np.ndarray, h: float) -> np.ndarray | None:
    """The corrector of :func:`continue_orbit`: Newton on ``(G(z), t . (z - yp)) = 0`` from the predicted
    point ``yp`` (at most 12 steps); the new point ``z``, or None where it does not converge or lands
    farther than ``3 h`` from the last point ``y``."""
    z = yp.copy()
    conv = False
    for _ in range(12):
        G, M, ok = prob.eval(z)
        if not ok:
            break
        F = np.array([G[0], G[1], float(t @ (z - yp))])
        if np.max(np.abs(F)) < 1e-11:
            conv = True
            break
        dG = prob.dG_dmu(z, G)
        Jx = np.vstack([np.hstack([M - np.eye(2), dG[:, None]]), t[None, :]])
        try:
            z = z - np.linalg.solve(Jx, F)
        except np.linalg.LinAlgError:
            break
    if not conv or np.linalg.norm(z - y) > 3 * h:
        return None
    return z


def _locate_crossings(br: Branch, prev: OrbitPoint, cur: OrbitPoint, y: np.ndarray) -> None:
    """Locate (:func:`locate`) a fold where ``prod(multipliers - 1)`` and a flip where
    ``prod(multipliers + 1)`` changes sign between the branch points ``prev`` and ``cur`` (at ``y``), and
    add them to ``br``."""
    f0 = np.real(np.prod(prev.multipliers - 1.0))
    f1 = np.real(np.prod(cur.multipliers - 1.0))
    if np.sign(f0) != np.sign(f1):
        br.folds.append(locate(br.params, br.param, "fold", y[0], y[1], y[2], br.impacts, br.turns))
    g0 = np.real(np.prod(prev.multipliers + 1.0))
    g1 = np.real(np.prod(cur.multipliers + 1.0))
    if np.sign(g0) != np.sign(g1):
        br.flips.append(locate(br.params, br.param, "flip", y[0], y[1], y[2], br.impacts, br.turns))


def _range_stop(name: str, mu: float, lo: float, hi: float) -> str:
    """Why the branch stops at ``mu``: it left ``[lo, hi]`` or ``r`` reached 1; "" where it goes on."""
    if not (lo <= mu <= hi):
        return f"{name} left [{lo}, {hi}]"
    if name == "r" and mu >= 1.0:
        return "r reached 1"
    return ""


def continue_orbit(
    params: Params,
    param: str,
    tau0: float,
    sdot0: float,
    impacts: int,
    turns: int = 1,
    mu_range: tuple[float, float] | None = None,
    direction: int = 1,
    ds: float = 2e-3,
    ds_max: float = 2e-2,
    max_points: int = 400,
    locate_points: bool = True,
    progress=None,
) -> Branch:
    """Pseudo-arclength continuation of a p-impact, m-turn periodic orbit in ``param`` (``"r"`` or
    ``"alpha"``) starting from the orbit through the guess ``(tau0, sdot0)`` at ``params``.

    ``direction`` (+1/-1) is the initial sense of ``param``; the branch may turn at folds.  Stops after
    ``max_points`` points, when ``param`` leaves ``mu_range = (lo, hi)``, or when the
    corrector fails at the smallest step.  Folds and flips met on the way are located with
    :func:`locate` when ``locate_points``.
    """
    name = _check_mu_name(param)
    impacts, turns = _check_counts(impacts, turns)
    lo, hi = _check_continuation(params, name, direction, ds, ds_max, max_points, mu_range)
    mu0 = getattr(params, name)
    orb = find_periodic(params, tau0, sdot0, impacts, turns)
    if not orb.converged:
        raise ValueError(
            f"no {impacts}-impact, {turns}-turn periodic orbit found from the guess "
            f"(tau0={tau0!r}, sdot0={sdot0!r}) at {name}={mu0!r}"
        )
    x0 = (float(orb.theta[0]), float(orb.sdot[0]))
    prob = OrbitResidual(params, name, impacts, turns, int(orb.walls[0]))
    br = Branch(params, name, impacts, turns)
    y = np.array([x0[0], x0[1], mu0])

    def record(y, M, res):
        br.points.append(OrbitPoint(float(y[0] % _TWO_PI), float(y[1]), float(y[2]), np.linalg.eigvals(M), res))

    G, M, ok = prob.eval(y)
    record(y, M, float(np.max(np.abs(G))))
    A = np.hstack([M - np.eye(2), prob.dG_dmu(y, G)[:, None]])
    t = _tangent(A, None)
    if np.sign(t[2]) != direction and abs(t[2]) > 1e-12:
        t = -t
    h = ds
    fails = 0
    while len(br.points) < max_points:
        z = _correct(prob, y, y + h * t, t, h)
        if z is None:
            h *= 0.5
            fails += 1
            if h < 1e-9:
                br.stop_reason = "corrector failed at the smallest step"
                break
            continue
        G, M, _ = prob.eval(z)
        A = np.hstack([M - np.eye(2), prob.dG_dmu(z, G)[:, None]])
        t_new = _tangent(A, t)
        prev = br.points[-1]
        y = z
        record(y, M, float(np.max(np.abs(G))))
        if locate_points:
            _locate_crossings(br, prev, br.points[-1], y)
        t = t_new
        if progress is not None:
            progress(len(br.points), max_points)
        br.stop_reason = _range_stop(name, y[2], lo, hi)
        if br.stop_reason:
            break
        h = min(ds_max, h * 1.3)
    else:
        br.stop_reason = "max_points reached"
    return br


def orbit_states(params: Params, tau: float, sdot: float, impacts: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``impacts`` pre-impact states ``(theta, sdot)`` of the orbit through ``(tau, sdot)``."""
    p = params.arrays()
    s = make_state(tau, sdot)
    th, sd = [float(s.theta)], [float(s.sdot)]
    for _ in range(int(impacts) - 1):
        s, _ = step(s, p)
        th.append(float(s.theta))
        sd.append(float(s.sdot))
    return np.array(th), np.array(sd)


__all__ = [
    "CONTINUATION_PARAMS",
    "closed_form_det",
    "OrbitResidual",
    "OrbitPoint",
    "BifurcationPoint",
    "Branch",
    "POLISH_STEPS",
    "locate",
    "continue_orbit",
    "orbit_states",
]
