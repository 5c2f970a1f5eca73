"""Figures: the paper's Figs. 2-3 time series of an orbit."""

from __future__ import annotations

import numpy as np

from ..mapimpl.dense import dense
from ..core.results import ImpactSequence
from .figures import subplots


def time_series_figure(seq: ImpactSequence, span: float = 50.0, title: str | None = None):
    """Figs. 2 and 3 of the paper: (a) the driven gear in absolute coordinates between the two tooth
    flanks of the driving gear; (b) the relative coordinate s(tau) with the impacts marked.

    Returns the :class:`matplotlib.figure.Figure`.  The normalised absolute angle is ``(R/v) phi = alpha sin(tau) - s`` (Eq. 2); the driving gear's
    flanks are at ``alpha sin(tau)`` (``s = 0``) and ``alpha sin(tau) + 1`` (``s = -1``).
    """
    p = seq.params
    t_end = seq.tau[0] + span
    tau, s, _ = dense(seq, points_per_unit=60.0, t_end=t_end)
    keep = tau <= t_end
    tau, s = tau[keep], s[keep]
    drive = p.alpha * np.sin(tau)
    fig, ax = subplots(2, 1, figsize=(8, 6), sharex=True)
    ax[0].plot(tau, drive, color="0.5", lw=0.8, label="driving gear flanks")
    ax[0].plot(tau, drive + 1.0, color="0.5", lw=0.8)
    ax[0].plot(tau, drive - s, color="C0", lw=1.0, label="driven gear")
    ax[0].set_ylabel(r"$(R/v)\,\varphi$")
    ax[0].legend(loc="upper right", fontsize=8)
    ax[0].set_title(title or f"alpha={p.alpha:g} beta={p.beta:g} gamma={p.gamma:g} r={p.r:g} ({seq.track} track)")
    ax[1].plot(tau, s, color="C0", lw=1.0)
    m = seq.impacts & (seq.tau <= t_end)
    ax[1].plot(seq.tau[m], seq.wall[m], "o", ms=3, color="C3", label="impacts")
    st = (seq.kind == "stick") & (seq.tau <= t_end)
    if np.any(st):
        ax[1].plot(seq.tau[st], seq.wall[st], "s", ms=4, color="C2", label="stick")
    ax[1].set_ylim(-1.1, 0.1)
    ax[1].set_ylabel("s")
    ax[1].set_xlabel(r"$\tau$")
    ax[1].legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    return fig


def plot_time_series(seq: ImpactSequence, path: str, span: float = 50.0, title: str | None = None) -> None:
    """:func:`time_series_figure` written to ``path`` (format from the extension)."""
    time_series_figure(seq, span, title).savefig(path, dpi=110)
