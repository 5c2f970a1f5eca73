"""The paper's two parameter scans (Figs. 4 and 8) as the report draws them, and the transients
discarded before the time series of Figs. 5-7.  Run sizes: :mod:`validation.profiles`."""

from __future__ import annotations

from ...core.params import Params
from ..paper import PAPER_SCANS

#: The paper's scans (:data:`validation.paper.PAPER_SCANS`) as ``(parameter, lo, hi, base parameters)``.
SCANS = {k: (s.param, s.lo, s.hi, Params(*s.fixed)) for k, s in PAPER_SCANS.items()}
#: Transient discarded before the time series of Figs. 5-7 (Fig. 5 shows the approach from the start).
TS_TRANSIENT = {"fig5": 0, "fig6": 2000, "fig7": 2000}


__all__ = [
    "SCANS",
    "TS_TRANSIENT",
]
