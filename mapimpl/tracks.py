"""The registry of tracks: every track is a :class:`core.results.Track` with a name, ``orbit`` and
``step_jacobian``.

* ``map`` -- the closed form (:mod:`mapimpl`): :func:`mapimpl.orbit.map_orbit`, and the analytic
  Jacobian of Eqs. (12)-(13) from :func:`mapimpl.impact_map.step`;
* ``scipy`` and ``diffrax`` -- Eq. (3) integrated numerically (:mod:`reference`), loaded on first use
  by the loader that the package's facade registers (:mod:`core.registry`: this layer may not import
  ``reference``; diffrax is heavy; a missing integrator shows up as ``ImportError`` from :func:`get`);
* ``certified`` (:func:`orbit` only, :data:`ORBIT_TRACKS`) -- the orbit in ball arithmetic, every row
  proven, with float64 bounds (:func:`mapimpl.certified.track.track_orbit`); it has no float64 step
  Jacobian, so it is not a :class:`core.results.Track` of :data:`TRACKS`.

All return :class:`core.results.ImpactSequence` and :class:`core.results.StepJacobian`.
"""

from __future__ import annotations

import math

import numpy as np

from ..core import jax_config  # noqa: F401
import jax

from ..core.deprecation import warn_renamed
from ..core.status import Status
from .impact_map import step
from ..core.state import make_state
from .orbit import map_orbit
from .sticking import STICK_TIME, check_stick_time
from ..core.checks import MAX_IMPACTS, check_choice, check_int, check_start, start_wall
from ..core.params import Params, check_params
from ..core.progress import check_progress
from ..core.registry import load_track
from ..core.results import TRACKS, ImpactSequence, StepJacobian, Track, TrackFunctions

#: The tracks :func:`orbit` takes: :data:`TRACKS` and the certified track.
ORBIT_TRACKS = TRACKS + ("certified",)

_step_jit = jax.jit(step)


def _no_options(options: dict) -> None:
    if options:
        name = next(iter(options))
        raise ValueError(
            f"option {name}={options[name]!r} is out of range: the map track takes no solver options (only stick_time)"
        )


def _map_orbit(
    params: Params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None = None,
    progress=None,
    stick_time: float = STICK_TIME,
    **options,
) -> ImpactSequence:
    _no_options(options)
    return map_orbit(params, tau0, sdot0, n_impacts, s0=s0, progress=progress, stick_time=stick_time)


def _map_step_jacobian(params: Params, tau: float, sdot: float, wall: int | None = None, **options) -> StepJacobian:
    """One map step (Eqs. 11-13 with the sticking policy) from the pre-impact state ``(tau, sdot)``
    with the analytic Jacobian of :func:`mapimpl.impact_map.step` (implicit differentiation of the
    impact condition; 0 if the step sticks)."""
    _no_options(options)
    check_params(params)
    tau, sdot, _ = check_start(tau, sdot, None, ("tau", "sdot"))
    wall = start_wall(wall, sdot)
    new, info = _step_jit(make_state(tau, sdot, wall), params.arrays())
    stuck, status = bool(info.stuck), int(new.status)
    if status != Status.ACTIVE:
        jac = np.zeros((2, 2)) if stuck else np.full((2, 2), np.nan)
        return StepJacobian(math.nan, math.nan, wall, jac, stuck, Status(status).label)
    return StepJacobian(
        float(new.tau), float(new.sdot), int(new.wall), np.asarray(info.jac), stuck, Status(status).label
    )


#: The closed-form track.
MAP = TrackFunctions("map", _map_orbit, _map_step_jacobian)


def get(track: str) -> Track:
    """The :class:`~core.results.Track` named ``track`` (one of :data:`TRACKS`); ``ValueError``
    for an unknown name, ``ImportError`` when its integrator is not installed."""
    check_choice("track", track, TRACKS)
    if track == "map":
        return MAP
    return load_track(track)


