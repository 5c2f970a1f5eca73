"""The map track's orbit driver, and the event table of a trajectory of pre-impact states.

An :class:`~mapimpl.results.ImpactSequence` (every track's result type, :mod:`mapimpl.results`)
lists the events of one orbit in time order: impacts (``kind ==
"impact"``, with the velocity just before the impact) and, under the sticking policy, ``"stick"``
and ``"release"`` events.  Impact 0 is the initial pre-impact state (or, for a start in free flight,
the first impact reached); impacts 1..N follow.  Sticking rows carry the index of the impact after
which the tooth sticks.  Every track (``map``, ``scipy``, ``diffrax``) returns this type, so every
analysis and the CLI run on any track.
"""

from __future__ import annotations

import numpy as np

from . import _jax  # noqa: F401
import jax

from .flight import TWO_PI
from .impact_map import ACTIVE, ORBIT_STATUS_NAMES, MapState, free_flight_start, iterate, make_state
from .params import Params
from .results import ImpactSequence

_iterate_jit = jax.jit(iterate, static_argnums=2, static_argnames=("stick_time", "t_max"))
_free_start_jit = jax.jit(free_flight_start)


def sequence_from_states(params: Params, first: MapState, traj, track: str = "map", meta=None) -> ImpactSequence:
    """Build the event table from an initial state and an :func:`mapimpl.impact_map.iterate` result."""
    st, info = traj.states, traj.infos
    status = np.asarray(st.status)
    taus = np.concatenate([[float(first.tau)], np.asarray(st.tau)])
    sdots = np.concatenate([[float(first.sdot)], np.asarray(st.sdot)])
    walls = np.concatenate([[int(first.wall)], np.asarray(st.wall)])
    alive = np.concatenate([[int(first.status) == ACTIVE], status == ACTIVE])
    stuck = np.asarray(info.stuck)
    stick_tau, rel_tau = np.asarray(info.stick_tau), np.asarray(info.release_tau)
    rows_n, rows_t, rows_w, rows_v, rows_k = [], [], [], [], []
    for i in range(len(taus)):
        if not alive[i]:
            break
        rows_n.append(i); rows_t.append(taus[i]); rows_w.append(walls[i]); rows_v.append(sdots[i]); rows_k.append("impact")
        if i < len(stuck) and stuck[i]:
            rows_n.append(i); rows_t.append(stick_tau[i]); rows_w.append(walls[i]); rows_v.append(np.nan)
            rows_k.append("stick")
            if np.isfinite(rel_tau[i]):
                rows_n.append(i); rows_t.append(rel_tau[i]); rows_w.append(walls[i]); rows_v.append(np.nan)
                rows_k.append("release")
    final = int(first.status) if int(first.status) != ACTIVE else (int(status[-1]) if len(status) else ACTIVE)
    t = np.asarray(rows_t, dtype=np.float64)
    return ImpactSequence(
        params=params, n=np.asarray(rows_n, dtype=np.int64), tau=t, theta=np.mod(t, TWO_PI),
        wall=np.asarray(rows_w, dtype=np.int64), sdot=np.asarray(rows_v, dtype=np.float64),
        kind=np.asarray(rows_k), status=ORBIT_STATUS_NAMES[final], track=track, meta=dict(meta or {}),
    )


def initial_state(params: Params, tau0: float, sdot0: float, s0: float | None = None) -> MapState:
    """Initial pre-impact map state.

    With ``s0`` None, ``(tau0, sdot0)`` is the state just before an impact (the paper's convention;
    ``sdot0 > 0`` hits ``s = 0``, ``sdot0 < 0`` hits ``s = -1``; ``sdot0 = 0`` is rejected as
    ambiguous).  With ``-1 <= s0 <= 0`` it is a free-flight state and the first impact is searched.
    """
    if s0 is None:
        if not np.isfinite(sdot0) or sdot0 == 0.0:
            raise ValueError(f"initial sdot0={sdot0!r} is out of range: a pre-impact state needs sdot0 != 0 "
                             "(> 0 hits s = 0, < 0 hits s = -1)")
        if not np.isfinite(tau0):
            raise ValueError(f"initial tau0={tau0!r} is out of range: allowed any finite real")
        return make_state(tau0, sdot0)
    if not (np.isfinite(s0) and -1.0 <= s0 <= 0.0):
        raise ValueError(f"initial s0={s0!r} is out of range: allowed -1 <= s0 <= 0")
    if not (np.isfinite(tau0) and np.isfinite(sdot0)):
        raise ValueError("initial tau0 and sdot0 must be finite")
    return _free_start_jit(tau0, s0, sdot0, params.arrays())


def map_orbit(params: Params, tau0: float, sdot0: float, n_impacts: int, s0: float | None = None) -> ImpactSequence:
    """Orbit of the closed-form impact map: impact 0 plus ``n_impacts`` further impacts (Eqs. 12-13)."""
    if int(n_impacts) < 0:
        raise ValueError(f"n_impacts={n_impacts!r} is out of range: allowed n_impacts >= 0")
    first = initial_state(params, tau0, sdot0, s0)
    traj = _iterate_jit(first, params.arrays(), int(n_impacts))
    return sequence_from_states(params, first, traj, track="map",
                                meta={"tau0": tau0, "sdot0": sdot0, "s0": s0, "n_impacts": int(n_impacts)})
