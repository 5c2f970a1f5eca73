"""Figures without pyplot: every plot of the project is drawn on a :class:`matplotlib.figure.Figure`
and saved with :meth:`~matplotlib.figure.Figure.savefig`, so the library never selects or changes a
matplotlib backend and never touches pyplot's global figure list."""

from __future__ import annotations


def subplots(nrows: int = 1, ncols: int = 1, **kwargs):
    """``(fig, axes)`` like :func:`matplotlib.pyplot.subplots` (``figsize``/``dpi``/``layout`` go to the
    figure, the rest to :meth:`Figure.subplots`), without pyplot."""
    from matplotlib.figure import Figure

    fig_kw = {k: kwargs.pop(k) for k in ("figsize", "dpi", "layout") if k in kwargs}
    fig = Figure(**fig_kw)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def legend_outside(ax, **kwargs):
    """The axes' legend to the right of it, outside the data (a legend inside covered data points in
    Figs. 2-4 and 8); the figure's ``tight_layout`` makes room for it."""
    kw = dict(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8, frameon=False)
    kw.update(kwargs)
    return ax.legend(**kw)


def params_text(params, swept: str | None = None, values=None) -> str:
    """The parameters a figure shows, for its title: every parameter of ``params`` (a
    :class:`~gear_rattle.core.params.Params`) as ``name=value``, in the order of its fields, the swept
    one (``swept``, over ``values``) as its range: ``"alpha=3, beta=0.1, gamma=0.1, r in [0.6, 1] (200
    values)"``."""
    from dataclasses import fields

    import numpy as np

    out = []
    for f in fields(params):
        if f.name == swept:
            v = np.asarray(values, dtype=np.float64)
            out.append(
                f"{f.name} in [{v.min():g}, {v.max():g}] ({v.size} values)" if v.size > 1 else f"{f.name}={v.min():g}"
            )
        else:
            out.append(f"{f.name}={getattr(params, f.name):g}")
    return ", ".join(out)


__all__ = [
    "subplots",
    "legend_outside",
    "params_text",
]
