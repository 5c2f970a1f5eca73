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
and ``p = m = 0``; an orbit with a sticking step (``J = 0``, :mod:`validation.dynamics.lyapunov`) in the
Lyapunov window has ``lambda1 = lambda2 = -inf`` (the formal value: the product of Jacobians vanishes),
and its period is still looked for.  The result of a point depends only on that point and the spec, not
on the other points of the batch, their number or order (this is what makes the atlas independent of
tiling and worker count).

Method (pure JAX, one jitted kernel, vmapped over points: nothing runs on the host but reshaping)
------------------------------------------------------------------------------------------------
1. ``transient`` map steps (Eqs. 12-13 with the sticking policy, :func:`mapimpl.impact_map.step`);
2. ``impacts`` steps carrying the tangent map as ``J Q = Q R`` (:func:`validation.dynamics.lyapunov._qr_run`,
   the same code as ``gear-rattle lyapunov``, here with per-point ``alpha`` and ``r``);
3. ``W = 2 * period_max`` more steps recorded (:func:`mapimpl.impact_map.iterate`); the period is the
   smallest ``p`` in ``1 .. period_max`` with ``|theta_n - theta_{n-p}|`` (on the circle) and
   ``|sdot_n - sdot_{n-p}|`` both below ``period_tol`` and the same wall, for every ``n`` of the window
   with ``n - p`` in it; ``m = round((tau_W - tau_{W-p}) / 2 pi)``.  A chaotic orbit, a quasi-periodic
   one, a period above ``period_max`` and a periodic orbit not yet converged to ``period_tol`` after the
   transient all give 0.

