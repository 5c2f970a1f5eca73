"""Dense trajectory s(tau) of an impact sequence from the closed form, Eqs. (7)-(8).

Between events the flight leaves each impact with ``sdot0 = -r sdot`` (Eq. 11) or, after a release
from sticking, with ``sdot0 = 0``; while stuck, ``s`` equals the wall.  Used for plots (Figs. 2-3)
and for invariant checks.
"""

from __future__ import annotations

import numpy as np

from . import _jax  # noqa: F401
import jax.numpy as jnp

from .flight import flight
from .results import ImpactSequence


def dense(seq: ImpactSequence, points_per_unit: float = 40.0, t_end: float | None = None):
    """Sample ``(tau, s, sdot)`` along the orbit from its first to its last event.

    Every event time is included as a sample (so walls are hit exactly in the output).  ``t_end``
    limits the sampled span.
    """
    p = seq.params
    taus, ss, vs = [], [], []
    kinds, t_ev, walls, sd = seq.kind, seq.tau, seq.wall, seq.sdot
    for i in range(len(t_ev) - 1):
        t0, t1 = t_ev[i], t_ev[i + 1]
        if t_end is not None and t0 >= t_end:
            break
        w = float(walls[i])
        if kinds[i] == "stick":  # stuck until the release row
            grid = np.linspace(t0, t1, max(2, int((t1 - t0) * points_per_unit)))
            taus.append(grid); ss.append(np.full_like(grid, w)); vs.append(np.zeros_like(grid))
            continue
        if kinds[i] == "impact" and i + 1 < len(kinds) and kinds[i + 1] == "stick":
            # the chatter accumulation interval (< STICK_TIME): the tooth stays at the wall
            taus.append(np.array([t0])); ss.append(np.array([w])); vs.append(np.array([0.0]))
            continue
        v0 = 0.0 if kinds[i] == "release" else -p.r * sd[i]
        m = max(2, int(np.ceil((t1 - t0) * points_per_unit)) + 1)
        grid = np.linspace(t0, t1, m)
        fp = flight(jnp.asarray(grid - t0), np.mod(t0, 2 * np.pi), v0, p.alpha, p.beta, p.gamma)
        s = np.clip(w + np.asarray(fp.ds), -1.0, 0.0)
        s[-1] = float(walls[i + 1])
        taus.append(grid[:-1]); ss.append(s[:-1]); vs.append(np.asarray(fp.v)[:-1])
    if len(t_ev):
        taus.append(np.array([t_ev[-1]])); ss.append(np.array([float(walls[-1])]))
        vs.append(np.array([sd[-1] if np.isfinite(sd[-1]) else 0.0]))
    return np.concatenate(taus), np.concatenate(ss), np.concatenate(vs)
