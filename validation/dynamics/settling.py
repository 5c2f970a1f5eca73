"""Settling and laminar phases near a periodic orbit (Figs. 5-6 and the orbit after alpha1, Section 3):
where orbits from random initial conditions end, when they got there, and the laminar stretches of a
displayed time series.

* :func:`settle`: ``n_ics`` orbits on the engine at one parameter value; whether and when each settles
  near a reference orbit (a :class:`Settling`);
* :func:`period_of`: the smallest period of a recorded tail (theta circular);
* :func:`laminar_in_series`: laminar fraction, phases and the final laminar stretch of ``sdot_n`` near a
  6-impact orbit;
* :func:`local_slopes`: the local slopes of the laminar-length law ``<l> ~ (r - r2)^k`` (type-I
  intermittency, theory k = -1/2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...core.params import Params

#: A settled orbit: its last SETTLE_TAIL impacts repeat with a period <= SETTLE_MAX_P to SETTLE_TOL.
SETTLE_TAIL, SETTLE_MAX_P, SETTLE_TOL = 240, 12, 1e-9
#: Laminar phases counted: at least this many impacts (as in crises.laminar_statistics).
MIN_LAMINAR = 12
#: Random initial conditions of :func:`settle`: pre-impact states at s = 0 with 0 <= tau0 < 2 pi and
#: SDOT0_RANGE[0] <= sdot0 <= SDOT0_RANGE[1].
SDOT0_RANGE = (0.05, 0.5)


def period_of(theta: np.ndarray, sdot: np.ndarray, max_p: int = SETTLE_MAX_P, tol: float = SETTLE_TOL) -> int | None:
    """Smallest p <= max_p with (theta, sdot) repeating after p impacts to ``tol`` (theta circular)."""
    for p in range(1, max_p + 1):
        if theta.size <= p:
            return None
        dt = np.abs(theta[p:] - theta[:-p])
        dt = np.minimum(dt, 2 * np.pi - dt)
        if max(dt.max(), np.abs(sdot[p:] - sdot[:-p]).max()) <= tol:
            return p
    return None


@dataclass
class Settling:
    """Orbits from ``n_ics`` random initial conditions at one parameter value, ``n`` impacts each:
    ``settled`` (ends periodic and inside the ``eps``-neighbourhood of the reference orbit), ``capture``
    (impact at which its final stay there began; -1 if not settled), ``phases`` (complete laminar
    phases of >= MIN_LAMINAR impacts before that), ``period`` (impacts, driving periods) of the final
    orbit, the Floquet multipliers of the orbit it settled on (the first settled one), and the
    complete stays of all orbits (>= MIN_LAMINAR impacts, begun after and ended by a burst): their
    number ``laminar_count``, the sum ``laminar_total`` and the sum of squares ``laminar_total_sq`` of
    their lengths."""

    value: float
    n_ics: int
    n: int
    eps: float
    settled: np.ndarray
    capture: np.ndarray
    phases: np.ndarray
    period: list
    multipliers: np.ndarray | None
    laminar_count: int
    laminar_total: float
    laminar_total_sq: float

    def laminar_mean(self) -> tuple[float, float]:
        """Mean length of the complete stays and its standard error (NaN below two stays)."""
        k = self.laminar_count
        if k < 2:
            return (self.laminar_total / k if k else float("nan")), float("nan")
        mean = self.laminar_total / k
        var = max(self.laminar_total_sq - k * mean * mean, 0.0) / (k - 1)
        return mean, math.sqrt(var / k)

    def common_period(self) -> tuple[int, int] | None:
        """The most common ``(impacts, driving periods)`` of the settled orbits (None: none settled)."""
        ps = [p for p, s in zip(self.period, self.settled) if s and p is not None]
        return max(set(ps), key=ps.count) if ps else None

    def impacts_per_period(self) -> int | float | None:
        """Impacts per driving period of :meth:`common_period` (an int when whole; None: none settled)."""
        cp = self.common_period()
        if cp is None:
            return None
        return cp[0] // cp[1] if cp[0] % cp[1] == 0 else cp[0] / cp[1]


def runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start indices and lengths of the runs of True in a 1-D boolean array."""
    m = np.concatenate([[False], mask, [False]]).astype(np.int8)
    dm = np.diff(m)
    starts = np.nonzero(dm == 1)[0]
    return starts, np.nonzero(dm == -1)[0] - starts