The lead's engine path (tangent accumulation in the lane-refilling engine) is meant to replace this
function behind the same contract; it must change :data:`ENGINE` (stored with every atlas, so that a
store is never resumed with another engine).
"""

from __future__ import annotations

from functools import partial

import numpy as np

from ...mapimpl import _jax  # noqa: F401  (float64)
import jax
import jax.numpy as jnp

from ...mapimpl.flight import TWO_PI
from ...mapimpl.impact_map import ACTIVE, MapState, make_state, step
from ...mapimpl.params import ParamArrays, validate_arrays
from .spec import AtlasSpec

#: Name and version of the compute path; stored in the atlas and compared on resume.
ENGINE = "jax-qr/1"

#: The keys, dtypes and fill values (for points not yet computed) of :func:`compute_tile`'s result.
FIELDS: dict[str, tuple[np.dtype, object]] = {
    "lambda1": (np.dtype(np.float64), np.nan),
    "lambda2": (np.dtype(np.float64), np.nan),
    "period_p": (np.dtype(np.int32), 0),
    "period_m": (np.dtype(np.int32), 0),
    "status": (np.dtype(np.int8), -1),
}


def _period(states: MapState, period_max: int, tol):
    """``(p, m)`` of the recorded window of one orbit (see module docstring); ``(0, 0)`` if none."""
    th, cyc, sd, wall = states.theta, states.cycles, states.sdot, states.wall
    w = th.shape[0]
    k = jnp.arange(w)

    def mismatch(p):
        j = jnp.maximum(k - p, 0)
        dth = jnp.abs(jnp.remainder(th - th[j] + jnp.pi, TWO_PI) - jnp.pi)
        d = jnp.maximum(dth, jnp.abs(sd - sd[j]))
        d = jnp.where(wall == wall[j], d, jnp.inf)
        return jnp.max(jnp.where(k >= p, d, 0.0))

    ps = jnp.arange(1, period_max + 1)
    ok = jax.vmap(mismatch)(ps) < tol
    found = jnp.any(ok) & (states.status[-1] == ACTIVE)
    p = jnp.where(found, ps[jnp.argmax(ok)], 0)
    j = w - 1 - p
    turns = (cyc[-1] - cyc[j]).astype(jnp.float64) + (th[-1] - th[j]) / TWO_PI
    m = jnp.where(found, jnp.round(turns), 0)
    return p.astype(jnp.int32), m.astype(jnp.int32)


def _qr_givens(z):
    """``z = Q R`` for a 2x2 ``z`` by one Givens rotation, ``R`` with a positive diagonal: returns ``(Q,
    ln R11, ln R22)``.  Closed form, element-wise (no LAPACK call: cheap in a vmapped loop on any device)."""
    a, b, c, d = z[0, 0], z[0, 1], z[1, 0], z[1, 1]
    rho = jnp.hypot(a, c)
    safe = rho > 0.0
    ca = jnp.where(safe, a / jnp.where(safe, rho, 1.0), 1.0)
    sa = jnp.where(safe, c / jnp.where(safe, rho, 1.0), 0.0)
    r22 = -sa * b + ca * d  # = det(z) / rho
    sg = jnp.where(r22 < 0.0, -1.0, 1.0)
    q = jnp.array([[ca, -sa * sg], [sa, ca * sg]])
    return q, jnp.log(rho), jnp.log(jnp.abs(r22))


def _point(st: MapState, p: ParamArrays, tol, transient: int, impacts: int, period_max: int):
    """One orbit: transient, Lyapunov average, period window, in one loop (the map step is traced once)."""
    w = 2 * period_max
    eye = jnp.eye(2)
    rec0 = MapState(jnp.zeros(w), jnp.zeros(w, st.cycles.dtype), jnp.zeros(w), jnp.zeros(w, st.wall.dtype),
                    jnp.full(w, ACTIVE, st.status.dtype))

    def body(i, c):
        s, q, acc, n_stuck, n_ok, rec = c
        s1, info = step(s, p)
        # Lyapunov window (validation/dynamics/lyapunov.py semantics): Q restarts at I after a sticking
        # (J = 0) or terminal step and outside the window; sticking steps are counted
        in_lyap = (i >= transient) & (i < transient + impacts)
        alive = s1.status == ACTIVE
        qn, l1, l2 = _qr_givens(jnp.where(info.stuck, eye, info.jac) @ q)
        use = in_lyap & alive & ~info.stuck
        acc = acc + jnp.where(use, jnp.stack([l1, l2]), 0.0)
        q = jnp.where(use, qn, eye)
        n_stuck = n_stuck + (in_lyap & alive & info.stuck)
        n_ok = n_ok + use
        # period window: the last 2 * period_max states
        k = i - transient - impacts
        put = k >= 0
        kk = jnp.maximum(k, 0)
        rec = MapState(*(jnp.where(put, r.at[kk].set(x), r) for r, x in zip(rec, s1)))
        return s1, q, acc, n_stuck, n_ok, rec

    c0 = (st, eye, jnp.zeros(2), jnp.asarray(0), jnp.asarray(0), rec0)
    _, _, acc, n_stuck, n_ok, rec = jax.lax.fori_loop(0, transient + impacts + w, body, c0)
    alive = rec.status[-1] == ACTIVE
    lam = acc / jnp.maximum(n_ok, 1)
    lam = jnp.where(n_stuck > 0, -jnp.inf, lam)
    lam = jnp.where(alive, lam, jnp.nan)
    per, m = _period(rec, period_max, tol)
    return lam[0], lam[1], per, m, rec.status[-1].astype(jnp.int8)


@partial(jax.jit, static_argnums=(3, 4, 5))
def _kernel(st: MapState, p: ParamArrays, tol, transient: int, impacts: int, period_max: int):
    axes = ParamArrays(*(0 if jnp.ndim(x) else None for x in p))
    return jax.vmap(_point, in_axes=(0, axes, None, None, None, None))(st, p, tol, transient, impacts, period_max)


def compute_tile(alpha: np.ndarray, r: np.ndarray, spec: AtlasSpec) -> dict[str, np.ndarray]:
    """Largest Lyapunov exponent and period at the points ``(alpha[i], r[i])`` (the atlas's compute seam;
    contract and method in the module docstring).  ``ValueError`` for mismatched shapes or a bad value."""
    a = np.asarray(alpha, dtype=np.float64)
    rr = np.asarray(r, dtype=np.float64)
    if a.shape != rr.shape:
        raise ValueError(f"alpha and r have shapes {a.shape} and {rr.shape}: allowed arrays of one shape")
    shape = a.shape
    if a.size == 0:
        return {k: np.full(shape, fill, dt) for k, (dt, fill) in FIELDS.items()}
    a, rr = a.ravel(), rr.ravel()
    p = validate_arrays(a, spec.beta, spec.gamma, rr)
    n = a.size
    st = make_state(np.full(n, spec.tau0), np.full(n, spec.sdot0))
    out = _kernel(st, p, spec.period_tol, spec.transient, spec.impacts, spec.period_max)
    return {k: np.asarray(v).astype(FIELDS[k][0]).reshape(shape) for k, v in zip(FIELDS, out)}
