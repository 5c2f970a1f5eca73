"""Figures of single orbits and parameter scans: the time series of Figs. 2-3 and Figs. 5-7, a
bifurcation diagram (Figs. 4a, 8a) with its Lyapunov exponents (Figs. 4b, 8b), and a continued branch of
periodic orbits.  Each function returns a :class:`matplotlib.figure.Figure`; callers save it."""

from __future__ import annotations

import numpy as np

from ...core.results import ImpactSequence
from ...mapimpl.dense import dense
from .base import legend_outside, params_text, subplots


def time_series_figure(seq: ImpactSequence, span: float = 50.0, title: str | None = None):
    """Figs. 2 and 3 of the paper: (a) the driven gear in absolute coordinates between the two tooth
    flanks of the driving gear; (b) the relative coordinate s(tau) with the impacts marked.

    Returns the :class:`matplotlib.figure.Figure`.  The normalised absolute angle is
    ``(R/v) phi = alpha sin(tau) - s`` (Eq. 2); the driving gear's
    flanks are at ``alpha sin(tau)`` (``s = 0``) and ``alpha sin(tau) + 1`` (``s = -1``).
    """
    p = seq.params
    t_end = seq.tau[0] + span
    tau, s, _ = dense(seq, points_per_unit=60.0, t_end=t_end)
    keep = tau <= t_end
    tau, s = tau[keep], s[keep]
    drive = p.alpha * np.sin(tau)
    fig, ax = subplots(2, 1, figsize=(9.5, 6), sharex=True)
    ax[0].plot(tau, drive, color="0.5", lw=0.8, label="driving gear flanks")
    ax[0].plot(tau, drive + 1.0, color="0.5", lw=0.8)
    ax[0].plot(tau, drive - s, color="C0", lw=1.0, label="driven gear")
    ax[0].set_ylabel(r"$(R/v)\,\varphi$")
    legend_outside(ax[0])
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
    legend_outside(ax[1])
    fig.tight_layout()
    return fig


def velocity_series_figure(ts, title: str | None = None):
    """Figs. 5-7: (a) ``sdot_n`` against ``n``, (b) the stroboscopic ``sdot(2 pi k)`` against ``k`` (a
    :class:`~gear_rattle.validation.dynamics.timeseries.TimeSeries`)."""
    fig, ax = subplots(2, 1, figsize=(7, 5))
    ax[0].plot(ts.n, ts.sdot_n, ".k", ms=1)
    ax[0].set_xlabel("n")
    ax[0].set_ylabel(r"$\dot s_n$")
    ax[1].plot(ts.k, ts.sdot_strobe, ".k", ms=1)
    ax[1].set_xlabel("k")
    ax[1].set_ylabel(r"$\dot s(2\pi k)$")
    ax[0].set_title(title or params_text(ts.params))
    fig.tight_layout()
    return fig


def diagram_figure(diag, lyap=None, title: str | None = None):
    """A bifurcation diagram (a :class:`~gear_rattle.validation.dynamics.bifurcation.Diagram`) and, if
    given, the Lyapunov exponents ``(values, lambdas (n, 2))`` below it (Figs. 4, 8).  The default title
    names every parameter, the swept one by its range (:func:`.base.params_text`)."""
    rows = 2 if lyap is not None else 1
    fig, axes = subplots(rows, 1, figsize=(7, 3.2 * rows + 0.5), sharex=True, squeeze=False)
    ax = axes[0, 0]
    x = np.repeat(diag.values, diag.sdot.shape[1])
    ax.plot(x, diag.sdot.ravel(), ",k", alpha=0.5)
    ax.set_ylabel(r"$\dot s_n$")
    ax.set_title(
        title
        or f"bifurcation diagram ({diag.mode}): {params_text(diag.base, diag.param, diag.values)}\n"
        f"{diag.transient} impacts discarded, {diag.keep} recorded",
        fontsize=9,
    )
    if lyap is not None:
        v, lam = lyap
        axes[1, 0].plot(v, lam[:, 0], "-", lw=0.8, label=r"$\lambda_1$")
        axes[1, 0].plot(v, lam[:, 1], "-", lw=0.8, label=r"$\lambda_2$")
        axes[1, 0].axhline(0, color="gray", lw=0.5)
        axes[1, 0].set_ylabel("Lyapunov exponents (per impact)")
        legend_outside(axes[1, 0])
    axes[-1, 0].set_xlabel(diag.param)
    fig.tight_layout()
    return fig


def lyapunov_figure(values, lam, param: str, title: str | None = None):
    """The two Lyapunov exponents ``lam (n, 2)`` against the parameter ``param`` (Figs. 4b, 8b); ``title``
    (the command's names every parameter, :func:`.base.params_text`)."""
    fig, ax = subplots(figsize=(7, 3.5))
    if title:
        ax.set_title(title, fontsize=9)
    ax.plot(values, lam[:, 0], "-", label=r"$\lambda_1$")
    ax.plot(values, lam[:, 1], "-", label=r"$\lambda_2$")
    ax.axhline(0, color="gray", lw=0.5)
    ax.set_xlabel(param)
    ax.set_ylabel("per impact")
    legend_outside(ax)
    fig.tight_layout()
    return fig


def branch_figure(branch, param: str, title: str | None = None):
    """A continued branch of periodic orbits (a :class:`~gear_rattle.mapimpl.continuation.Branch`):
    one point's ``sdot`` (stable / unstable) and the moduli of the Floquet multipliers, fold (green) and
    flip (magenta) points marked."""
    a = branch.arrays()
    fig, ax = subplots(2, 1, figsize=(7, 5), sharex=True)
    st = a["stable"]
    ax[0].plot(a["mu"], a["sdot"], "-", color="gray", lw=0.6)
    ax[0].plot(a["mu"][st], a["sdot"][st], ".b", ms=3, label="stable")
    ax[0].plot(a["mu"][~st], a["sdot"][~st], ".r", ms=3, label="unstable")
    ax[0].set_ylabel(r"$\dot s$ (one point of the orbit)")
    legend_outside(ax[0])
    mods = np.abs(a["mult_re"] + 1j * a["mult_im"])
    ax[1].semilogy(a["mu"], mods, ".", ms=3)
    ax[1].axhline(1, color="k", lw=0.5)
    for f in branch.folds + branch.flips:
        for x in ax:
            x.axvline(f.mu, color="g" if f.kind == "fold" else "m", lw=0.6)
    ax[1].set_ylabel("|Floquet multipliers|")
    ax[1].set_xlabel(param)
    ax[0].set_title(
        title
        or f"{branch.impacts}-impact orbit in {branch.turns} driving period(s), {param} continued; "
        f"start: {params_text(branch.params)}",
        fontsize=9,
    )
    fig.tight_layout()
    return fig


__all__ = [
    "time_series_figure",
    "velocity_series_figure",
    "diagram_figure",
    "lyapunov_figure",
    "branch_figure",
]
