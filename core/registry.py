"""Where the numerical tracks are found: the tracks' names (:data:`TRACKS`) and a loader per numerical one.

The registry of tracks (:mod:`gear_rattle.mapimpl.tracks`) sits below the numerical tracks
(:mod:`gear_rattle.reference`), which it may not import (docs/architecture.md).  The layer above both,
the package's facade (``gear_rattle/__init__.py``, which Python runs before any module of the package),
registers one loader per numerical track with :func:`register_track`: a function that imports the
track's module (an import statement that the import contract and tests/test_import_cycles.py see, not a
module name in a string) and returns its ``TRACK``.  The loader runs on the track's first use, so that
diffrax is imported only by a program that uses it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # (core.results imports numpy; this module is imported by ``import gear_rattle``: stdlib only)
    from .results import Track

#: The tracks that compute an orbit: the closed-form map (:mod:`gear_rattle.mapimpl`) and two numerical
#: integrations of Eq. (3) (:mod:`gear_rattle.reference`); :func:`gear_rattle.mapimpl.tracks.get` returns one.
#: (``gear_rattle.core.results.TRACKS`` and ``gear_rattle.TRACKS`` are the same tuple.)
TRACKS = ("map", "scipy", "diffrax")

_LOADERS: dict[str, Callable[[], Track]] = {}


def register_track(name: str, load: Callable[[], Track]) -> None:
    """Register ``load()``, which returns the :class:`~core.results.Track` named ``name`` (one of
    :data:`TRACKS` other than the closed-form ``"map"``); ``ValueError`` for another
    name, ``TypeError`` for a ``load`` that is not callable."""
    if name not in TRACKS or name == "map":
        raise ValueError(f"name={name!r} is out of range: allowed one of {[t for t in TRACKS if t != 'map']}")
    if not callable(load):
        raise TypeError(f"load={load!r} is not callable: allowed a function returning the track")
    _LOADERS[name] = load


def load_track(name: str) -> Track:
    """The registered track ``name``, loaded (``ImportError`` when its integrator is not installed);
    ``LookupError`` when no loader is registered for it (the package's facade registers them)."""
    try:
        load = _LOADERS[name]
    except KeyError:
        raise LookupError(
            f"track {name!r} has no registered loader (gear_rattle/__init__.py registers "
            "the numerical tracks when the package is imported)"
        ) from None
    return load()


def registered_tracks() -> tuple[str, ...]:
    """The names with a registered loader, in the order of :data:`TRACKS`."""
    return tuple(t for t in TRACKS if t in _LOADERS)


__all__ = [
    "TRACKS",
    "register_track",
    "load_track",
    "registered_tracks",
]
