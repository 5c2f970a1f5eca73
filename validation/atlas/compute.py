"""The atlas's one compute seam: :func:`compute_tile` turns a batch of ``(alpha, r)`` points into the
largest Lyapunov exponent and the period of the attractor reached from the spec's initial condition.

Contract (pinned by ``tests/test_atlas.py::test_compute_tile_contract``)
---------------------------------------------------------------------------
``compute_tile(alpha, r, spec) -> dict[str, np.ndarray]`` with ``alpha`` and ``r`` float64 arrays of one
shape (any shape, validated: ``alpha >= 0``, ``0 < r <= 1``; ``beta``, ``gamma``, ``tau0``, ``sdot0`` and
the lengths come from ``spec``).  It returns, each with the input's shape:

==============  =========  ===========================================================================
key             dtype      meaning
==============  =========  ===========================================================================
``lambda1``     float64    largest Lyapunov exponent per impact (natural log), QR method over
                           ``spec.impacts`` impacts after ``spec.transient``
``lambda2``     float64    the other exponent of the 2-D map (``lambda1 >= lambda2``)
``period_p``    int32      impacts in the period (``1 <= p <= spec.period_max``), 0: no period found
``period_m``    int32      whole driving periods (turns of 2 pi) elapsed in those ``p`` impacts, 0 if none
``status``      int8       final orbit status (``mapimpl.impact_map``: 0 active, 1 stuck forever,
                           2 no further impact, 3 step cap)
==============  =========  ===========================================================================

Conventions: an orbit that *ends* (status != 0 at the end of the run) has ``lambda1 = lambda2 = NaN``
and ``p = m = 0``; an orbit with a sticking step (``J = 0``, :mod:`mapimpl.lyapunov`) in the
Lyapunov window has ``lambda1 = lambda2 = -inf`` (the formal value: the product of Jacobians vanishes),
and its period is still looked for.  The exponents follow the one rule of
:func:`gear_rattle.mapimpl.engine.exponents.exponents`.  The result of a point depends only on that point and the spec, not
on the other points of the batch, their number or order (this is what makes the atlas independent of
tiling and worker count).

**Method** (the many-orbit engine, :mod:`gear_rattle.mapimpl.engine`: every point is one orbit with its
own parameters, lanes are refilled as orbits end, nothing runs on the host but the period search):

1. ``transient`` map steps (Eqs. 12-13 with the sticking policy);
2. ``impacts`` steps carrying the tangent map as ``J Q = Q R`` (the engine's
   :class:`~gear_rattle.mapimpl.engine.observers.Tangent` observer; the same exponents as
   ``gear-rattle lyapunov``);
3. ``W = 2 * period_max`` more states recorded (:class:`~gear_rattle.mapimpl.engine.observers.Sample`);
   the period is the smallest ``p`` in ``1 .. period_max`` with ``|theta_n - theta_{n-p}|`` (on the
   circle) and ``|sdot_n - sdot_{n-p}|`` both below ``period_tol`` and the same wall, for every ``n`` of
   the window with ``n - p`` in it; ``m = round((tau_W - tau_{W-p}) / 2 pi)``.  A chaotic orbit, a
   quasi-periodic one, a period above ``period_max`` and a periodic orbit not yet converged to
   ``period_tol`` after the transient all give 0.

:data:`ENGINE` names this compute path; it is stored with every atlas, so that a store is never
resumed with another one.
"""

from __future__ import annotations

import numpy as np

from ...core import jax_config  # noqa: F401  (float64)

from ...mapimpl.engine.driver import run
from ...mapimpl.engine.exponents import exponents
from ...mapimpl.engine.observers import Sample, Tangent
from ...core.phase import TWO_PI
from ...core.checks import InputTypeError, check_array
from ...core.params import RANGES, ParamArrays, validate_arrays
from ...core.status import Status
from .spec import AtlasSpec

#: Name and version of the compute path; stored in the atlas and compared on resume.
ENGINE = "engine-tangent/1"

#: The keys, dtypes and fill values (for points not yet computed) of :func:`compute_tile`'s result.
FIELDS: dict[str, tuple[np.dtype, object]] = {
    "lambda1": (np.dtype(np.float64), np.nan),
    "lambda2": (np.dtype(np.float64), np.nan),
    "period_p": (np.dtype(np.int32), 0),
    "period_m": (np.dtype(np.int32), 0),
    "status": (np.dtype(np.int8), -1),
}


