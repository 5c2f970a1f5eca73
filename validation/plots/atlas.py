"""The atlas figure: largest Lyapunov exponent and period over the (alpha, r) plane, with the paper's two
scans drawn as lines (Fig. 4: r-scan at alpha = 3; Fig. 8: alpha-scan at r = 0.9), from an atlas's data
(:func:`gear_rattle.validation.atlas.store.AtlasStore.read`)."""

from __future__ import annotations

import numpy as np

from ..atlas.spec import AtlasSpec
from ..atlas.summary import paper_lines, period_classes
from .base import subplots


def _edges(v: np.ndarray) -> np.ndarray:
    if v.size == 1:
        h = 0.005 * max(1.0, abs(float(v[0])))
        return np.array([v[0] - h, v[0] + h])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def atlas_figure(data: dict[str, np.ndarray], spec: AtlasSpec, title: str | None = None):
    """Two panels over (alpha, r): lambda1 (diverging colours around 0; black: a sticking step, J = 0,
    lambda1 = -inf; grey: orbit ended or not computed) and the period class ``p in m`` (p impacts in m
    driving periods; white: no period found), with the paper's scans as lines where the plane is the paper's."""
    from matplotlib import colormaps, patheffects
    from matplotlib.colors import ListedColormap, TwoSlopeNorm
    from matplotlib.patches import Patch

    xa, yr = _edges(data["alpha"]), _edges(data["r"])
    lam, p, m = data["lambda1"], data["period_p"], data["period_m"]
    fig, (ax1, ax2) = subplots(1, 2, figsize=(13, 5.2))

    fin = lam[np.isfinite(lam)]
    lo = min(float(fin.min()), -1e-3) if fin.size else -1.0
    hi = max(float(fin.max()), 1e-3) if fin.size else 1.0
    cmap = colormaps["RdBu_r"].with_extremes(under="black", bad="0.6")
    shown = np.where(np.isneginf(lam), lo - 1.0, lam)
    im = ax1.pcolormesh(xa, yr, np.ma.masked_invalid(shown), cmap=cmap, norm=TwoSlopeNorm(0.0, lo, hi))
    fig.colorbar(im, ax=ax1, extend="min", label=r"$\lambda_1$ per impact (black: sticking, $-\infty$)")
    ax1.set_title(r"largest Lyapunov exponent $\lambda_1$")

    classes = period_classes(p, m)
    codes = np.zeros(p.shape)  # 0: no period
    for k, (pp, mm, _n) in enumerate(classes, start=1):
        codes[(p == pp) & (m == mm)] = k
    other = (p > 0) & (codes == 0)
    codes[other] = len(classes) + 1
    ended = np.isnan(lam) | (data["status"] != 0)
    codes = np.ma.masked_where(ended, codes)
    tab = colormaps["tab20"]
    colours = ["white"] + [tab(k % 20) for k in range(len(classes))] + ["0.85"]
    pcm = ListedColormap(colours).with_extremes(bad="0.45")
    ax2.pcolormesh(xa, yr, codes, cmap=pcm, vmin=-0.5, vmax=len(colours) - 0.5)
    handles = [Patch(facecolor="white", edgecolor="k", label="no period found")]
    handles += [
        Patch(facecolor=colours[k], edgecolor="k", label=f"{pp} impacts in {mm} period{'s' * (mm != 1)}")
        for k, (pp, mm, _n) in enumerate(classes, start=1)
    ]
    if other.any():
        handles.append(Patch(facecolor="0.85", edgecolor="k", label="other periodic"))
    if ended.any():
        handles.append(Patch(facecolor="0.45", edgecolor="k", label="orbit ended / not computed"))
    ax2.legend(handles=handles, fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False)
    ax2.set_title(r"period: $p$ impacts in $m$ driving periods ($p \leq$ %d)" % spec.period_max)

    outline = [patheffects.withStroke(linewidth=4.0, foreground="white")]
    lines = []
    for ax in (ax1, ax2):
        for k, (label, xs, ys) in enumerate(paper_lines(spec)):
            colour = ("#007000", "#b000b0")[k % 2]
            lines.append(
                ax.plot(
                    xs,
                    ys,
                    "-",
                    color=colour,
                    lw=2.2,
                    solid_capstyle="butt",
                    path_effects=outline,
                    label=f"the paper's {label} scan",
                )[0]
            )
        ax.set_xlabel(r"$\alpha$ (driving amplitude)")
        ax.set_ylabel(r"$r$ (restitution)")
    # the scans' names in a legend below the panels: a label inside covered cells
    if lines:  # none where the plane is not the paper's (atlas.summary.paper_plane)
        fig.legend(handles=lines[: len(lines) // 2], loc="lower center", ncol=2, fontsize=8, frameon=False)
    fig.suptitle(
        title
        or (
            rf"Parameter-plane atlas, $\beta$ = {spec.beta:g}, $\gamma$ = {spec.gamma:g}: "
            f"{spec.n_alpha} x {spec.n_r} points, {spec.transient} transient + {spec.impacts} "
            f"measured impacts from (tau0, sdot0) = ({spec.tau0:g}, {spec.sdot0:g})"
        ),
        fontsize=10,
    )
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    return fig


__all__ = [
    "atlas_figure",
]
