"""The map track's orbit driver, and the event table of a trajectory of pre-impact states.

An :class:`~core.results.ImpactSequence` (every track's result type, :mod:`core.results`)
lists the events of one orbit in time order: impacts (``kind ==
"impact"``, with the velocity just before the impact) and, under the sticking policy, ``"stick"``
and ``"release"`` events.  Impact 0 is the initial pre-impact state (or, for a start in free flight,
the first impact reached); impacts 1..N follow.  Sticking rows carry the index of the impact after
which the tooth sticks.  Every track (``map``, ``scipy``, ``diffrax``) returns this type, so every
analysis and the CLI run on any track.
"""

from __future__ import annotations

import numpy as np

from ..core import _jax  # noqa: F401
import jax

from .impact_map import free_flight_start, iterate
from ..core.checks import check_tau0
from ..core.state import MapState, make_state, run_in_chunks, sequence_from_states
from ..core.params import Params
from ..core.results import ImpactSequence

_iterate_jit = jax.jit(iterate, static_argnums=2, static_argnames=("stick_time", "t_max"))
_free_start_jit = jax.jit(free_flight_start)





#: Impacts per XLA call of :func:`map_orbit` (about 0.1 s on a CPU core): Ctrl-C acts between
#: chunks, and one compilation serves every orbit length.
CHUNK = 1024


def initial_state(params: Params, tau0: float, sdot0: float, s0: float | None = None) -> MapState:
    """Initial pre-impact map state.

    With ``s0`` None, ``(tau0, sdot0)`` is the state just before an impact (the paper's convention;
    ``sdot0 > 0`` hits ``s = 0``, ``sdot0 < 0`` hits ``s = -1``; ``sdot0 = 0`` is rejected as
    ambiguous).  With ``-1 <= s0 <= 0`` it is a free-flight state and the first impact is searched.
    ``|tau0| <= TAU0_MAX`` (1e6) in both cases: beyond it the phase reduction loses the phase.
    """
    tau0 = check_tau0(tau0)
    if s0 is None:
        if not np.isfinite(sdot0) or sdot0 == 0.0:
            raise ValueError(f"initial sdot0={sdot0!r} is out of range: a pre-impact state needs sdot0 != 0 "
                             "(> 0 hits s = 0, < 0 hits s = -1)")
        return make_state(tau0, sdot0)
    if not (np.isfinite(s0) and -1.0 <= s0 <= 0.0):
        raise ValueError(f"initial s0={s0!r} is out of range: allowed -1 <= s0 <= 0")
    if not np.isfinite(sdot0):
        raise ValueError(f"initial sdot0={sdot0!r} is out of range: allowed a finite real")
    if (s0 == 0.0 and sdot0 > 0.0) or (s0 == -1.0 and sdot0 < 0.0):
        # on a wall moving into it: the pre-impact state itself (the flight from it hits at t = 0), decided
        # here on the host, where a subnormal sdot0 keeps its sign (XLA would see 0: _jax.positive)
        return make_state(tau0, sdot0, wall=0 if s0 == 0.0 else -1)
    return _free_start_jit(tau0, s0, sdot0, params.arrays())


def iterate_chunked(first: MapState, params: Params, n: int, chunk: int = CHUNK, progress=False):
    """:func:`mapimpl.impact_map.iterate` for ``n`` steps, run as a sequence of fixed-length scans
    (:func:`core.state.run_in_chunks`): Ctrl-C acts between chunks, and the result is bitwise the one
    of a single scan."""
    return run_in_chunks(_iterate_jit, first, params, n, chunk, progress=progress, label="map orbit")


def map_orbit(params: Params, tau0: float, sdot0: float, n_impacts: int, s0: float | None = None, *,
              chunk: int = CHUNK, progress=False) -> ImpactSequence:
    """Orbit of the closed-form impact map: impact 0 plus ``n_impacts`` further impacts (Eqs. 12-13).

    Runs in chunks of ``chunk`` impacts (:func:`iterate_chunked`): interruptible with Ctrl-C, and the
    same result as one scan.  An orbit that ends (stuck forever, no impact) stops early.  ``progress``:
    None or True for a bar of the impacts on a terminal for runs over a second (default False: none;
    :mod:`gear_rattle.core.progress`).
    """
    from ..core.params import check_params

    check_params(params)
    if isinstance(n_impacts, bool) or int(n_impacts) != n_impacts or int(n_impacts) < 0:
        raise ValueError(f"n_impacts={n_impacts!r} is out of range: allowed an integer n_impacts >= 0")
    first = initial_state(params, tau0, sdot0, s0)
    traj = iterate_chunked(first, params, int(n_impacts), chunk, progress=progress)
    return sequence_from_states(params, first, traj, track="map",
                                meta={"tau0": tau0, "sdot0": sdot0, "s0": s0, "n_impacts": int(n_impacts)})
