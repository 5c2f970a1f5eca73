"""Brackets of a crisis by direct observation, the next bracket runs, and the reported crisis point
(fit or bracket; methods: :mod:`.stats`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .meantime import LEVEL, check_counts, check_level, check_side, lifetime_lower_bound


# ------------------------------------------------------------------------------ bracket


@dataclass
class Bracket:
    """A crisis bracketed by direct observation.

    ``seen``: the parameter value nearest to the crisis at which events were observed (the crisis lies
    on the other side of it: for ``side="above"`` ``mu_c < seen``); ``clear``: the nearest value beyond
    it with no event (NaN if none), observed for ``clear_exposure`` impacts, which excludes mean times
    below ``clear_bound`` (one-sided, ``level``) -- not a proof that the set is an attractor there;
    ``interval``: ``(lo, hi)`` between the two.
    """

    side: str
    seen: float
    clear: float
    clear_exposure: float
    clear_bound: float
    level: float

    @property
    def interval(self) -> tuple[float, float]:
        return (min(self.seen, self.clear), max(self.seen, self.clear))

    @property
    def width(self) -> float:
        return abs(self.seen - self.clear)

    def as_dict(self) -> dict:
        return {
            "side": self.side,
            "seen": self.seen,
            "clear": self.clear,
            "clear_exposure": self.clear_exposure,
            "clear_bound": self.clear_bound,
            "level": self.level,
            "interval": self.interval,
            "width": self.width,
        }


def bracket(mu, events, exposure, side: str, level: float = LEVEL, min_exposure: float = 0.0) -> Bracket:
    """The tightest bracket of the crisis from counts at several parameter values: ``seen`` is the value
    with events nearest to the crisis side (``min`` for ``side="above"``, ``max`` for ``"below"``),
    ``clear`` the nearest value beyond it without events in at least ``min_exposure`` impacts (runs of
    one value are summed)."""
    side = check_side(side)
    check_level(level)
    mu, k, E, _ = check_counts(mu, events, exposure)
    vals = np.unique(mu)
    kk = np.array([k[mu == v].sum() for v in vals])
    EE = np.array([E[mu == v].sum() for v in vals])
    if not np.any(kk > 0):
        raise ValueError("bracket needs at least one value with events")
    strong = (kk == 0) & (EE >= min_exposure)
    if side == "above":
        seen = float(vals[kk > 0].min())
        cand = (vals < seen) & strong
        j = int(np.argmax(np.where(cand, vals, -np.inf))) if cand.any() else -1
    else:
        seen = float(vals[kk > 0].max())
        cand = (vals > seen) & strong
        j = int(np.argmin(np.where(cand, vals, np.inf))) if cand.any() else -1
    if j < 0:
        return Bracket(side, seen, math.nan, 0.0, 0.0, level)
    return Bracket(side, seen, float(vals[j]), float(EE[j]), lifetime_lower_bound(EE[j], level), level)


def next_probes(
    mu,
    events,
    exposure,
    side: str,
    mu_fit: float,
    step: float,
    target: float,
    strong: float,
    event_probe: float | None = None,
) -> list[float]:
    """The next bracket runs (a bisection started from a fit), each to be observed for ``strong`` impacts.

    Pre-crisis side: with no value there lacking events after ``strong`` impacts, probe ``step`` beyond
    ``mu_fit`` (or beyond ``seen`` when that is further); with one, and the bracket wider than
    ``2 target``, probe the midpoint of the bracket.  Event side: ``event_probe`` (e.g. where the law
    predicts a long mean time) unless a value within ``target / 10`` of it was observed for ``strong``
    impacts.  Returns the sorted new values (empty: done)."""
    side = check_side(side)
    mu, k, E, _ = check_counts(mu, events, exposure)
    if not (math.isfinite(step) and step > 0 and math.isfinite(target) and target > 0):
        raise ValueError("step and target are out of range: allowed finite values > 0")
    b = bracket(mu, k, E, side, min_exposure=strong)
    s = -1.0 if side == "above" else 1.0  # from the crisis towards the pre-crisis side
    out = []
    if not np.isfinite(b.clear):
        start = max(s * mu_fit, s * b.seen) * s
        out.append(start + s * step)
    elif b.width > 2 * target:
        out.append(0.5 * (b.seen + b.clear))
    if event_probe is not None:
        near = np.abs(mu - event_probe) <= target / 10
        if not np.any(near & (E >= strong)):
            out.append(float(event_probe))
    return sorted(set(float(v) for v in out))


# ------------------------------------------------------------------------------ the reported value


@dataclass(frozen=True)
class Located:
    """The crisis point a report states: ``value`` +- ``err`` and how it was decided.

    ``method``: ``"fit"`` (the GOY fit, +- its statistical and fit-range error) or ``"bracket"`` (the
    midpoint and half-width of the bracket by direct observation); ``why``: the reason (see
    :func:`locate`); ``outside``: how far the fit lies outside the bracket, in units of its error (0
    inside); ``interval``: the bracket ``(lo, hi)`` (NaN without one)."""

    value: float
    err: float
    method: str
    outside: float
    interval: tuple[float, float]
    why: str = ""

    def as_dict(self) -> dict:
        return {
            "value": self.value,
            "err": self.err,
            "method": self.method,
            "why": self.why,
            "outside": self.outside,
            "interval": self.interval,
        }


#: The reasons :func:`locate` gives.
WHY_NO_BRACKET = "no bracket"
WHY_FIT_NARROWER = "fit inside the bracket and narrower"
WHY_BRACKET_NARROWER = "bracket narrower than the fit"
WHY_FIT_OUTSIDE = "fit outside the bracket"


def locate(fit_mu: float, fit_err: float, brk: Bracket, margin: float = 0.0) -> Located:
    """Decide the reported crisis point from a fit (``fit_mu`` +- ``fit_err``, statistical and fit-range
    systematic combined) and a :class:`Bracket` (``margin``: the distance beyond ``clear`` that the
    fitted law still allows, :meth:`CrisisFit.distance_at` of ``clear_bound``).

    The bracket is what the data show without a model; the fit adds the crisis law.  So: without a
    bracket, the fit; with the fit more than its error outside the bracket, the bracket (the law does
    not hold that close to the crisis); with the fit inside (within its error), the narrower of the two
    -- the fit's error or the bracket's half-width."""
    if not np.isfinite(brk.clear):
        return Located(float(fit_mu), float(fit_err), "fit", 0.0, (math.nan, math.nan), WHY_NO_BRACKET)
    if brk.side == "above":  # events seen above the crisis: mu_c < seen, and mu_c > clear - margin
        lo, hi = brk.clear - margin, brk.seen
    else:  # events seen below: mu_c > seen, and mu_c < clear + margin
        lo, hi = brk.seen, brk.clear + margin
    gap = max(lo - fit_mu, fit_mu - hi, 0.0)
    outside = gap / fit_err if fit_err > 0 else (math.inf if gap > 0 else 0.0)
    interval = (float(lo), float(hi))
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    if outside > 1.0:
        return Located(mid, half, "bracket", float(outside), interval, WHY_FIT_OUTSIDE)
    if half < fit_err:
        return Located(mid, half, "bracket", float(outside), interval, WHY_BRACKET_NARROWER)
    return Located(float(fit_mu), float(fit_err), "fit", float(outside), interval, WHY_FIT_NARROWER)


__all__ = [
    "Bracket",
    "bracket",
    "next_probes",
    "Located",
    "WHY_NO_BRACKET",
    "WHY_FIT_NARROWER",
    "WHY_BRACKET_NARROWER",
    "WHY_FIT_OUTSIDE",
    "locate",
]
