"""Parameter-plane atlas (beyond the paper): the largest Lyapunov exponent and the period of the attractor
over a grid of (alpha, r) at fixed beta, gamma, computed in tiles on Dask and stored in Zarr.

Modules: :mod:`.spec` (what is computed: :class:`AtlasSpec`), :mod:`.compute` (the one compute seam,
:func:`compute_tile`), :mod:`.store` (the Zarr layout, resume), :mod:`.run` (tiles on Dask or in-process:
:func:`run_atlas`), :mod:`.summary` (the numbers; the figure is drawn by
:mod:`gear_rattle.validation.plots.atlas`).  ``compute`` and ``spec`` need only the core dependencies; ``store`` and ``run`` need the ``atlas`` extra (zarr, dask[distributed]),
imported when used.  See docs/atlas.md.
"""

from .compute import ENGINE, FIELDS, compute_tile
from .spec import PAPER_LINES, AtlasSpec

__all__ = ["AtlasSpec", "PAPER_LINES", "ENGINE", "FIELDS", "compute_tile"]
