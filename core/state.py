"""The map state every track steps (a pre-impact state) and how a run of states becomes the result type.

:class:`MapState` is the state just before impact n: phase ``theta`` in ``[0, 2 pi)``, whole turns
``cycles``, velocity ``sdot`` and the wall being hit (0: ``s = 0``; -1: ``s = -1``), with its orbit
status (:class:`~.status.Status`).  :class:`StepInfo` is what happened in one step, a
:class:`Trajectory` the stacked states and infos of many steps, and :func:`sequence_from_states`
turns one into an :class:`~.results.ImpactSequence`.
"""

from __future__ import annotations

from typing import NamedTuple, TypeAlias

import numpy as np

from . import jax_config  # noqa: F401  (float64)
import jax
import jax.numpy as jnp

from .jax_config import positive
from .params import Params
from .phase import TWO_PI, reduce_phase
from .results import ImpactSequence
from .status import Status

#: The arrays of the state records: traced or device JAX arrays, or their host (numpy) copies.
Array: TypeAlias = jax.Array | np.ndarray


class MapState(NamedTuple):
    """Pre-impact state of the map (see module docstring); ``status`` is an orbit status code."""

    theta: Array
    cycles: Array
    sdot: Array
    wall: Array
    status: Array

    @property
    def tau(self):
        """Elapsed time ``2 pi cycles + theta`` (float64; loses digits for very long orbits)."""
        return self.cycles.astype(self.theta.dtype) * TWO_PI + self.theta


class StepInfo(NamedTuple):
    """What happened during one map step.

    ``stuck``: the step stuck to the wall (a sticking episode); ``stick_tau`` / ``release_tau``:
    elapsed times of sticking and release (NaN if none); ``dt``: time from impact n to impact n+1;
    ``graze``: the new impact touches the wall at zero velocity to within rounding;
    ``steps``: safe steps of the first-impact search; ``jac``: 2x2 Jacobian (0 if stuck).
    """

    stuck: Array
    stick_tau: Array
    release_tau: Array
    dt: Array
    graze: Array
    steps: Array
    jac: Array


def make_state(tau, sdot, wall=None, status=Status.ACTIVE) -> MapState:
    """Map state from an elapsed time and pre-impact velocity; the wall follows the sign of ``sdot``
    (``sdot > 0``: wall 0; ``sdot < 0``: wall -1; a subnormal ``sdot`` too, :func:`.jax_config.positive`)
    unless given."""
    tau = jnp.asarray(tau, jnp.float64)
    sdot = jnp.asarray(sdot, jnp.float64)
    if wall is None:
        wall = jnp.where(positive(sdot), 0, -1)
    theta, cycles = reduce_phase(tau, jnp.zeros(jnp.shape(tau), jnp.int64))
    return MapState(
        theta,
        cycles,
        sdot,
        jnp.asarray(wall, jnp.int32) + jnp.zeros(jnp.shape(sdot), jnp.int32),
        jnp.asarray(status, jnp.int32) + jnp.zeros(jnp.shape(sdot), jnp.int32),
    )


class Trajectory(NamedTuple):
    """Stacked pre-impact states (leading axis: impact index 1..n) and step infos."""

    states: MapState
    infos: StepInfo


