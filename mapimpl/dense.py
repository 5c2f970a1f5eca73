"""Dense trajectory s(tau) of an impact sequence from the closed form, Eqs. (7)-(8).

Between events the flight leaves each impact with ``sdot0 = -r sdot`` (Eq. 11) or, after a release
from sticking, with ``sdot0 = 0``; while stuck, ``s`` equals the wall.  Used for plots (Figs. 2-3)
and for invariant checks.

All flight samples of an orbit are evaluated together, in blocks of a fixed size :data:`BLOCK`
(the last one padded), by one jitted kernel: one compilation serves every orbit, span and
parameter set (evaluating flight by flight with eager JAX compiled anew for every flight length).
"""

from __future__ import annotations

import numpy as np

from ..core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from .flight import flight
from ..core.phase import TWO_PI
from ..core.results import ImpactSequence

#: Samples per kernel call (fixed shape: the last block is padded with t = 0).
BLOCK = 4096


@jax.jit
def _flight_block(t, theta0, v0, alpha, beta, gamma):
    """``(ds, v)`` of :func:`mapimpl.flight.flight` at ``BLOCK`` samples (elementwise)."""
    fp = flight(t, theta0, v0, alpha, beta, gamma)
    return fp.ds, fp.v


def flight_samples(t, theta0, v0, alpha: float, beta: float, gamma: float) -> tuple[np.ndarray, np.ndarray]:
    """Closed-form flight (Eqs. 7-8) at arrays of samples ``t`` after leaving phase ``theta0`` with
    velocity ``v0`` (arrays of one length): ``(ds, v)`` as numpy arrays, evaluated in padded blocks of
    :data:`BLOCK` so that the kernel compiles once for every length."""
    t, theta0, v0 = (np.asarray(x, dtype=np.float64).ravel() for x in (t, theta0, v0))
    m = t.size
    nb = max(1, -(-m // BLOCK))
    pad = nb * BLOCK - m
    tp, thp, vp = (np.concatenate([x, np.zeros(pad)]).reshape(nb, BLOCK) for x in (t, theta0, v0))
    a, b, g = (jnp.float64(x) for x in (alpha, beta, gamma))
    ds, v = np.empty((nb, BLOCK)), np.empty((nb, BLOCK))
    for k in range(nb):
        dsk, vk = _flight_block(tp[k], thp[k], vp[k], a, b, g)
        ds[k], v[k] = np.asarray(dsk), np.asarray(vk)
    return ds.ravel()[:m], v.ravel()[:m]


def dense(seq: ImpactSequence, points_per_unit: float = 40.0, t_end: float | None = None):
    """Sample ``(tau, s, sdot)`` along the orbit from its first to its last event.

    Every event time is included as a sample (so walls are hit exactly in the output).  ``t_end``
    limits the sampled span.
    """
    p = seq.params
    kinds, t_ev, walls, sd = seq.kind, seq.tau, seq.wall, seq.sdot
    # pieces in time order: (grid, kind) with kind "flight" (evaluated below) or a constant state
    pieces: list[tuple] = []
    fl_t: list[np.ndarray] = []
    fl_th: list[np.ndarray] = []
    fl_v: list[np.ndarray] = []
    fl_w: list[np.ndarray] = []
    for i in range(len(t_ev) - 1):
        t0, t1 = t_ev[i], t_ev[i + 1]
        if t_end is not None and t0 >= t_end:
            break
        w = float(walls[i])
        if kinds[i] == "stick":  # stuck until the release row
            grid = np.linspace(t0, t1, max(2, int((t1 - t0) * points_per_unit)))
            pieces.append((grid, np.full_like(grid, w), np.zeros_like(grid)))
            continue
        if kinds[i] == "impact" and i + 1 < len(kinds) and kinds[i + 1] == "stick":
            # the chatter accumulation interval (< STICK_TIME): the tooth stays at the wall
            pieces.append((np.array([t0]), np.array([w]), np.array([0.0])))
            continue
        v0 = 0.0 if kinds[i] == "release" else -p.r * sd[i]
        m = max(2, int(np.ceil((t1 - t0) * points_per_unit)) + 1)
        grid = np.linspace(t0, t1, m)[:-1]  # the next event's own sample closes the flight
        pieces.append((grid, None, len(fl_t)))
        fl_t.append(grid - t0)
        fl_th.append(np.full(grid.size, np.mod(t0, TWO_PI)))
        fl_v.append(np.full(grid.size, v0))
        fl_w.append(np.full(grid.size, w))
    if fl_t:
        sizes = [g.size for g in fl_t]
        ds, v = flight_samples(
            np.concatenate(fl_t), np.concatenate(fl_th), np.concatenate(fl_v), p.alpha, p.beta, p.gamma
        )
        s = np.clip(np.concatenate(fl_w) + ds, -1.0, 0.0)
        bounds = np.concatenate([[0], np.cumsum(sizes)])
    taus, ss, vs = [], [], []
    for grid, s_const, v_or_index in pieces:
        taus.append(grid)
        if s_const is None:
            j = v_or_index
            ss.append(s[bounds[j] : bounds[j + 1]])
            vs.append(v[bounds[j] : bounds[j + 1]])
        else:
            ss.append(s_const)
            vs.append(v_or_index)
    if len(t_ev):
        taus.append(np.array([t_ev[-1]]))
        ss.append(np.array([float(walls[-1])]))
        vs.append(np.array([sd[-1] if np.isfinite(sd[-1]) else 0.0]))
    if not taus:
        return np.empty(0), np.empty(0), np.empty(0)
    return np.concatenate(taus), np.concatenate(ss), np.concatenate(vs)


__all__ = [
    "BLOCK",
    "flight_samples",
    "dense",
]