def _final_orbits(P: Params, tail: dict, reached: np.ndarray, run_end: np.ndarray, n: int):
    """Per orbit: settled, the capture impact and the period of the recorded tail; the multipliers of
    the first settled orbit."""
    from ...mapimpl.orbit import map_orbit
    from ...mapimpl.periodic import find_periodic

    settled: list[bool] = []
    capture: list[int] = []
    period: list[tuple[int, int] | None] = []
    mult = None
    for j in range(reached.size):
        th, sd = tail["theta"][j], tail["sdot"][j]
        p = period_of(th, sd) if bool(reached[j]) else None
        ok = bool(run_end[j] > 0) and p is not None
        settled.append(ok)
        capture.append(int(n - run_end[j] + 1) if ok else -1)
        if p is None:
            period.append(None)
            continue
        tau = map_orbit(P, float(th[-1]), float(sd[-1]), p).impact_arrays()[0]
        turns = int(round((tau[-1] - tau[0]) / (2 * np.pi)))
        period.append((p, turns))
        if ok and mult is None:
            po = find_periodic(P, float(th[-1]), float(sd[-1]), p, turns)
            mult = po.multipliers if po.converged else None
    return settled, capture, period, mult


def settle(
    base: Params, param: str, value: float, ref_th, ref_sd, n_ics: int, n: int, eps: float, seed: int
) -> Settling:
    """Run ``n_ics`` orbits (random pre-impact states at s = 0, 0 <= tau0 < 2 pi, 0.05 <= sdot0 <= 0.5) at
    ``param = value`` for ``n`` impacts on the engine and see whether and when each settles near the
    reference orbit (``ref_th, ref_sd``).  Two observers, no history: a
    :class:`~gear_rattle.mapimpl.engine.observers.Laminar` counts the stays within ``eps`` (Euclidean)
    of the reference orbit from impact 1 on and gives the length of the stay in progress at impact
    ``n``; a :class:`~gear_rattle.mapimpl.engine.observers.Sample` keeps the last SETTLE_TAIL states for
    the period test."""
    from ...mapimpl.engine.driver import run
    from ...mapimpl.engine.observers import Laminar, Sample

    if n < SETTLE_TAIL:
        raise ValueError(f"n={n!r} is out of range: allowed n >= {SETTLE_TAIL} (the tail of the period test)")
    rng = np.random.default_rng(seed)
    t0, s0 = rng.uniform(0.0, 2 * np.pi, n_ics), rng.uniform(SDOT0_RANGE[0], SDOT0_RANGE[1], n_ics)
    P = base.replace(**{param: value})
    lam = Laminar(
        np.mod(np.asarray(ref_th, float), 2 * np.pi),
        np.asarray(ref_sd, float),
        eps=eps,
        min_length=MIN_LAMINAR,
        n_start=1,
    )
    res = run(
        t0,
        s0,
        np.zeros(n_ics, np.int32),
        P,
        (lam, Sample(keep=SETTLE_TAIL, n_start=n - SETTLE_TAIL + 1)),
        cap=n,
        progress=False,
    )
    lo, tail = res.obs
    reached = res.n == n
    settled, capture, period, mult = _final_orbits(P, tail, reached, np.where(reached, lo["run"], 0), n)
    return Settling(
        float(value),
        n_ics,
        n,
        float(eps),
        np.array(settled),
        np.array(capture),
        np.asarray(lo["count"], int),
        period,
        mult,
        int(np.sum(lo["count"])),
        float(np.sum(lo["total"])),
        float(np.sum(lo["total_sq"])),
    )


def laminar_in_series(sd: np.ndarray, eps: float) -> tuple[float, int, int | None]:
    """In a displayed series sdot_n near a 6-impact orbit: the fraction of impacts with
    ``|sdot_{n+6} - sdot_n| < eps``, the number of laminar phases (>= MIN_LAMINAR such impacts in a row)
    and the index at which the final laminar phase began (None if the series ends in a burst)."""
    lam = np.abs(sd[6:] - sd[:-6]) < eps
    starts, lens = runs(lam)
    n_ph = int((lens >= MIN_LAMINAR).sum())
    ends_laminar = starts.size and starts[-1] + lens[-1] == lam.size and lens[-1] >= MIN_LAMINAR
    tail = int(starts[-1]) if ends_laminar else None
    return float(lam.mean()), n_ph, tail


def local_slopes(dr, mean, sem) -> list[tuple[float, float, float, float]]:
    """Slopes of log(mean laminar length) between successive r - r2 with their errors (from the standard
    errors of the two means): ``(dr_lo, dr_hi, slope, error)``."""
    out = []
    for i in range(len(dr) - 1):
        dx = math.log(dr[i + 1]) - math.log(dr[i])
        s = (math.log(mean[i + 1]) - math.log(mean[i])) / dx
        e = math.hypot(sem[i] / mean[i], sem[i + 1] / mean[i + 1]) / abs(dx)
        out.append((float(dr[i]), float(dr[i + 1]), s, e))
    return out


__all__ = [
    "SETTLE_TAIL",
    "SETTLE_MAX_P",
    "SETTLE_TOL",
    "MIN_LAMINAR",
    "SDOT0_RANGE",
    "period_of",
    "Settling",
    "runs",
    "settle",
    "laminar_in_series",
    "local_slopes",
]