def sequence_from_states(params: Params, first: MapState, traj, track: str = "map", meta=None) -> ImpactSequence:
    """Build the event table from an initial state and an :func:`mapimpl.impact_map.iterate` result."""
    st, info = traj.states, traj.infos
    status = np.asarray(st.status)
    taus = np.concatenate([[float(first.tau)], np.asarray(st.tau)])
    sdots = np.concatenate([[float(first.sdot)], np.asarray(st.sdot)])
    walls = np.concatenate([[int(first.wall)], np.asarray(st.wall)])
    alive = np.concatenate([[int(first.status) == Status.ACTIVE], status == Status.ACTIVE])
    stuck = np.asarray(info.stuck)
    stick_tau, rel_tau = np.asarray(info.stick_tau), np.asarray(info.release_tau)
    rows_n, rows_t, rows_w, rows_v, rows_k = [], [], [], [], []
    for i in range(len(taus)):
        if not alive[i]:
            break
        rows_n.append(i)
        rows_t.append(taus[i])
        rows_w.append(walls[i])
        rows_v.append(sdots[i])
        rows_k.append("impact")
        if i < len(stuck) and stuck[i]:
            rows_n.append(i)
            rows_t.append(stick_tau[i])
            rows_w.append(walls[i])
            rows_v.append(np.nan)
            rows_k.append("stick")
            if np.isfinite(rel_tau[i]):
                rows_n.append(i)
                rows_t.append(rel_tau[i])
                rows_w.append(walls[i])
                rows_v.append(np.nan)
                rows_k.append("release")
    final = (
        int(first.status) if int(first.status) != Status.ACTIVE else (int(status[-1]) if len(status) else Status.ACTIVE)
    )
    t = np.asarray(rows_t, dtype=np.float64)
    return ImpactSequence(
        params=params,
        n=np.asarray(rows_n, dtype=np.int64),
        tau=t,
        theta=np.mod(t, TWO_PI),
        wall=np.asarray(rows_w, dtype=np.int64),
        sdot=np.asarray(rows_v, dtype=np.float64),
        kind=np.asarray(rows_k),
        status=Status(final).label,
        track=track,
        meta=dict(meta or {}),
    )


#: Scan length of runs of at most this many impacts (a short run does not pay for a long scan).
SHORT = 32


def chunk_length(n: int, chunk: int) -> int:
    """Scan length of every chunk of an ``n``-impact run: :data:`SHORT` for short runs, else ``chunk``.

    Two lengths only, so two compilations serve every orbit length (a compilation costs seconds,
    a wasted step ~0.1 ms)."""
    return min(int(chunk), SHORT) if int(n) <= SHORT else int(chunk)


def run_in_chunks(run, first: MapState, params: Params, n: int, chunk: int, progress=None, label: str = "orbit"):
    """``run(first, params.arrays(), n)`` -- ``n`` steps of a track's map, a jitted ``lax.scan`` of
    ``length`` (static) steps returning a pytree whose ``states`` field is the stacked
    :class:`MapState` -- as a sequence of fixed-length scans (the map track,
    :func:`mapimpl.orbit.iterate_chunked`, and the diffrax track, :mod:`reference.diffrax_track`).

    Every chunk is one XLA call of a fixed length (the last one truncated), synchronised before the
    next starts, so a KeyboardInterrupt (Ctrl-C) acts between chunks, within a fraction of a second.
    The steps are the same as in one long scan (the carry is the state), so the result is bitwise the
    same.  The run stops early once the orbit has ended (terminal states are frozen by the map, and
    :func:`sequence_from_states` stops at the first one).  ``progress``: a bar of the impacts (None:
    when stderr is a terminal and the run lasts over a second; True: also lines where it is not; in
    the phase "compiling" until the first chunk returns) or a callable ``(done, n)`` (:mod:`core.progress`).
    """
    from .progress import Bar, sink, wanted

    n = int(n)
    if int(chunk) < 1:
        raise ValueError(f"chunk={chunk!r} is out of range: allowed chunk >= 1")
    pa = params.arrays()
    length = chunk_length(n, chunk)
    parts = []
    state, done = first, 0
    report = sink(progress)
    with Bar(label, total=n, enabled=wanted(progress), phase="compiling", delay=1.0) as bar:
        while done < n:
            traj = run(state, pa, length)
            take = min(length, n - done)
            part = jax.tree_util.tree_map(lambda x: np.asarray(x)[:take], traj)  # blocks: Ctrl-C acts here
            parts.append(part)
            done += take
            bar.update(done)
            if report is not None:
                report(done, n)
            state = MapState(*(jnp.asarray(x[-1]) for x in part.states))  # host copies: bitwise the carry
            if int(state.status) != Status.ACTIVE:
                break
    if not parts:  # n = 0: empty arrays of the right shapes and types (traced, not compiled)
        shapes = jax.eval_shape(lambda s: run(s, pa, 0), first)
        return jax.tree_util.tree_map(lambda a: np.zeros(a.shape, a.dtype), shapes)
    return jax.tree_util.tree_map(lambda *xs: np.concatenate(xs), *parts)


__all__ = [
    "Array",
    "MapState",
    "StepInfo",
    "make_state",
    "Trajectory",
    "sequence_from_states",
    "SHORT",
    "chunk_length",
    "run_in_chunks",
]