def period(
    theta: np.ndarray, sdot: np.ndarray, wall: np.ndarray, cycles: np.ndarray, period_max: int, tol: float
) -> tuple[np.ndarray, np.ndarray]:
    """``(p, m)`` of recorded windows (arrays ``(n_orbits, W)``, see the module docstring); 0 if none."""
    th, sd, w, cyc = (np.asarray(x) for x in (theta, sdot, wall, cycles))
    n, W = th.shape
    p_out = np.zeros(n, np.int32)
    m_out = np.zeros(n, np.int32)
    todo = np.isfinite(th).all(axis=1)
    for p in range(1, int(period_max) + 1):
        if not todo.any():
            break
        dth = np.abs(np.remainder(th[:, p:] - th[:, :-p] + np.pi, TWO_PI) - np.pi)
        d = np.maximum(dth, np.abs(sd[:, p:] - sd[:, :-p]))
        d = np.where(w[:, p:] == w[:, :-p], d, np.inf)
        ok = todo & (d.max(axis=1) < tol) if W > p else np.zeros(n, bool)
        if ok.any():
            j = W - 1 - p
            turns = (cyc[ok, -1] - cyc[ok, j]).astype(np.float64) + (th[ok, -1] - th[ok, j]) / TWO_PI
            p_out[ok] = p
            m_out[ok] = np.round(turns).astype(np.int32)
            todo &= ~ok
    return p_out, m_out


def compute_tile(alpha: np.ndarray, r: np.ndarray, spec: AtlasSpec) -> dict[str, np.ndarray]:
    """Largest Lyapunov exponent and period at the points ``(alpha[i], r[i])`` (the atlas's compute seam;
    contract and method in the module docstring).

    Parameters
    ----------
    alpha, r : numpy.ndarray
        The points, float64 arrays of one shape (``alpha >= 0``, ``0 < r <= 1``).
    spec : AtlasSpec
        ``beta``, ``gamma``, the initial condition and the lengths (``transient``, ``impacts``,
        ``period_max``, ``period_tol``).

    Returns
    -------
    dict of str to numpy.ndarray
        The fields of :data:`FIELDS` (``lambda1``, ``lambda2``, ``period_p``, ``period_m``, ``status``),
        each with the input's shape.

    Raises
    ------
    ValueError
        For mismatched shapes or a value out of range.

    Examples
    --------
    Fig. 2's regular motion (alpha = 0.5: three impacts per driving period, a negative exponent) and
    Fig. 4's chaos (alpha = 3: a positive exponent, no period), both at r = 0.9:

    >>> import numpy as np
    >>> from gear_rattle.validation.atlas.compute import compute_tile
    >>> from gear_rattle.validation.atlas.spec import AtlasSpec
    >>> spec = AtlasSpec(transient=300, impacts=500, period_max=16)
    >>> out = compute_tile(np.array([0.5, 3.0]), np.array([0.9, 0.9]), spec)
    >>> out["period_p"].tolist(), out["period_m"].tolist(), out["status"].tolist()
    ([3, 0], [1, 0], [0, 0])
    >>> bool(out["lambda1"][0] < 0 < out["lambda1"][1])
    True
    """
    if not isinstance(spec, AtlasSpec):
        raise InputTypeError(f"spec is a {type(spec).__name__}: allowed a validation.atlas.spec.AtlasSpec")
    a, rr = np.asarray(alpha), np.asarray(r)
    if a.size and rr.size:  # an empty tile is answered empty; else numbers, checked once (core.checks)
        check_array("alpha", alpha, ndim=None, allowed=RANGES["alpha"])
        check_array("r", r, ndim=None, allowed=RANGES["r"])
    a, rr = a.astype(np.float64), rr.astype(np.float64)
    if a.shape != rr.shape:
        raise ValueError(f"alpha and r have shapes {a.shape} and {rr.shape}: allowed arrays of one shape")
    shape = a.shape
    if a.size == 0:
        return {k: np.full(shape, fill, dt) for k, (dt, fill) in FIELDS.items()}
    a, rr = a.ravel(), rr.ravel()
    validate_arrays(a, spec.beta, spec.gamma, rr)
    n = a.size
    W = spec.window
    lyap_end = spec.transient + spec.impacts
    obs = (Tangent(n_start=spec.transient, n_end=lyap_end), Sample(keep=W, n_start=lyap_end + 1))
    res = run(
        np.full(n, spec.tau0),
        np.full(n, spec.sdot0),
        np.full(n, 0 if spec.sdot0 > 0 else -1, np.int32),
        ParamArrays(alpha=a, beta=np.full(n, spec.beta), gamma=np.full(n, spec.gamma), r=rr),
        obs,
        cap=lyap_end + W,
        progress=False,
        label="atlas",
    )
    sm = res.obs[1]
    ex = exponents(res, 0)  # the one rule: -inf where a step stuck, NaN where the orbit ended early
    lam, ended = ex.lam, ~ex.ran
    p, m = period(sm["theta"], sm["sdot"], sm["wall"], sm["cycles"], spec.period_max, spec.period_tol)
    p = np.where(ended, 0, p)
    m = np.where(ended, 0, m)
    status = np.where(ended, res.status, int(Status.ACTIVE)).astype(np.int8)
    out = {"lambda1": lam[:, 0], "lambda2": lam[:, 1], "period_p": p, "period_m": m, "status": status}
    return {k: np.asarray(v).astype(FIELDS[k][0]).reshape(shape) for k, v in out.items()}


__all__ = [
    "ENGINE",
    "FIELDS",
    "period",
    "compute_tile",
]
