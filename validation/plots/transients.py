"""Figures of Section 4: the transient basins (Fig. 9), the uncertain fraction (Fig. 10) and the survival
curve with the Eq. (14) fit (Fig. 11), drawn from the results of
:mod:`gear_rattle.validation.transient.experiments`."""

from __future__ import annotations

import numpy as np
from matplotlib.patches import Rectangle

from ...core.paper import PAPER_BOX
from ...mapimpl.engine.t_post import decimal_params
from ..paper import PAPER
from ..transient.results import paper_setting
from .base import params_text, subplots


#: The title's line where the parameters are not the paper's (Figs. 9-11).
NO_COMPARISON = "not the paper's parameters: no comparison with the paper"


def _paper_line(res, paper: str | None = None) -> str:
    """The title's line about the paper: ``paper`` (the paper's values as text; None: nothing to show) where
    ``res.params`` are the paper's (:func:`~gear_rattle.validation.transient.results.paper_setting`), else
    :data:`NO_COMPARISON`, in parentheses on a line of its own."""
    text = paper if paper_setting(res.params) else NO_COMPARISON
    return f"\n({text})" if text else ""


def basins_figure(res):
    """Fig. 9: one panel per threshold n (black = duration < n), the paper's box of Figs. 10-11 in red
    (a :class:`~gear_rattle.validation.transient.results.BasinsResult`)."""
    fig, axs = subplots(2, 2, figsize=(9, 7), sharex=True, sharey=True)
    for ax, n, lab in zip(axs.ravel(), res.ns, "abcd"):
        ax.imshow(
            res.duration < n,
            origin="lower",
            extent=res.window,
            aspect="auto",
            cmap="Greys",
            vmin=0,
            vmax=1,
            interpolation="nearest",
        )
        ax.add_patch(
            Rectangle(
                (PAPER_BOX[0], PAPER_BOX[2]),
                PAPER_BOX[1] - PAPER_BOX[0],
                PAPER_BOX[3] - PAPER_BOX[2],
                fill=False,
                ec="C3",
                lw=1,
            )
        )
        ax.set_title(f"({lab}) n = {n}: black = duration < n ({100 * res.short_fraction[n]:.1f}%)", fontsize=9)
    for ax in axs[1]:
        ax.set_xlabel(r"$\tau_0$")
    for ax in axs[:, 0]:
        ax.set_ylabel(r"$\dot s_0$")
    fig.suptitle(
        f"Fig. 9: transient basins, {params_text(res.params)}, {res.nx}x{res.ny}, delta={res.delta:g}, "
        f"IC {res.ic_mode}{_paper_line(res)}",
        fontsize=10,
    )
    fig.tight_layout()
    return fig


def uncertainty_figure(res):
    """Fig. 10: f(eps) per threshold n with binomial error bars and the fitted power laws (a
    :class:`~gear_rattle.validation.transient.results.UncertaintyResult`)."""
    eps = res.eps
    fig, ax = subplots(figsize=(6, 4.5))
    for n, mk in zip(res.ns, ("s", "o", "^", "v")):
        f = res.fraction(n)
        se = np.sqrt(f * (1.0 - f) / res.n_points)  # binomial standard error of each f(eps)
        pos = f > 0
        lo = np.minimum(se, 0.999 * f)  # keep the lower bar on the log axis
        eb = ax.errorbar(
            eps[pos],
            f[pos],
            yerr=[lo[pos], se[pos]],
            fmt=mk,
            mfc="none" if mk == "s" else None,
            capsize=2,
            label=f"n = {n} (bars: sqrt(f(1-f)/{res.n_points}))",
        )
        ft = res.fits[n]
        if ft is not None:
            ax.loglog(
                eps,
                10**ft.log10_C * eps**ft.phi,
                "-",
                lw=0.8,
                color=eb[0].get_color(),
                label=f"fit: phi = {ft.phi:.4f} +- {ft.phi_se_ls:.4f} (boot {ft.phi_se_boot:.4f})",
            )
    ax.set_xscale("log")
    if any(np.any(res.fraction(n) > 0) for n in res.ns):
        ax.set_yscale("log")
    else:  # no uncertain point at any eps: nothing to draw on a log axis
        ax.text(0.5, 0.5, "no uncertain points (f = 0 at every eps)", transform=ax.transAxes, ha="center")
    ax.set_xlabel(r"$\epsilon$")
    ax.set_ylabel(r"$f(\epsilon)$")
    ax.set_title(
        f"Fig. 10: uncertain fraction, {params_text(res.params)},\n{res.n_points} points in the paper's box"
        f"{_paper_line(res)}",
        fontsize=10,
    )
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def survival_figure(res):
    """Fig. 11: N(n) at the main delta and the Eq. (14) fit over its range (a
    :class:`~gear_rattle.validation.transient.results.SurvivalResult`); the title names the parameters
    and gives the paper's values only where the parameters are the paper's."""
    n, N, main = res.n, res.N, res.main_fit
    fig, ax = subplots(figsize=(6, 4.5))
    ax.semilogy(n, np.where(N > 0, N, np.nan), "-", lw=1, label=f"N(n), delta = {res.delta:g}")
    if main is not None:
        xs = np.array([main.n_lo, main.n_hi])
        ax.semilogy(
            xs,
            main.N0 * np.exp(-main.kappa * xs / main.mean_n),
            "k--",
            lw=1,
            label=f"Eq. (14): <n> = {main.mean_n:.0f}, kappa = {main.kappa:.3f} +- {main.kappa_se_boot:.3f}",
        )
    ax.set_xlabel("n")
    ax.set_ylabel("N(n): orbits still transient")
    named = ", ".join(f"{k} = {v}" for k, v in decimal_params(res.params).items())
    paper = _paper_line(res, f"paper: <n> = {PAPER['mean_n'].printed}, kappa = {PAPER['kappa'].printed}")
    ax.set_title(
        f"Fig. 11: {named}\n{res.nx}x{res.ny} mesh, cap {res.cap}, IC {res.ic_mode}, T_post {res.release.value}{paper}",
        fontsize=9,
    )
    ax.legend(fontsize=8, loc="upper right")  # N(n) falls from the upper left: the upper right is empty
    fig.tight_layout()
    return fig


__all__ = [
    "NO_COMPARISON",
    "basins_figure",
    "uncertainty_figure",
    "survival_figure",
]
