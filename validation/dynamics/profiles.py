"""Run sizes of the Section 3 analyses outside the crises (Figs. 4-8: diagrams with Lyapunov exponents,
time series, settling runs) per profile, and the paper's two parameter scans.  The crisis analyses
(r2, r1, alpha1) have theirs in :mod:`.crises.profiles`.

* ``fig4_values``, ``fig8_values``: parameter values of the Fig. 4 and Fig. 8 diagrams; ``transient``
  impacts discarded and ``keep`` recorded per value; ``lyap_n``: impacts of each Lyapunov exponent;
* ``ts_n``: impacts of each Figs. 5-7 time series (after :data:`TS_TRANSIENT`);
* ``settle_ics`` orbits of ``settle_n`` impacts for each settling run (:func:`.settling.settle`).
"""

from __future__ import annotations

from ...core.params import Params
from ..paper import PAPER_SCANS

#: The paper's scans (:data:`validation.paper.PAPER_SCANS`) as ``(parameter, lo, hi, base parameters)``.
SCANS = {k: (s.param, s.lo, s.hi, Params(*s.fixed)) for k, s in PAPER_SCANS.items()}
#: Transient discarded before the time series of Figs. 5-7 (Fig. 5 shows the approach from the start).
TS_TRANSIENT = {"fig5": 0, "fig6": 2000, "fig7": 2000}

PROFILES = {
    "quick": {"fig4_values": 120, "fig8_values": 120, "transient": 1000, "keep": 150, "lyap_n": 4000,
              "ts_n": 1500, "settle_ics": 8, "settle_n": 20000},
    "paper": {"fig4_values": 600, "fig8_values": 600, "transient": 5000, "keep": 400, "lyap_n": 20000,
              "ts_n": 4000, "settle_ics": 32, "settle_n": 100000},
}


def get_profile(profile: str) -> dict:
    """The run sizes of ``profile`` (a copy); ``ValueError`` for an unknown profile."""
    if profile not in PROFILES:
        raise ValueError(f"profile={profile!r} is out of range: allowed one of {', '.join(PROFILES)}")
    return dict(PROFILES[profile])
