"""One entry point for every track: ``orbit(track, params, tau0, sdot0, n_impacts, s0=None)``.

``map`` is the closed form (:mod:`mapimpl`); ``scipy`` and ``diffrax`` integrate Eq. (3)
numerically (:mod:`reference`).  All return :class:`mapimpl.orbit.ImpactSequence`.
"""

from __future__ import annotations

import importlib

from ..mapimpl.orbit import ImpactSequence, map_orbit
from ..mapimpl.params import Params

TRACKS = ("map", "scipy", "diffrax")
_MODULES = {"scipy": "gear_rattle.reference.scipy_track", "diffrax": "gear_rattle.reference.diffrax_track"}


def orbit(track: str, params: Params, tau0: float, sdot0: float, n_impacts: int, s0: float | None = None,
          **kwargs) -> ImpactSequence:
    """Orbit of ``n_impacts`` impacts after impact 0 on the chosen track."""
    if track not in TRACKS:
        raise ValueError(f"track={track!r} is out of range: allowed one of {', '.join(TRACKS)}")
    if track == "map":
        return map_orbit(params, tau0, sdot0, n_impacts, s0=s0)
    mod = importlib.import_module(_MODULES[track])
    return mod.orbit(params, tau0, sdot0, n_impacts, s0=s0, **kwargs)
