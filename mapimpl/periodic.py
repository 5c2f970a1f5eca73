"""Periodic orbits of the impact map: "period-m with p impacts" means p map steps advance time by
exactly ``2 pi m`` and return the velocity (Section 3 of the paper: the 6-impact period-1 orbit of
Fig. 4 and the 4-impact period-1 orbit of Fig. 8).

Newton's method on ``G(tau, sdot) = (tau_p - tau - 2 pi m, sdot_p - sdot)`` with the exact Jacobian
``DF^p - I`` (product of the analytic step Jacobians of :mod:`mapimpl.impact_map`).  The Floquet
multipliers are the eigenvalues of ``DF^p``; their product equals the product of the closed-form
determinants ``r^2 exp(-beta dt) sdot_n / sdot_{n+1}`` over the orbit.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np

from ..core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from ..core.phase import TWO_PI
from ..core.checks import MAX_ITER, MAX_PERIOD, InputTypeError, check_int, check_start, check_tol
from ..core.deprecation import UNSET, renamed_argument, renamed_attribute
from ..core.outcome import Outcome, check_lengths, check_status
from ..core.status import Status
from .impact_map import step
from ..core.state import make_state
from ..core.params import ParamArrays, Params


@partial(jax.jit, static_argnums=(3,))
def pfold(tau, sdot, p: ParamArrays, n_steps: int, wall=None):
    """Apply the map ``n_steps`` times from the pre-impact state ``(tau, sdot)``.

    Returns ``(tau_p, sdot_p, J, walls, stuck_any, ok)`` with ``J`` the product of step Jacobians
    (``d(tau_p, sdot_p)/d(tau, sdot)``) and ``walls`` the walls hit (length ``n_steps``).
    """
    s = make_state(tau, sdot, wall)

    def body(c, _):
        st, J = c
        st1, info = step(st, p)
        return (st1, info.jac @ J), (st1.wall, info.stuck)

    (sp, J), (walls, stuck) = jax.lax.scan(body, (s, jnp.eye(2)), None, length=n_steps)
    return sp.tau, sp.sdot, J, walls, jnp.any(stuck), sp.status == Status.ACTIVE


_step = jax.jit(step)


@dataclass
class PeriodicOrbit(Outcome):
    """A periodic orbit found by :func:`find_periodic`.

    ``period``: impacts per period; ``turns``: driving periods per period; ``theta``/``sdot``: the
    ``period`` pre-impact states (the phase ``theta = tau mod 2 pi``); ``walls``: walls hit;
    ``multipliers``: Floquet multipliers (eigenvalues of DF^p); ``residual``: max-norm of G;
    ``status``: ``"converged"`` when Newton reached ``tol``, else ``"not_converged"``, with ``ok`` and
    ``message`` (:class:`~gear_rattle.core.outcome.Outcome`).  The old names ``impacts`` and ``tau`` still
    work, with a DeprecationWarning.
    """

    params: Params
    period: int
    turns: int
    theta: np.ndarray
    sdot: np.ndarray
    walls: np.ndarray
    multipliers: np.ndarray
    monodromy: np.ndarray
    residual: float
    status: str
    iterations: int

    impacts = renamed_attribute("impacts", "period")
    tau = renamed_attribute("tau", "theta")

    def __post_init__(self) -> None:
        """Refuse a status other than ``converged`` / ``not_converged`` and points that are not ``period``
        of each (``ValueError`` naming them): such an orbit would say ``ok`` about nothing."""
        check_status(self.status, (Status.CONVERGED, Status.NOT_CONVERGED))
        check_int("period", self.period, 1, MAX_PERIOD, strict=True)
        check_lengths(
            "theta, sdot and walls of a PeriodicOrbit",
            int(self.period),
            theta=self.theta,
            sdot=self.sdot,
            walls=self.walls,
        )

    @property
    def converged(self) -> bool:
        """Newton converged to ``tol`` (the same as ``ok``)."""
        return self.status == Status.CONVERGED.label

    @property
    def stable(self) -> bool:
        """All Floquet multipliers inside the unit circle."""
        return bool(np.all(np.abs(self.multipliers) < 1.0))

    def table(self) -> tuple[list[str], list[list]]:
        """``(header, rows)``: the p points of the orbit, ``k, tau_mod_2pi, sdot, wall`` (a CSV file)."""
        return ["k", "tau_mod_2pi", "sdot", "wall"], [
            [k, float(t), float(s), int(w)] for k, (t, s, w) in enumerate(zip(self.theta, self.sdot, self.walls))
        ]

    def arrays(self) -> dict:
        """The orbit's arrays and numbers (an NPZ file): points, multipliers (complex), monodromy matrix,
        Newton's residual, iterations and convergence, p, m and the parameters."""
        p = self.params
        return dict(
            tau_mod_2pi=self.theta,
            sdot=self.sdot,
            wall=self.walls,
            multipliers=self.multipliers,
            monodromy=self.monodromy,
            residual=self.residual,
            converged=self.converged,
            iterations=self.iterations,
            stable=self.stable,
            impacts=self.period,
            turns=self.turns,
            **p.as_dict(),
        )

    def as_dict(self) -> dict:
        """The orbit as JSON data: :meth:`arrays` with the multipliers as ``[real, imag]`` pairs and the
        points as rows."""
        d = {k: v for k, v in self.arrays().items() if k not in ("tau_mod_2pi", "sdot", "wall", "multipliers")}
        d["points"] = [dict(zip(self.table()[0], row)) for row in self.table()[1]]
        d["multipliers"] = [[float(np.real(m)), float(np.imag(m))] for m in self.multipliers]
        return d


