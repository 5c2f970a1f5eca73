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


from ..core import jax_config  # noqa: F401
import jax

from .impact_map import free_flight_start, iterate
from .sticking import STICK_TIME, check_stick_time, stick_time_meta
from ..core.checks import MAX_IMPACTS, check_int, check_start
from ..core.state import MapState, make_state, run_in_chunks, sequence_from_states
from ..core.params import Params
from ..core.results import ImpactSequence

# ``stick_time`` is traced (one compilation serves every threshold: the fuzzer draws many), ``t_max`` static
_iterate_jit = jax.jit(iterate, static_argnums=2, static_argnames=("t_max",))
_free_start_jit = jax.jit(free_flight_start)


#: Impacts per XLA call of :func:`map_orbit` (about 0.1 s on a CPU core): Ctrl-C acts between
#: chunks, and one compilation serves every orbit length.
CHUNK = 1024

#: Largest ``chunk`` of :func:`map_orbit` (one compiled scan of that many steps).
MAX_CHUNK = 1 << 20


def initial_state(params: Params, tau0: float, sdot0: float, s0: float | None = None) -> MapState:
    """Initial pre-impact map state.

    With ``s0`` None, ``(tau0, sdot0)`` is the state just before an impact (the paper's convention;
    ``sdot0 > 0`` hits ``s = 0``, ``sdot0 < 0`` hits ``s = -1``; ``sdot0 = 0`` is rejected as
    ambiguous).  With ``-1 <= s0 <= 0`` it is a free-flight state and the first impact is searched.
    ``|tau0| <= TAU0_MAX`` (1e6) in both cases: beyond it the phase reduction loses the phase.
    """
    tau0, sdot0, s0 = check_start(tau0, sdot0, s0)
    if s0 is None:
        return make_state(tau0, sdot0)
    if (s0 == 0.0 and sdot0 > 0.0) or (s0 == -1.0 and sdot0 < 0.0):
        # on a wall moving into it: the pre-impact state itself (the flight from it hits at t = 0), decided
        # here on the host, where a subnormal sdot0 keeps its sign (XLA would see 0: jax_config.positive)
        return make_state(tau0, sdot0, wall=0 if s0 == 0.0 else -1)
    return _free_start_jit(tau0, s0, sdot0, params.arrays())


def iterate_chunked(
    first: MapState, params: Params, n: int, chunk: int = CHUNK, progress=None, stick_time: float = STICK_TIME
):
    """:func:`mapimpl.impact_map.iterate` for ``n`` steps with the sticking threshold ``stick_time`` (checked
    by the caller), run as a sequence of fixed-length scans (:func:`core.state.run_in_chunks`): Ctrl-C acts
    between chunks, and the result is bitwise the one of a single scan."""

    def run(state: MapState, p, length: int):
        return _iterate_jit(state, p, length, stick_time=stick_time)

    return run_in_chunks(run, first, params, n, chunk, progress=progress, label="map orbit")


def map_orbit(
    params: Params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None = None,
    *,
    chunk: int = CHUNK,
    progress=None,
    stick_time: float = STICK_TIME,
) -> ImpactSequence:
    """Orbit of the closed-form impact map: impact 0 plus ``n_impacts`` further impacts (Eqs. 12-13).

    Runs in chunks of ``chunk`` impacts (:func:`iterate_chunked`): interruptible with Ctrl-C, and the
    same result as one scan.  An orbit that ends (stuck forever, no impact) stops early.

    Parameters
    ----------
    params : Params
        The model's parameters.
    tau0, sdot0 : float
        Impact 0, a pre-impact state (``sdot0 > 0``: at ``s = 0``; ``sdot0 < 0``: at ``s = -1``), or
        with ``s0`` the free state ``(tau0, s0, sdot0)`` whose first impact is impact 0.
    n_impacts : int
        Impacts after impact 0, ``0 <= n_impacts <= MAX_IMPACTS`` (1e7: every impact is kept in memory).
    s0 : float, optional
        A start in free flight, ``-1 <= s0 <= 0``.
    chunk : int, optional
        Impacts per compiled scan, ``1 <= chunk <= 2**20``.
    progress : None, bool or callable, optional
        None (default) or True for a bar of the impacts on a terminal for runs over a second, False for
        none, or a callable ``progress(done, total)`` (:mod:`gear_rattle.core.progress`).
    stick_time : float, optional
        The sticking policy's threshold (:mod:`gear_rattle.mapimpl.sticking`), ``0 <= stick_time <= 1e-2``
        (default :data:`~gear_rattle.mapimpl.sticking.STICK_TIME`, 1e-6).

    Returns
    -------
    ImpactSequence
        One row per event (impacts, and a ``stick``/``release`` pair per sticking episode), with the
        orbit's ``status``.

    Raises
    ------
    ValueError, TypeError
        For an argument out of range or of the wrong type (:mod:`gear_rattle.core.checks`), naming it.

    Examples
    --------
    Fig. 4's attractor at alpha = 3, r = 0.9 is chaotic: the impacts alternate irregularly between the
    walls.

    >>> from gear_rattle.core.params import Params
    >>> from gear_rattle.mapimpl.orbit import map_orbit
    >>> seq = map_orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 200)
    >>> len(seq.n), seq.status, sorted(set(seq.wall.tolist()))
    (201, 'active', [-1, 0])

    With alpha = 2, gamma = 1, r = 0.5 the bounces accumulate at a wall and the teeth stick: a
    ``stick`` row, then a ``release`` row where the contact force changes sign (the sticking policy,
    docs/model.md).

    >>> chatter = map_orbit(Params(2.0, 0.1, 1.0, 0.5), 0.0, 0.5, 150)
    >>> chatter.n_sticking >= 3, "release" in chatter.kind.tolist()
    (True, True)
    """
    from ..core.params import check_params

    check_params(params)
    n_impacts = check_int("n_impacts", n_impacts, 0, MAX_IMPACTS)
    chunk = check_int("chunk", chunk, 1, MAX_CHUNK)
    stick_time = check_stick_time(stick_time)
    first = initial_state(params, tau0, sdot0, s0)
    traj = iterate_chunked(first, params, n_impacts, chunk, progress=progress, stick_time=stick_time)
    meta = {"tau0": tau0, "sdot0": sdot0, "s0": s0, "n_impacts": int(n_impacts), **stick_time_meta(stick_time)}
    return sequence_from_states(params, first, traj, track="map", meta=meta)


__all__ = [
    "CHUNK",
    "MAX_CHUNK",
    "initial_state",
    "iterate_chunked",
    "map_orbit",
]
