"""Intermittency (r2), interior crisis (r1) and boundary crisis (alpha1): the sudden changes of
Section 3 and Fig. 8 of the paper, located with error bars on the many-orbit engine.

* :func:`locate_r2` (:mod:`.r2`): fold of the 6-impact period-1 orbit at alpha = 3 (continuation) and
  the type-I intermittency exponent of the mean laminar length above it (Laminar observer);
* :func:`locate_r1` (:mod:`.r1`): interior crisis at alpha = 3 from the mean time between band hops
  (BandEscape observer, counting mode): GOY and free fits, and a bracket by direct observation;
* :func:`locate_alpha1` (:mod:`.alpha1`): boundary crisis at r = 0.9 from escape times of the
  pre-crisis chaotic set to the stable 4-impact orbit (Capture observer): GOY and free fits, the
  fit-range systematic, a bracket, and where the paper's 1.24370 sits.

The statistics (censored maximum likelihood, exact intervals, the crisis-law fits, the GOY exponent,
brackets) are in :mod:`.stats`, the typed results in :mod:`.results`, the periodic orbits and the engine
wrapper in :mod:`.orbits`, the run sizes in :mod:`validation.profiles`.  Methods and results: docs/dynamics.md.
"""

from .alpha1 import PAPER_ALPHA1, locate_alpha1
from ....mapimpl.branches import (
    ALPHA1_START,
    R2_START,
    attractor_point,
    four_impact_branch,
    orbit_on_branch,
    six_impact_branch,
)
from .r1 import PAPER_R1_FIG7, locate_r1
from .r2 import PAPER_R2_FIG5, LaminarStats, laminar_statistics, locate_r2
from .results import Alpha1Result, CrisisResult, R1Result, R2Result
from .stats import (
    Bracket,
    CrisisFit,
    Located,
    MeanTime,
    bracket,
    locate,
    censored_lifetimes,
    fit_crisis,
    fit_crisis_fixed,
    fit_power_law,
    goy_exponent,
    lifetime_lower_bound,
    mean_time,
    range_systematic,
)

__all__ = [
    "locate_r2",
    "locate_r1",
    "locate_alpha1",
    "R2Result",
    "CrisisResult",
    "R1Result",
    "Alpha1Result",
    "PAPER_R2_FIG5",
    "PAPER_R1_FIG7",
    "PAPER_ALPHA1",
    "attractor_point",
    "six_impact_branch",
    "four_impact_branch",
    "orbit_on_branch",
    "R2_START",
    "ALPHA1_START",
    "LaminarStats",
    "laminar_statistics",
    "MeanTime",
    "CrisisFit",
    "Bracket",
    "mean_time",
    "censored_lifetimes",
    "lifetime_lower_bound",
    "fit_crisis",
    "fit_crisis_fixed",
    "range_systematic",
    "fit_power_law",
    "goy_exponent",
    "bracket",
    "Located",
    "locate",
]
