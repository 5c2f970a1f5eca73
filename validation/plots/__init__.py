"""Every figure of the project, drawn from the analyses' results and returned as a
:class:`matplotlib.figure.Figure` (without pyplot: :func:`.base.subplots`); the commands and the report
save them (:func:`gear_rattle.validation.io.save_figure`).  Modules: :mod:`.orbits` (Figs. 2-3, 4-8
single orbits and scans), :mod:`.dynamics` (the report's Figs. 4 and 8 with the crises, the crisis laws,
the intermittency law), :mod:`.transients` (Figs. 9-11), :mod:`.atlas` (the (alpha, r) atlas)."""

from .base import subplots
from .orbits import branch_figure, diagram_figure, lyapunov_figure, time_series_figure, velocity_series_figure

__all__ = [
    "subplots",
    "branch_figure",
    "diagram_figure",
    "lyapunov_figure",
    "time_series_figure",
    "velocity_series_figure",
]
