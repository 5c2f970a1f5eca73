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

from ..core import _jax  # noqa: F401
import jax

from ..core.status import Status
from .impact_map import step
from ..core.state import make_state
from .orbit import map_orbit
from ..core.checks import MAX_IMPACTS, check_choice, check_int, check_start, start_wall
from ..core.params import Params, check_params
from ..core.registry import load_track
from ..core.results import TRACKS, ImpactSequence, StepJacobian, Track, TrackFunctions

#: The tracks :func:`orbit` takes: :data:`TRACKS` and the certified track.
ORBIT_TRACKS = TRACKS + ("certified",)

_step_jit = jax.jit(step)


def _no_options(options: dict) -> None:
    if options:
        name = next(iter(options))
        raise ValueError(f"option {name}={options[name]!r} is out of range: the map track takes no options")


def _map_orbit(params: Params, tau0: float, sdot0: float, n_impacts: int, s0: float | None = None,
               progress=False, **options) -> ImpactSequence:
    _no_options(options)
    return map_orbit(params, tau0, sdot0, n_impacts, s0=s0, progress=progress)


def _map_step_jacobian(params: Params, tau: float, sdot: float, wall: int | None = None,
                       **options) -> StepJacobian:
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
    return StepJacobian(float(new.tau), float(new.sdot), int(new.wall), np.asarray(info.jac), stuck,
                        Status(status).label)


#: The closed-form track.
MAP = TrackFunctions("map", _map_orbit, _map_step_jacobian)


def get(track: str) -> Track:
    """The :class:`~core.results.Track` named ``track`` (one of :data:`TRACKS`); ``ValueError``
    for an unknown name, ``ImportError`` when its integrator is not installed."""
    check_choice("track", track, TRACKS)
    if track == "map":
        return MAP
    return load_track(track)


def orbit(track: str, params: Params, tau0: float, sdot0: float, n_impacts: int, s0: float | None = None,
          **options) -> ImpactSequence:
    """Orbit of ``n_impacts`` impacts after impact 0 on the chosen track (:meth:`Track.orbit`, or the
    certified track: one of :data:`ORBIT_TRACKS`); every track takes ``progress=``
    (:mod:`gear_rattle.core.progress`), the numerical ones their solver options, the certified one
    :data:`mapimpl.certified.track.TRACK_OPTIONS`.  ``TypeError`` when ``params`` is not a :class:`Params`;
    ``ValueError``/``TypeError`` naming the argument for a bad start or count (:mod:`core.checks`:
    ``0 <= n_impacts <= MAX_IMPACTS``, 1e7), before any track is loaded."""
    check_choice("track", track, ORBIT_TRACKS)
    check_params(params)
    check_int("n_impacts", n_impacts, 0, MAX_IMPACTS)
    check_start(tau0, sdot0, s0)
    if track == "certified":
        from .certified.track import track_orbit

        return track_orbit(params, tau0, sdot0, n_impacts, s0=s0, **options)
    return get(track).orbit(params, tau0, sdot0, n_impacts, s0=s0, **options)


def step_jacobian(track: str, params: Params, tau: float, sdot: float, wall: int | None = None,
                  **options) -> StepJacobian:
    """One impact-to-impact step with its Jacobian on the chosen track (:meth:`Track.step_jacobian`); the
    arguments are checked first (:mod:`core.checks`), naming them."""
    check_choice("track", track, TRACKS)
    check_params(params)
    check_start(tau, sdot, None, ("tau", "sdot"))
    start_wall(wall, sdot)
    return get(track).step_jacobian(params, tau, sdot, wall, **options)


__all__ = ["TRACKS", "ORBIT_TRACKS", "MAP", "get", "orbit", "step_jacobian"]
