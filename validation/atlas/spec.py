"""What an atlas computes: :class:`AtlasSpec`, the validated grid and method of a parameter-plane atlas.

The grid is ``alpha = linspace(alpha_lo, alpha_hi, n_alpha)`` by ``r = linspace(r_lo, r_hi, n_r)`` at fixed
``beta`` and ``gamma`` (Eqs. 4-6, 11; the paper's plane is beta = gamma = 0.1).  Every point starts from the
same pre-impact state ``(tau0, sdot0)``, discards ``transient`` impacts, averages the largest Lyapunov
exponent over ``impacts`` impacts (QR method, per impact) and then looks for a period in the next
``2 * period_max`` impacts (see :mod:`.compute`).  Arrays are indexed ``[i_r, i_alpha]`` (rows: r).

The spec says everything that determines the numbers of an atlas; it is stored in the Zarr store's
attributes (:meth:`AtlasSpec.to_dict`), and a store made with another spec is refused on resume.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import numpy as np

from ...core.checks import check_int, check_real, check_tau0
from ...core.params import PARAM_MAX, RANGES, check_param
from ..paper import PAPER_SCANS

#: Bounds that keep an atlas finite.
MAX_GRID = 100_000_000
MAX_IMPACTS = 50_000_000
MAX_PERIOD = 1024

#: The paper's scans drawn on the atlas: (label, fixed parameter, value, varied parameter, lo, hi).
#: (:data:`validation.paper.PAPER_SCANS`: Fig. 4 at alpha = 3, Fig. 8 at r = 0.9).
PAPER_LINES = tuple(
    (f"{s.figure} ({fixed} = {value:g})", fixed, value, s.param, s.lo, s.hi)
    for s in PAPER_SCANS.values()
    for fixed, value in [("alpha", s.fixed[0]) if s.param == "r" else ("r", s.fixed[3])]
)


@dataclass(frozen=True)
class AtlasSpec:
    """Grid, fixed parameters, initial condition and measurement lengths of an atlas (validated)."""

    alpha_lo: float = 1.0
    alpha_hi: float = 3.2
    n_alpha: int = 67  # alpha step 1/30 and r step 0.005: alpha = 3 and r = 0.9 (Figs. 4, 8) are grid lines
    r_lo: float = 0.70
    r_hi: float = 0.95
    n_r: int = 51
    beta: float = 0.1
    gamma: float = 0.1
    tau0: float = 0.0
    sdot0: float = 0.5
    transient: int = 1000
    impacts: int = 2000
    period_max: int = 32
    period_tol: float = 1e-6

    def __post_init__(self) -> None:
        s = object.__setattr__
        for name in ("alpha_lo", "alpha_hi"):  # the library's range of alpha (mapimpl.params.PARAM_MAX)
            s(self, name, check_real(name, getattr(self, name), 0.0, PARAM_MAX, allowed=RANGES["alpha"]))
        for name in ("r_lo", "r_hi"):
            s(self, name, check_real(name, getattr(self, name), 0.0, 1.0, lo_open=True, allowed=f"0 < {name} <= 1"))
        s(self, "beta", check_param("beta", self.beta))
        s(self, "gamma", check_param("gamma", self.gamma))
        if self.alpha_lo > self.alpha_hi:
            raise ValueError(
                f"alpha_lo={self.alpha_lo!r}, alpha_hi={self.alpha_hi!r} are out of range: allowed alpha_lo <= alpha_hi"
            )
        if self.r_lo > self.r_hi:
            raise ValueError(f"r_lo={self.r_lo!r}, r_hi={self.r_hi!r} are out of range: allowed r_lo <= r_hi")
        s(self, "n_alpha", check_int("n_alpha", self.n_alpha, 1, MAX_GRID, strict=True))
        s(self, "n_r", check_int("n_r", self.n_r, 1, MAX_GRID, strict=True))
        if self.n_alpha * self.n_r > MAX_GRID:
            raise ValueError(f"n_alpha * n_r = {self.n_alpha * self.n_r} is out of range: allowed <= {MAX_GRID}")
        s(self, "tau0", check_tau0(self.tau0))
        s(self, "sdot0", check_real("sdot0", self.sdot0, nonzero=True, allowed="a finite sdot0 != 0"))
        s(self, "transient", check_int("transient", self.transient, 0, MAX_IMPACTS, strict=True))
        s(self, "impacts", check_int("impacts", self.impacts, 1, MAX_IMPACTS, strict=True))
        s(self, "period_max", check_int("period_max", self.period_max, 1, MAX_PERIOD, strict=True))
        s(
            self,
            "period_tol",
            check_real(
                "period_tol",
                self.period_tol,
                0.0,
                1.0,
                lo_open=True,
                hi_open=True,
                allowed="a period_tol with 0 < period_tol < 1",
            ),
        )

    # grid -------------------------------------------------------------------------------------------
    @property
    def alphas(self) -> np.ndarray:
        """The alpha values (columns), float64."""
        return np.linspace(self.alpha_lo, self.alpha_hi, self.n_alpha)

    @property
    def rs(self) -> np.ndarray:
        """The r values (rows), float64."""
        return np.linspace(self.r_lo, self.r_hi, self.n_r)

    @property
    def shape(self) -> tuple[int, int]:
        """``(n_r, n_alpha)``: the shape of every atlas array."""
        return (self.n_r, self.n_alpha)

    @property
    def window(self) -> int:
        """Impacts recorded after the Lyapunov average to look for a period: ``2 * period_max``."""
        return 2 * self.period_max

    @property
    def impacts_per_point(self) -> int:
        """Map steps run per grid point: transient + Lyapunov average + period window."""
        return self.transient + self.impacts + self.window

    # storage ----------------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """JSON-able dict (floats round-trip exactly through JSON)."""
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> "AtlasSpec":
        """The spec of :meth:`to_dict` (unknown or missing keys are a ValueError)."""
        names = {f.name for f in fields(cls)}
        extra = set(d) - names
        if extra:
            raise ValueError(f"atlas spec has unknown fields {sorted(extra)}: allowed {sorted(names)}")
        return cls(**d)


__all__ = [
    "MAX_GRID",
    "MAX_IMPACTS",
    "MAX_PERIOD",
    "PAPER_LINES",
    "AtlasSpec",
]
