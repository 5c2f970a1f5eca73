"""Figures of the report's Section 3: the Fig. 4 and Fig. 8 diagrams with their Lyapunov exponents and the
located points marked, the crisis laws (mean times against the distance to r1 and alpha1 with the GOY
fits), and the laminar-length law of type-I intermittency above r2."""

from __future__ import annotations

import numpy as np

from .base import legend_outside, params_text, subplots


def diagram_lyapunov_figure(dl, fig: str, marks=()):
    """``fig`` (e.g. ``"Fig. 4"``) reproduced: (a) the diagram of ``dl.diagram``, (b) the two Lyapunov
    exponents of ``dl.lyapunov`` (a :class:`~gear_rattle.validation.dynamics.bifurcation.DiagramLyapunov`),
    dashed lines at ``marks`` (``(name, value)``)."""
    d, lam = dl.diagram, dl.lyapunov
    f, ax = subplots(2, 1, figsize=(8.8, 6.5), sharex=True)
    vv = np.repeat(d.values, d.sdot.shape[1]) if d.sdot.ndim == 2 else d.values
    ax[0].plot(vv, np.ravel(d.sdot), ",", color="k", alpha=0.6)
    ax[0].set_ylabel(r"$\dot s_n$")
    ax[1].plot(lam.values, lam.lam_free[:, 0], lw=0.8, label=r"$\lambda_1$")
    ax[1].plot(lam.values, lam.lam_free[:, 1], lw=0.8, label=r"$\lambda_2$")
    ax[1].axhline(0, color="0.5", lw=0.5)
    ax[1].set_ylabel("Lyapunov exponents")
    ax[1].set_xlabel(d.param)
    legend_outside(ax[1])
    for name, val in marks:
        for a in ax:
            a.axvline(val, color="C3", lw=0.6, ls="--")
        # inside the axes (x in data, y in axes units), clear of the title above
        ax[0].text(
            val,
            0.97,
            f" {name}",
            transform=ax[0].get_xaxis_transform(),
            color="C3",
            fontsize=8,
            ha="left",
            va="top",
            bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 1},
        )
    ax[0].set_title(
        f"{fig} reproduced (computed): {params_text(d.base, d.param, d.values)}, {d.transient} impacts discarded",
        fontsize=9,
    )
    f.tight_layout()
    return f


def _crisis_panel(axis, res, key: str, rows: list, name: str) -> None:
    mu_c = res.goy
    side = -1.0 if key == "r1" else 1.0
    x = np.array([side * (row_[name] - mu_c) for row_ in rows])
    T = np.array([row_["T"] for row_ in rows], float)
    lo = np.array([row_["lo"] for row_ in rows], float)
    hi = np.array([row_["hi"] for row_ in rows], float)
    ok = (x > 0) & np.isfinite(T)
    axis.errorbar(
        x[ok],
        T[ok],
        yerr=[T[ok] - lo[ok], np.where(np.isfinite(hi[ok]), hi[ok] - T[ok], 0)],
        fmt="o",
        label="measured (95%)",
    )
    cens = (x > 0) & ~np.isfinite(T)
    if cens.any():
        axis.plot(x[cens], lo[cens], "^", label="no event: lower bound (95%)")
    if ok.any():
        xx = np.geomspace(x[ok].min(), x[ok].max(), 50)
        fit = res.fit_goy
        axis.plot(xx, np.exp(fit.log_C) * xx ** (-fit.g), "-", label=f"GOY fit, g = {fit.g:.3f}")
    axis.set_xscale("log")
    axis.set_yscale("log")
    axis.set_xlabel("r1 - r" if key == "r1" else "alpha - alpha1")
    axis.set_ylabel("mean time (impacts)")
    axis.set_title(
        f"GOY fit {key} = {mu_c:.7g} +- {res.goy_err:.1g}; reported {res.value:.7g} +- {res.err:.1g}",
        fontsize=8,
    )
    axis.legend(fontsize=7)


def crisis_laws_figure(r1, a1):
    """Mean time between band hops (r1, an :class:`~gear_rattle.validation.dynamics.crises.R1Result`) and
    mean escape time (alpha1, an :class:`~gear_rattle.validation.dynamics.crises.Alpha1Result`) with their
    95% intervals and the GOY fits, against the distance to the fitted crisis."""
    f, ax = subplots(1, 2, figsize=(10, 4))
    _crisis_panel(ax[0], r1, "r1", r1.hops, "r")
    _crisis_panel(ax[1], a1, "alpha1", a1.lifetimes, "alpha")
    f.tight_layout()
    return f


def laminar_law_figure(r2, theory: float):
    """Type-I intermittency above r2 (an :class:`~gear_rattle.validation.dynamics.crises.R2Result`): the mean
    laminar length against r - r2, the fitted power law and the theory's slope through the first point."""
    dr, ls = np.asarray(r2.dr, float), r2.laminar
    fg, ax = subplots(figsize=(5.5, 4))
    ax.errorbar(dr, ls.mean, yerr=ls.sem, fmt="o")
    xx = np.array([dr.min(), dr.max()])
    k = np.exp(np.mean(np.log(ls.mean) - r2.slope * np.log(dr)))
    ax.plot(xx, k * xx**r2.slope, "-", label=f"fit: slope {r2.slope:.3f} +- {r2.slope_err:.3f}")
    ax.plot(xx, ls.mean[0] * (xx / dr[0]) ** theory, ":", label=f"slope {theory:g} (theory) through the first point")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("r - r2")
    ax.set_ylabel("mean laminar length (impacts)")
    ax.legend(fontsize=8)
    fg.tight_layout()
    return fg


__all__ = [
    "diagram_lyapunov_figure",
    "crisis_laws_figure",
    "laminar_law_figure",
]
