"""How the orbits that stick are counted in Eq. (14): the Fig. 11 durations refitted under other
conventions (the paper does not say how chattering orbits were treated; docs/transients.md).

Conventions (:func:`sticking_conventions`): followed with the certified ``T_post`` of the decimal
parameters (ours), with the certified ``T_post`` of their float64 roundings, with the float64 engine's
own post-release orbit (a sample); counted as decayed at once (duration 0); left out.  Every one uses
the one composition :func:`mapimpl.engine.release.compose_durations` through
:meth:`~gear_rattle.mapimpl.engine.transients.TransientResult.duration`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...mapimpl.engine.release import TPost, ReleaseSource
from ...mapimpl.engine.t_post import release_for
from ..paper import PAPER
from .analysis import SurvivalFit, fit_survival

OURS = "followed, certified T_post of the decimal parameters (ours)"
FLOAT64_ROUNDING = "followed, certified T_post of the float64-rounded parameters"
SAMPLE = "followed, the float64 engine's own post-release orbit (a sample)"
DECAYED = "counted as decayed at once (duration 0)"
LEFT_OUT = "left out"
#: Bootstrap resamples of each refit.
N_BOOT = 50


@dataclass
class ConventionFit:
    """The Eq. (14) fit of ``orbits`` durations under the convention ``name``."""

    name: str
    orbits: int
    fit: SurvivalFit


@dataclass
class StickingConventions:
    """The refits (``rows``, ours first), ``sticking_fraction`` (orbits that stick before capture),
    ``spans`` of the decay time, <n> and kappa over the conventions (``(lo, hi)``) and their relative
    widths ``rel_spans``; ``paper_between``: the paper's <n> and kappa both lie between ours and
    'counted as decayed at once'; ``sample``: the row with the float64 sample of T_post (None without
    orbits that stick)."""

    rows: list
    sticking_fraction: float
    spans: dict
    rel_spans: dict
    paper_between: bool

    @property
    def ours(self) -> ConventionFit:
        return self.rows[0]

    @property
    def sample(self) -> ConventionFit | None:
        return next((r for r in self.rows if r.name == SAMPLE), None)


def rounding_t_post(fig11) -> TPost:
    """The certified ``T_post`` for the float64-rounded parameters that the Fig. 11 run ``fig11`` was
    given (``transients(float64_rounding=True)``), or certified now at its main delta (the float64 sample
    where that certification is undecided, as for every certified source)."""
    if fig11.float64_rounding is not None:
        return fig11.float64_rounding
    return release_for(
        fig11.engine,
        fig11.delta,
        ReleaseSource.CERTIFIED_FLOAT64_ROUNDING,
        deltas=(fig11.delta,),
        confirm=fig11.confirm,
        stick_time=fig11.stick_time,
    )


def sticking_conventions(fig11, seed: int = 0, n_boot: int = N_BOOT) -> StickingConventions:
    """Refit Eq. (14) on the durations of the Fig. 11 run ``fig11`` (a
    :class:`~gear_rattle.validation.transient.results.SurvivalResult` with the certified T_post) at its
    main delta under each convention (module docstring)."""
    res, delta, cap = fig11.engine, fig11.delta, fig11.cap
    dur, cens = fig11.durations(delta)
    stuck = fig11.composed
    variants = [(OURS, dur, cens)]
    if fig11.main_t_post.walls:
        variants.append((FLOAT64_ROUNDING, *res.duration(release=rounding_t_post(fig11))))
        variants.append((SAMPLE, *res.duration(delta)))
    variants += [(DECAYED, np.where(stuck, 0, dur), cens & ~stuck), (LEFT_OUT, dur[~stuck], cens[~stuck])]
    rows = [
        ConventionFit(name, int(d.size), fit_survival(d, c, cap=cap, n_boot=n_boot, seed=seed))
        for name, d, c in variants
    ]
    decayed = next(r for r in rows if r.name == DECAYED)
    between = all(
        min(getattr(rows[0].fit, k), getattr(decayed.fit, k))
        <= pv
        <= max(getattr(rows[0].fit, k), getattr(decayed.fit, k))
        for k, pv in (("mean_n", PAPER["mean_n"].value), ("kappa", PAPER["kappa"].value))
    )
    spans = {
        name: (min(getattr(r.fit, k) for r in rows), max(getattr(r.fit, k) for r in rows))
        for name, k in (("decay time", "tau_fit"), ("<n>", "mean_n"), ("kappa", "kappa"))
    }
    rel_spans = {name: (hi - lo) / lo if lo else float("nan") for name, (lo, hi) in spans.items()}
    return StickingConventions(rows, float(stuck.mean()), spans, rel_spans, between)


__all__ = [
    "OURS",
    "FLOAT64_ROUNDING",
    "SAMPLE",
    "DECAYED",
    "LEFT_OUT",
    "N_BOOT",
    "ConventionFit",
    "StickingConventions",
    "rounding_t_post",
    "sticking_conventions",
]
