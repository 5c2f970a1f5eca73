"""Time series of Figs. 5, 6 and 7: the discrete velocity ``sdot_n`` just before each impact and the
stroboscopic velocity ``sdot(2 pi k)`` sampled once per driving period.

The stroboscopic value needs the flight state at ``tau = 2 pi k``: it is the closed-form flight
(:func:`mapimpl.flight.flight`, Eqs. 7-8) from the last event before ``2 pi k`` -- the post-impact state
``(tau_n, -r sdot_n)`` of the last impact, or the release ``(tau_rel, 0)`` after a sticking episode
(and ``0`` while the tooth sticks).

Figure parameters (alpha = 3, beta = gamma = 0.1), as the paper's captions give them: Fig. 5
``r = 0.82144`` ("≳ r2"), Fig. 6 ``r = 0.82145`` ("≳ r2"), Fig. 7 ``r = 0.74001`` ("≲ r1").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...core import jax_config  # noqa: F401
import jax.numpy as jnp

from ...mapimpl.flight import flight
from ...core.phase import TWO_PI
from ...mapimpl.orbit import map_orbit
from ...core.results import ImpactSequence
from ...core.params import Params
from ...core.checks import MAX_IMPACTS, check_int
from ..paper import PAPER

#: r values of the time-series figures (alpha = 3, beta = gamma = 0.1).
FIGURE_R = {"fig5": float(PAPER["r2"].value), "fig6": float(PAPER["r2_fig6"].value), "fig7": float(PAPER["r1"].value)}
_TP = float(TWO_PI)


@dataclass
class TimeSeries:
    """``n``, ``sdot_n`` (discrete), ``k``, ``sdot_strobe`` (at tau = 2 pi k)."""

    params: Params
    n: np.ndarray
    sdot_n: np.ndarray
    k: np.ndarray
    sdot_strobe: np.ndarray

    def arrays(self) -> dict:
        """The arrays of the series' NPZ file."""
        p = self.params
        return dict(n=self.n, sdot_n=self.sdot_n, k=self.k, sdot_strobe=self.sdot_strobe, **p.as_dict())

    def table(self) -> tuple[list, list]:
        """``(header, rows)`` of the series' CSV: ``n, sdot_n`` beside ``k, sdot_strobe`` (the shorter
        column pair padded with empty fields)."""
        m = max(self.n.size, self.k.size)
        rows = []
        for i in range(m):
            a = [self.n[i], float(self.sdot_n[i])] if i < self.n.size else [None, None]
            b = [self.k[i], float(self.sdot_strobe[i])] if i < self.k.size else [None, None]
            rows.append(a + b)
        return ["n", "sdot_n", "k", "sdot_strobe"], rows


def stroboscopic(seq: ImpactSequence) -> tuple[np.ndarray, np.ndarray]:
    """``(k, sdot(2 pi k))`` for every whole period ``2 pi k`` inside the orbit's time span."""
    p = seq.params
    t = seq.tau
    if t.size < 2:
        raise ValueError("the orbit needs at least 2 events for a stroboscopic sample")
    k = np.arange(int(np.ceil(t[0] / _TP)), int(np.floor(t[-1] / _TP)) + 1)
    tk = k * _TP
    j = np.searchsorted(t, tk, side="right") - 1  # last event at or before 2 pi k
    kind = seq.kind[j]
    # post-event initial velocity: impact -> -r sdot; release -> 0; stick -> stays on the wall (0)
    v0 = np.where(kind == "impact", -p.r * np.nan_to_num(seq.sdot[j]), 0.0)
    dt = tk - t[j]
    fp = flight(jnp.asarray(dt), jnp.asarray(np.mod(t[j], _TP)), jnp.asarray(v0), p.alpha, p.beta, p.gamma)
    v = np.where(kind == "stick", 0.0, np.asarray(fp.v))
    return k, v


def time_series(
    params: Params, n_impacts: int = 3000, transient: int = 2000, tau0: float = 0.0, sdot0: float = 0.5, progress=False
) -> TimeSeries:
    """Discrete and stroboscopic velocity series after ``transient`` impacts (n counted after it);
    ``progress``: see :func:`gear_rattle.mapimpl.orbit.map_orbit`."""
    check_int("n_impacts", n_impacts, 2, MAX_IMPACTS)
    check_int("transient", transient, 0, MAX_IMPACTS)
    seq = map_orbit(params, tau0, sdot0, int(n_impacts) + int(transient), progress=progress)
    keep = seq.n >= int(transient)
    sub = ImpactSequence(
        params,
        seq.n[keep] - int(transient),
        seq.tau[keep],
        seq.theta[keep],
        seq.wall[keep],
        seq.sdot[keep],
        seq.kind[keep],
        seq.status,
    )
    k, v = stroboscopic(sub)
    m = sub.kind == "impact"
    return TimeSeries(params, sub.n[m], sub.sdot[m], k - k[0] if k.size else k, v)  # no sample: span < 2 pi


__all__ = [
    "FIGURE_R",
    "TimeSeries",
    "stroboscopic",
    "time_series",
]