#: Loosest Newton tolerance of :func:`find_periodic`: above it the "orbit" would be the guess.
MAX_TOL = 1e-6


def check_newton(period, turns, tol, max_iter):
    """The shape and the solver settings of :func:`find_periodic`, checked (:mod:`core.checks`):
    ``1 <= period, turns <= MAX_PERIOD``, ``TOL_FLOOR <= tol <= MAX_TOL`` (1e-15 .. 1e-6),
    ``1 <= max_iter <= MAX_ITER`` (1e4)."""
    return (
        check_int("period", period, 1, MAX_PERIOD),
        check_int("turns", turns, 1, MAX_PERIOD),
        check_tol("tol", tol, MAX_TOL),
        check_int("max_iter", max_iter, 1, MAX_ITER),
    )


def find_periodic(
    params: Params,
    tau0: float,
    sdot0: float,
    period=UNSET,
    turns: int = 1,
    tol: float = 1e-12,
    max_iter: int = 60,
    *,
    impacts=UNSET,
) -> PeriodicOrbit:
    """Newton search for an orbit with ``period`` impacts per ``turns`` driving periods.

    Solves ``G(tau, sdot) = F^p(tau, sdot) - (tau + 2 pi turns, sdot) = 0`` for the p-fold impact map
    ``F^p`` (Eqs. 12-13) with its analytic Jacobian; the Floquet multipliers are the eigenvalues of the
    monodromy matrix ``DF^p`` at the solution.

    Parameters
    ----------
    params : Params
        The model's parameters.
    tau0, sdot0 : float
        A guess of one pre-impact state (e.g. the end of a long run on the attractor).
    period : int
        Impacts per period, ``1 <= period <= 100000``.
    turns : int, optional
        Driving periods (``2 pi``) per period, ``1 <= turns <= 100000``.
    tol : float, optional
        Newton's tolerance on the max-norm of ``G``, ``1e-15 <= tol <= 1e-6``.
    max_iter : int, optional
        Most Newton iterations, ``1 <= max_iter <= 10000``.
    impacts : int, optional
        The old name of ``period`` (a DeprecationWarning).

    Returns
    -------
    PeriodicOrbit
        The states, walls, multipliers, monodromy matrix, residual and whether Newton converged
        (``ok``, ``status``, ``message``).

    Raises
    ------
    ValueError
        For an argument out of range (``period``, ``turns`` up to 1e5, ``tol``, ``max_iter``, a guess
        that is not finite, ``sdot0 = 0``), naming it; ``TypeError`` for one of the wrong type.

    Examples
    --------
    Fig. 2 (alpha = 0.5, r = 0.9): a stable orbit with one impact on the lower wall and two on the
    upper per driving period, from a 4-digit guess:

    >>> import gear_rattle as gr
    >>> orb = gr.find_periodic(gr.Params(0.5, 0.1, 0.1, 0.9), 2.034, -0.7343, period=3)
    >>> orb.ok, orb.status, orb.walls.tolist(), orb.stable
    (True, 'converged', [-1, 0, 0], True)
    >>> print(" ".join(f"{t:.6f}" for t in orb.theta))
    2.034489 4.110239 6.086836

    The product of the multipliers is ``det DF^3 = r^6 exp(-2 pi beta)`` (the closed-form determinant
    of the step Jacobian, telescoped over one period):

    >>> import numpy as np
    >>> print(f"{np.prod(orb.multipliers).real:.12f} {0.9**6 * np.exp(-0.2 * np.pi):.12f}")
    0.283517444618 0.283517444618
    """
    from ..core.params import check_params

    p = check_params(params).arrays()
    period = renamed_argument("impacts", "period", period, impacts, UNSET)
    if period is UNSET:
        raise InputTypeError("find_periodic() is missing period (impacts per period, 1 <= period <= 100000)")
    period, turns, tol, max_iter = check_newton(period, turns, tol, max_iter)
    tau0, sdot0, _ = check_start(tau0, sdot0)
    x = np.array([tau0 % float(TWO_PI), sdot0])
    wall0 = 0 if x[1] > 0 else -1
    res, it, conv = np.inf, 0, False
    for it in range(1, max_iter + 1):
        tp, sp, J, walls, stuck, ok = pfold(x[0], x[1], p, int(period), wall0)
        if not bool(ok) or bool(stuck):
            break
        G = np.array([float(tp) - x[0] - float(TWO_PI) * turns, float(sp) - x[1]])
        res = float(np.max(np.abs(G)))
        if res < tol:
            conv = True
            break
        try:
            dx = np.linalg.solve(np.asarray(J) - np.eye(2), -G)
        except np.linalg.LinAlgError:
            if it > 1:  # at a later iterate: Newton failed there (not converged), the guess was fine
                break
            raise ValueError(
                f"the Newton step is singular at (tau, sdot) = ({float(x[0])!r}, {float(x[1])!r}) (DF^p - I has no "
                f"inverse: a multiplier is 1): allowed a guess (tau0, sdot0) where it is "
                "invertible, e.g. closer to the orbit"
            ) from None
        # damped step: never flip the wall the orbit starts on
        lam = 1.0
        while lam > 1e-4 and np.sign(x[1] + lam * dx[1]) != np.sign(x[1]):
            lam *= 0.5
        x_new = x + lam * dx
        if not (np.all(np.isfinite(x_new)) and abs(x_new[0]) <= 1e6):  # Newton diverged: not converged
            break
        x = x_new
    tp, sp, J, walls, stuck, ok = pfold(x[0], x[1], p, int(period), wall0)
    # record the p states along the orbit
    taus, sds = [x[0]], [x[1]]
    s = make_state(x[0], x[1], wall0)
    for _ in range(int(period) - 1):
        s, _info = _step(s, p)
        taus.append(float(s.theta))
        sds.append(float(s.sdot))
    Jn = np.asarray(J)
    # the scan records the walls of states 1..p; state p is state 0, so roll to align with tau/sdot
    status = Status.CONVERGED if conv else Status.NOT_CONVERGED
    return PeriodicOrbit(
        params,
        int(period),
        int(turns),
        np.mod(np.array(taus), float(TWO_PI)),
        np.array(sds),
        np.roll(np.asarray(walls), 1),
        _multipliers(Jn),
        Jn,
        res,
        status.label,
        it,
    )


def _multipliers(J: np.ndarray) -> np.ndarray:
    """Eigenvalues of the monodromy matrix; NaN where it is not finite (the orbit ended or overflowed)."""
    return np.linalg.eigvals(J) if np.all(np.isfinite(J)) else np.full(J.shape[0], np.nan)


__all__ = [
    "pfold",
    "PeriodicOrbit",
    "MAX_TOL",
    "check_newton",
    "find_periodic",
]
