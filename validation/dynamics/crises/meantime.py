"""Mean times of memoryless processes from censored observations (exact Poisson intervals, Pearson
dispersion, left truncation) and the Grebogi-Ott-Yorke exponent; the checks the crisis statistics share
(methods: :mod:`.stats`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from ....core.checks import MAX_AVERAGED, MAX_TOTAL, check_int

#: Confidence level of the intervals of mean times and of the bracket.
LEVEL = 0.95
SIDES = ("above", "below")


def check_level(level: float) -> float:
    if not (isinstance(level, (int, float)) and 0.0 < level < 1.0):
        raise ValueError(f"level={level!r} is out of range: allowed 0 < level < 1")
    return float(level)


def check_side(side: str) -> str:
    if side not in SIDES:
        raise ValueError(f"side={side!r} is out of range: allowed one of {SIDES}")
    return side


def check_counts(mu, k, E, dispersion=None):
    """``(mu, events, exposure, dispersion)`` as flat float arrays of one length, or ValueError: finite mu,
    exposure > 0, events >= 0, dispersion >= 1 (default 1)."""
    mu = np.asarray(mu, float).ravel()
    k = np.asarray(k, float).ravel()
    E = np.asarray(E, float).ravel()
    if not (mu.shape == k.shape == E.shape):
        raise ValueError("mu, events and exposure must have the same length")
    if not (np.all(np.isfinite(mu)) and np.all(np.isfinite(E)) and np.all(E > 0) and np.all(k >= 0)):
        raise ValueError("mu, events or exposure out of range: allowed finite mu, exposure > 0, events >= 0")
    w = np.ones_like(mu) if dispersion is None else np.broadcast_to(np.asarray(dispersion, float), mu.shape).copy()
    if not np.all(np.isfinite(w) & (w >= 1.0)):
        raise ValueError("dispersion is out of range: allowed values >= 1")
    return mu, k, E, w


# ------------------------------------------------------------------------------ mean times


@dataclass(frozen=True)
class MeanTime:
    """Mean time ``T = exposure / events`` (impacts) of a memoryless process and its exact interval.

    ``events``: events seen (escapes, hops); ``exposure``: impacts observed; ``dispersion``: Pearson
    dispersion of the per-orbit counts (>= 1; 1 = Poisson); ``orbits``: orbits contributing;
    ``level``: confidence level of :attr:`lo`, :attr:`hi`.
    """

    events: int
    exposure: float
    dispersion: float = 1.0
    orbits: int = 0
    level: float = LEVEL

    def __post_init__(self):
        check_int("events", self.events, 0, MAX_TOTAL)
        if not (math.isfinite(self.exposure) and self.exposure > 0):
            raise ValueError(f"exposure={self.exposure!r} is out of range: allowed a finite exposure > 0")
        if not (math.isfinite(self.dispersion) and self.dispersion >= 1.0):
            raise ValueError(f"dispersion={self.dispersion!r} is out of range: allowed >= 1")
        check_level(self.level)

    @property
    def T(self) -> float:
        """Maximum-likelihood mean time (``inf`` without events)."""
        return self.exposure / self.events if self.events else math.inf

    @property
    def lo(self) -> float:
        """Lower end of the two-sided interval (exact Poisson, on ``k/phi`` events in ``E/phi``)."""
        k, E = self.events / self.dispersion, self.exposure / self.dispersion
        return 2.0 * E / float(stats.chi2.ppf(0.5 + self.level / 2, 2 * k + 2))

    @property
    def hi(self) -> float:
        """Upper end of the two-sided interval (``inf`` without events)."""
        if self.events == 0:
            return math.inf
        k, E = self.events / self.dispersion, self.exposure / self.dispersion
        return 2.0 * E / float(stats.chi2.ppf(0.5 - self.level / 2, 2 * k))

    @property
    def rel_err(self) -> float:
        """One-sigma relative error ``sqrt(phi / k)`` (``inf`` without events)."""
        return math.sqrt(self.dispersion / self.events) if self.events else math.inf

    @property
    def bound(self) -> float:
        """One-sided lower bound on ``T`` at :attr:`level` (the statement a run without events makes)."""
        return lifetime_lower_bound(self.exposure, self.level, self.events, self.dispersion)

    def as_dict(self) -> dict:
        return {
            "T": self.T,
            "lo": self.lo,
            "hi": self.hi,
            "events": int(self.events),
            "exposure": float(self.exposure),
            "dispersion": float(self.dispersion),
            "orbits": int(self.orbits),
            "level": self.level,
        }


def lifetime_lower_bound(exposure: float, level: float = LEVEL, events: int = 0, dispersion: float = 1.0) -> float:
    """One-sided lower bound on the mean time at ``level`` after ``events`` events in ``exposure``
    impacts: ``2E / chi2.ppf(level, 2k + 2)``; with no event ``E / (-ln(1 - level))`` (= E / 3.0 at 95 %)."""
    check_level(level)
    k, E = events / dispersion, exposure / dispersion
    return 2.0 * E / float(stats.chi2.ppf(level, 2 * k + 2))


def pearson_dispersion(events, exposure) -> float:
    """Pearson dispersion ``sum (k_i - E_i/T)^2 / (E_i/T) / (n - 1)`` of per-orbit counts, floored at 1
    (1 when there are fewer than two orbits or no events)."""
    k = np.asarray(events, float).ravel()
    E = np.asarray(exposure, float).ravel()
    if k.shape != E.shape:
        raise ValueError("events and exposure must have the same length")
    ok = E > 0
    k, E = k[ok], E[ok]
    if k.size < 2 or k.sum() == 0:
        return 1.0
    m = E * k.sum() / E.sum()
    return max(1.0, float(np.sum((k - m) ** 2 / m) / (k.size - 1)))


def mean_time(events, exposure, *, overdispersed: bool = False, level: float = LEVEL) -> MeanTime:
    """:class:`MeanTime` of per-orbit counts ``events`` in per-orbit ``exposure`` (arrays); with
    ``overdispersed`` the interval is widened by the Pearson dispersion of the counts (for repeated
    events per orbit, e.g. band hops)."""
    k = np.asarray(events).ravel()
    E = np.asarray(exposure, float).ravel()
    if k.shape != E.shape or k.size == 0:
        raise ValueError("events and exposure must be non-empty arrays of the same length")
    if np.any(k < 0) or np.any(E < 0):
        raise ValueError("events and exposure are out of range: allowed values >= 0")
    phi = pearson_dispersion(k, E) if overdispersed else 1.0
    return MeanTime(int(k.sum()), float(E.sum()), phi, int(np.sum(E > 0)), level)


def censored_lifetimes(escape, n_run, n0: int = 0, level: float = LEVEL) -> tuple[MeanTime, int]:
    """Mean lifetime from per-orbit escape indices with censoring and left truncation.

    ``escape[i]``: the impact at which orbit ``i`` escaped (< 0: not within its run); ``n_run[i]``: the
    impacts the orbit was followed (its censoring time when it did not escape); ``n0``: counting
    starts at impact ``n0`` (orbits that escaped by then are dropped: exponential lifetimes are
    memoryless, so the survivors' remaining lifetimes have the same mean).  Returns the
    :class:`MeanTime` and the number of orbits dropped.
    """
    esc = np.asarray(escape).ravel()
    n = np.asarray(n_run).ravel()
    if esc.shape != n.shape or esc.size == 0:
        raise ValueError("escape and n_run must be non-empty arrays of the same length")
    check_int("n0", n0, 0, MAX_AVERAGED)
    escaped = esc >= 0
    end = np.where(escaped, esc, n)
    alive = end > n0
    k = int(np.sum(escaped & alive))
    E = float(np.sum(np.where(alive, end - n0, 0)))
    if E <= 0:
        raise ValueError(f"no orbit was followed beyond n0={n0}")
    return MeanTime(k, E, 1.0, int(alive.sum()), level), int(np.sum(~alive))


# ------------------------------------------------------------------------------ GOY exponent


def goy_exponent(multipliers) -> float:
    """Grebogi-Ott-Yorke critical exponent ``1/2 + ln|m_u| / |ln|m_s||`` of a crisis mediated by a saddle
    orbit with multipliers ``m_u`` (unstable) and ``m_s`` (stable) of a 2-D map."""
    m = np.sort(np.abs(np.asarray(multipliers, complex)))
    if m.size != 2 or not (0.0 < m[0] < 1.0 < m[1]):
        raise ValueError(f"multipliers {multipliers!r} are out of range: allowed a saddle (0 < |m_s| < 1 < |m_u|)")
    return float(0.5 + np.log(m[1]) / abs(np.log(m[0])))


__all__ = [
    "LEVEL",
    "SIDES",
    "check_level",
    "check_side",
    "check_counts",
    "MeanTime",
    "lifetime_lower_bound",
    "pearson_dispersion",
    "mean_time",
    "censored_lifetimes",
    "goy_exponent",
]
