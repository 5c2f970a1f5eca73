"""Damped Newton for a small nonlinear system ``R^3 -> R^3`` (the extended systems of the fold and flip
points, :func:`.continuation.locate`), with a forward-difference Jacobian where no exact one is given."""

from __future__ import annotations

import numpy as np


def fd_jacobian(fun, y, F, fd_h=None):
    """Forward-difference Jacobian of ``fun`` at ``y`` (``F = fun(y)``), a backward difference in a
    column whose forward point is invalid; ``None`` when neither is valid."""
    Jm = np.empty((3, 3))
    for j in range(3):
        h = (fd_h or 1e-7) * max(1.0, abs(y[j]))
        e = np.zeros(3)
        e[j] = h
        Fp = fun(y + e)
        if Fp is None or not np.all(np.isfinite(Fp)):
            Fm = fun(y - e)
            if Fm is None:
                return None
            Jm[:, j] = (F - Fm) / h
        else:
            Jm[:, j] = (Fp - F) / h
    return Jm


def newton(fun, y0, max_iter=30, tol=1e-12, fd_h=None, polish_steps=0, jac=None):
    """Newton for ``fun: R^3 -> R^3``; returns (y, res, iters, ok).

    ``jac(y)`` gives the 3x3 Jacobian (:func:`.continuation.locate` passes the ``jax.jacfwd`` one); where it is not
    given or returns ``None`` (not differentiable there, not finite), a forward-difference Jacobian
    (step ``fd_h``, default ``1e-7``, relative) is used instead.  Once the residual is below ``tol``,
    up to ``polish_steps`` more steps are taken while they lower it (the solution is then at the
    rounding level of ``fun``)."""
    y = np.array(y0, dtype=np.float64)
    res, it = np.inf, 0
    polish = 0
    y_prev = y  # the point before the last step (a polishing step that did not help goes back to it)
    for it in range(1, max_iter + polish_steps + 1):
        F = fun(y)
        if F is None or not np.all(np.isfinite(F)):
            return y, np.inf, it, False
        r_now = float(np.max(np.abs(F)))
        if polish and r_now >= res:  # the polishing step did not help: keep the previous point
            return y_prev, res, it, True
        res = r_now
        if res < tol:
            if polish >= polish_steps or res == 0.0:
                return y, res, it, True
            polish += 1
        elif it > max_iter:
            break
        Jm = jac(y) if jac is not None else None
        if Jm is None:
            Jm = fd_jacobian(fun, y, F, fd_h)
            if Jm is None:
                return y, res, it, False
        try:
            dy = np.linalg.solve(Jm, -F)
        except np.linalg.LinAlgError:
            return y, res, it, False
        y_prev = y
        if polish:  # a full step, judged at the next iteration
            y = y + dy
            continue
        lam = 1.0
        while lam > 1e-3:
            Fn = fun(y + lam * dy)
            if Fn is not None and np.all(np.isfinite(Fn)) and np.max(np.abs(Fn)) < (1 - 0.1 * lam) * res + 1e-15:
                break
            lam *= 0.5
        y = y + lam * dy
    F = fun(y)
    res = float(np.max(np.abs(F))) if F is not None else np.inf
    return y, res, it, res < tol


__all__ = [
    "fd_jacobian",
    "newton",
]
