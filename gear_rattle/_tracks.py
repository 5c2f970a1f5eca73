"""The loaders of the numerical tracks (:mod:`gear_rattle.reference`), registered with
:mod:`gear_rattle.core.registry` when the package is imported (``gear_rattle/__init__.py`` imports this
module; Python runs it before any module of the package).

The registry of tracks (:mod:`gear_rattle.mapimpl.tracks`) may not import the layer above it; this
module, above every layer, may.  Each loader imports its track's module when the track is first used
(diffrax is heavy) -- an import statement, which the import contract and tests/test_import_cycles.py
see -- and returns its ``TRACK``.  A new track adds its loader here (docs/architecture.md).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .core.registry import register_track

if TYPE_CHECKING:  # (core.results imports numpy; this module runs on ``import gear_rattle``: no numpy)
    from .core.results import Track


def _scipy() -> Track:
    from .reference import scipy_track

    return scipy_track.TRACK


def _diffrax() -> Track:
    from .reference import diffrax_track

    return diffrax_track.TRACK


register_track("scipy", _scipy)
register_track("diffrax", _diffrax)