def orbit(
    params: Params,
    tau0: float,
    sdot0: float,
    n_impacts: int,
    s0: float | None = None,
    *,
    track: str = "map",
    stick_time: float = STICK_TIME,
    progress=None,
    **solver_options,
) -> ImpactSequence:
    """Impact sequence of one orbit on ``track``: impact 0, then ``n_impacts`` further impacts.

    Parameters
    ----------
    params : Params
        The model's parameters ``alpha, beta, gamma, r`` of Eq. (3) and the reset of Eq. (11).
    tau0, sdot0 : float
        Impact 0 as a pre-impact state (the paper's map variables, Eqs. 12-13): time ``tau0`` and
        velocity ``sdot0 != 0`` just before the impact (``sdot0 > 0`` hits ``s = 0``, ``sdot0 < 0``
        hits ``s = -1``); with ``s0``, the free state ``(tau0, s0, sdot0)`` whose flight's first
        impact is impact 0.
    n_impacts : int
        Impacts after impact 0, ``0 <= n_impacts <= 1e7`` (every impact is kept in memory; an orbit that
        sticks forever or never lands again ends early).
    track : {"map", "scipy", "diffrax", "certified"}
        The closed-form impact map (:mod:`gear_rattle.mapimpl.orbit`), a numerical integration of
        Eq. (3) (:mod:`gear_rattle.reference`; :data:`TRACKS`), or the certified track
        (:mod:`gear_rattle.mapimpl.certified.track`: every row proven in ball arithmetic, the values the
        float64 nearest to the exact ones and float64 bounds in ``seq.bounds``; it raises
        :class:`~gear_rattle.mapimpl.certified.track.UncertifiedOrbit`, holding the certified prefix, where
        no precision up to its limit certifies every impact).
    s0 : float, optional
        A start in free flight, ``-1 <= s0 <= 0``.
    stick_time : float, optional
        The sticking policy's threshold, the same on every track (:mod:`gear_rattle.mapimpl.sticking`): a
        chatter whose predicted accumulation time is at most ``stick_time`` sticks to the wall;
        ``0 <= stick_time <= 1e-2`` (:data:`~gear_rattle.mapimpl.sticking.MAX_STICK_TIME`), default
        :data:`~gear_rattle.mapimpl.sticking.STICK_TIME` (1e-6).
    progress : None, bool or callable, optional
        None (default) or True: a bar when stderr is a terminal; False: none; a callable
        ``progress(done, total)`` (:mod:`gear_rattle.core.progress`).
    **solver_options
        Of the numerical tracks: ``rtol``, ``atol``, ``t_max`` and ``max_step`` (scipy) or ``dtmax``,
        ``max_steps`` (diffrax); the map track takes none; the certified track ``prec``,
        ``max_prec`` (the precision schedule's start and limit, bits), ``t_max`` and ``time_budget_s``.

    Returns
    -------
    ImpactSequence
        :class:`gear_rattle.core.results.ImpactSequence`: per event ``n``, ``tau`` (absolute time),
        ``theta = tau mod 2 pi``, ``wall``, ``sdot``, ``kind``, and whether it worked (``ok``, ``status``,
        ``message``).

    Raises
    ------
    ValueError, TypeError
        For an argument out of range or of the wrong type, naming it and its range
        (:mod:`gear_rattle.core.checks`; ``0 <= n_impacts <= MAX_IMPACTS``, 1e7), before any track is
        loaded or anything computed.  The old call ``orbit(track, params, ...)`` still works, with a
        DeprecationWarning.

    Examples
    --------
    The same orbit on the closed-form map and on scipy's integration of Eq. (3):

    >>> import gear_rattle as gr
    >>> p = gr.Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.9)
    >>> seq = gr.orbit(p, tau0=0.0, sdot0=0.5, n_impacts=10, track="map")
    >>> seq.wall[:5].tolist()
    [0, -1, -1, 0, 0]
    >>> print(f"{seq.tau[10]:.6f}", seq.status, seq.ok)
    10.831944 active True
    >>> ref = gr.orbit(p, tau0=0.0, sdot0=0.5, n_impacts=10, track="scipy")
    >>> bool(abs(ref.tau - seq.tau).max() < 1e-8)
    True
    """
    if isinstance(params, str):  # the old order: orbit(track, params, tau0, sdot0, n_impacts)
        warn_renamed(
            "orbit(track, params, tau0, sdot0, n_impacts)", "orbit(params, tau0, sdot0, n_impacts, track=track)"
        )
        track, params, tau0, sdot0, n_impacts, s0 = params, tau0, sdot0, n_impacts, s0, solver_options.pop("s0", None)
    check_choice("track", track, ORBIT_TRACKS)
    check_params(params)
    check_int("n_impacts", n_impacts, 0, MAX_IMPACTS)
    check_start(tau0, sdot0, s0)
    check_progress(progress)
    stick_time = check_stick_time(stick_time)
    if track == "certified":
        from .certified.track import track_orbit

        return track_orbit(
            params, tau0, sdot0, n_impacts, s0=s0, progress=progress, stick_time=stick_time, **solver_options
        )
    return get(track).orbit(
        params, tau0, sdot0, n_impacts, s0=s0, progress=progress, stick_time=stick_time, **solver_options
    )


def step_jacobian(
    track: str, params: Params, tau: float, sdot: float, wall: int | None = None, **options
) -> StepJacobian:
    """One impact-to-impact step with its Jacobian on the chosen track (:meth:`Track.step_jacobian`); the
    arguments are checked first (:mod:`core.checks`), naming them."""
    check_choice("track", track, TRACKS)
    check_params(params)
    check_start(tau, sdot, None, ("tau", "sdot"))
    start_wall(wall, sdot)
    return get(track).step_jacobian(params, tau, sdot, wall, **options)


__all__ = ["TRACKS", "ORBIT_TRACKS", "MAP", "get", "orbit", "step_jacobian"]
