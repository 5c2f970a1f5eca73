"""Regular and chaotic rattling (Figs. 2-3): the orbit from (tau0, sdot0) = (0, 0.5) at one alpha, the
period of its impact velocities, its Lyapunov exponents and, when periodic, the periodic orbit found by
Newton -- and the verdict: ``regular`` (a period and lambda1 < 0), ``chaotic`` (no period and
lambda1 > 0) or ``undetermined``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...core.params import Params
from ...core.results import ImpactSequence
from ..profiles import get_profile

if TYPE_CHECKING:  # the library is imported where the orbit is computed, not on import
    from ...mapimpl.periodic import PeriodicOrbit

#: Periodicity test: the last TAIL impact velocities repeat with a period <= MAX_PERIOD to PERIOD_ATOL.
TAIL, MAX_PERIOD, PERIOD_ATOL = 120, 12, 1e-9
#: Impacts discarded before the Lyapunov average.
LYAP_TRANSIENT = 1000
#: The initial state of Figs. 2-3.
START = (0.0, 0.5)


def velocity_period(sd: np.ndarray, max_p: int = MAX_PERIOD, atol: float = PERIOD_ATOL) -> int | None:
    """Smallest p <= max_p with ``sd`` repeating after p entries to ``atol`` (None: none)."""
    for p in range(1, max_p + 1):
        if np.allclose(sd[p:], sd[:-p], atol=atol):
            return p
    return None


@dataclass
class Motion:
    """The orbit ``seq`` at ``params``: ``period`` of its last TAIL impact velocities (None: none up to
    MAX_PERIOD) and the driving periods ``turns`` it spans, ``lam1``, ``lam2`` (QR, ``lyap_n`` impacts),
    ``det_mean`` (mean ln|det J|), ``orbit`` (the periodic orbit by Newton, or None) and ``kind``."""

    params: Params
    seq: ImpactSequence
    period: int | None
    turns: int | None
    lam1: float
    lam2: float
    det_mean: float
    lyap_n: int
    orbit: PeriodicOrbit | None

    @property
    def kind(self) -> str:
        if self.period is not None and self.lam1 < 0:
            return "regular"
        if self.period is None and self.lam1 > 0:
            return "chaotic"
        return "undetermined"

    @property
    def sum_error(self) -> float:
        """``|lambda1 + lambda2 - mean ln|det J||`` (the closed-form sum rule)."""
        return abs(self.lam1 + self.lam2 - self.det_mean)


def motion(params: Params, profile: str = "quick") -> Motion:
    """The orbit of Figs. 2-3 at ``params`` and its verdict (module docstring); run sizes: ``motion`` of
    :data:`gear_rattle.validation.profiles.PROFILES`."""
    from ...mapimpl.lyapunov import lyapunov
    from ...mapimpl.orbit import map_orbit
    from ...mapimpl.periodic import find_periodic

    size = get_profile(profile, "motion")
    seq = map_orbit(params, START[0], START[1], size["impacts"])
    tau, theta, sd, _ = seq.impact_arrays()
    per = velocity_period(sd[-TAIL:], MAX_PERIOD)
    lam = lyapunov(params, "alpha", [params.alpha], n_impacts=size["lyap_n"], transient=LYAP_TRANSIENT)
    l1, l2 = (float(x) for x in lam.lam[0])
    po = turns = None
    if per:
        po = find_periodic(params, theta[-per], sd[-per], per)
        turns = round((tau[-1] - tau[-1 - per]) / (2 * np.pi))
    return Motion(params, seq, per, turns, l1, l2, float(lam.det_mean[0]), size["lyap_n"], po)


__all__ = [
    "TAIL",
    "MAX_PERIOD",
    "PERIOD_ATOL",
    "LYAP_TRANSIENT",
    "START",
    "velocity_period",
    "Motion",
    "motion",
]
