"""r2: the fold of the 6-impact period-1 orbit (alpha = 3) and the type-I intermittency above it
(Section 3, Figs. 4-6).

**The fold.**  r2 is the saddle-node of the 6-impact period-1 orbit, located to ~12 digits by Newton
on the extended system ``(G, det(M - I)) = 0`` (:mod:`..continuation`), no time series involved.

**Laminar phases.**  Above r2 the orbit pair is gone and its ghost gives type-I intermittency: long
laminar phases near the fold orbit interrupted by chaotic bursts, of mean length
``<l> ~ (r - r2)^(-1/2)`` (theory, Pomeau-Manneville).  The
:class:`~gear_rattle.mapimpl.engine.observers.Laminar` observer counts maximal runs of at least
``MIN_LENGTH`` impacts within Euclidean distance ``EPS`` of the fold orbit's 6 points (both ends seen)
from impact ``n_start``, on several orbits per r value (per-orbit parameters, one engine run).  The
mean length and its standard error come from the sums of lengths and squared lengths; the slope of
``ln <l>`` against ``ln (r - r2)`` is a weighted fit (:func:`~.stats.fit_power_law`), with a fit-range
systematic (the fit without the 1 or 2 largest offsets, which lie furthest from the asymptotic regime).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ....core import jax_config  # noqa: F401
from ....mapimpl.engine.observers import Laminar
from ....core.params import Params
from ....mapimpl.continuation import orbit_states
from ....mapimpl.branches import R2_START, six_impact_branch
from .orbits import Cost, Timer, box_ics, engine_run, per_orbit
from ...profiles import get_profile, label as _label
from .results import LaminarStats, R2Result
from .stats import fit_power_law
from ...paper import PAPER

#: The paper's Fig. 5: r = 0.82144 ">~ r2".
PAPER_R2_FIG5 = float(PAPER["r2"].value)
#: Laminar criterion: distance to the fold orbit and the shortest run counted.
EPS, MIN_LENGTH = 0.05, 12


def laminar_statistics(
    r_values,
    fold,
    orbits: int,
    cap: int,
    n_start: int = 2000,
    eps: float = EPS,
    min_length: int = MIN_LENGTH,
    base: Params = R2_START,
    seed: int = 2,
    cost: Cost | None = None,
) -> LaminarStats:
    """Laminar phases at each r of ``r_values`` near the fold orbit ``fold`` (a
    :class:`~..continuation.BifurcationPoint`): ``orbits`` box orbits per value, ``cap`` impacts each,
    counted from ``n_start`` (one engine run)."""
    r_values = np.atleast_1d(np.asarray(r_values, float))
    oth, osd = orbit_states(base.replace(r=fold.mu), fold.theta, fold.sdot, 6)
    th, sd, w = box_ics(orbits * r_values.size, seed)
    obs = Laminar(oth, osd, eps=eps, min_length=min_length, n_start=n_start)
    res = engine_run(
        cost, "r2: laminar phases", th, sd, w, per_orbit(base, "r", np.repeat(r_values, orbits)), obs, cap=cap
    )
    o = res.obs[0]
    shape = (r_values.size, orbits)
    n = o["count"].reshape(shape).sum(axis=1).astype(float)
    s1 = o["total"].reshape(shape).sum(axis=1)
    s2 = o["total_sq"].reshape(shape).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(n > 0, s1 / n, np.nan)
        var = np.where(n > 1, (s2 - n * mean**2) / (n - 1), np.nan)
        sem = np.sqrt(var / n)
    return LaminarStats(
        r_values,
        mean,
        sem,
        n.astype(int),
        o["exposure"].reshape(shape).sum(axis=1).astype(float),
        float(eps),
        int(min_length),
        int(orbits),
        int(cap),
    )


def locate_r2(profile: str = "quick", branch=None, progress=None, *, sizes: dict | None = None) -> R2Result:
    """r2 (fold of the 6-impact orbit, alpha = 3) and the type-I intermittency exponent of the mean
    laminar length (Figs. 4-5; the module docstring).

    Parameters
    ----------
    profile : {"quick", "paper"}, optional
        Run sizes: :data:`validation.profiles.PROFILES` ``[profile]["r2"]``.
    branch : Branch, optional
        The 6-impact branch through r2 (default :func:`gear_rattle.mapimpl.branches.six_impact_branch`; shared with r1).
    progress : optional
        Unused (the engine runs show their own progress where stderr is a terminal).
    sizes : dict, optional
        Run sizes that replace the profile's (keys of :data:`validation.profiles.PROFILES` ``[profile]["r2"]``;
        the result's ``profile`` is then ``"<profile>+sizes"``).

    Returns
    -------
    R2Result
        r2 (the fold, Newton on the extended system), the laminar statistics and the fitted exponent
        of ``<l> ~ (r - r2)^slope`` with its errors (:class:`~.results.R2Result`).

    Examples
    --------
    With tiny run sizes (three offsets, two orbits of 4000 impacts each: the exponent is rough; the
    paper profile gives -0.5 within its error, docs/dynamics.md):

    >>> from gear_rattle.validation.dynamics.crises.r2 import locate_r2
    >>> tiny = {"dr": [1e-4, 3e-4, 1e-3], "orbits": 2, "cap": 4000, "n_start": 200}
    >>> res = locate_r2(sizes=tiny)
    >>> print(f"r2 = {res.r2:.10f}", res.profile)
    r2 = 0.8214404476 quick+sizes
    >>> bool(res.slope < 0), res.laminar.mean.shape
    (True, (3,))
    """
    pr = get_profile(profile, "r2", sizes)
    cost = Cost()
    with Timer(cost, "r2: 6-impact branch and fold"):
        br = branch or six_impact_branch()
    if not br.folds:
        raise RuntimeError("the 6-impact branch has no fold in its range")
    f = br.folds[0]
    dr = np.asarray(pr["dr"], float)
    ls = laminar_statistics(f.mu + dr, f, pr["orbits"], pr["cap"], pr["n_start"], cost=cost)
    slope, stat, _, chi2 = fit_power_law(dr, ls.mean, ls.sem)
    order = np.argsort(dr)
    subs = []
    for j in (1, 2):
        keep = order[:-j]
        if keep.size >= 3:
            subs.append((f"without the {j} largest r - r2", fit_power_law(dr[keep], ls.mean[keep], ls.sem[keep])[0]))
    syst = max((abs(s - slope) for _, s in subs), default=0.0)
    return R2Result(
        r2=f.mu,
        fold=f,
        branch=br,
        laminar=ls,
        dr=dr,
        slope=slope,
        slope_err=math.hypot(stat, syst),
        slope_stat=stat,
        slope_syst=syst,
        chi2_red=chi2,
        subranges=subs,
        paper_fig5={"r": PAPER_R2_FIG5, "minus_r2": PAPER_R2_FIG5 - f.mu},
        cost=cost.as_dict(),
        profile=_label(profile, sizes),
    )


@dataclass(frozen=True)
class CertifiedR2:
    """r2 proven: the fold of the 6-impact orbit for the paper's *printed* parameters (exact decimals
    alpha = 3.0, beta = gamma = 0.1; :data:`core.paper.PAPER_FIG3_DECIMAL`), by the Krawczyk operator on
    the extended system (:func:`mapimpl.certified.periodic.certify_bifurcation`).  ``lo``, ``hi``:
    float64 bounds of the enclosure, rounded outward; ``mid``: the float64 nearest its midpoint;
    ``decimal``: its :data:`DIGITS`-digit decimal interval (outward); ``width``: the enclosure's width."""

    lo: float
    hi: float
    mid: float
    width: float
    decimal: tuple


#: Significant digits of :attr:`CertifiedR2.decimal`.
DIGITS = 20


def certified_r2(fold) -> CertifiedR2:
    """r2 proven from the float64 fold ``fold`` (a :class:`~..continuation.BifurcationPoint`, the guess
    only: any guess Newton takes to the fold gives the same enclosure)."""
    from ....core.paper import PAPER_FIG3_DECIMAL
    from ....mapimpl.certified.balls import decimal_interval, precision
    from ....mapimpl.certified.periodic import certify_bifurcation

    th, sd = orbit_states(R2_START.replace(r=fold.mu), fold.theta, fold.sdot, 6)
    b = certify_bifurcation("fold", PAPER_FIG3_DECIMAL, "r", th, sd, fold.mu)
    with precision(320):
        lo, hi = b.value.lower(), b.value.upper()
        lo_f, hi_f = float(lo), float(hi)
        lo_f = lo_f if lo_f <= lo else math.nextafter(lo_f, -math.inf)
        hi_f = hi_f if hi_f >= hi else math.nextafter(hi_f, math.inf)
        return CertifiedR2(lo_f, hi_f, float(b.value.mid()), float(hi - lo), decimal_interval(b.value, DIGITS))


__all__ = [
    "PAPER_R2_FIG5",
    "EPS",
    "MIN_LENGTH",
    "laminar_statistics",
    "locate_r2",
    "CertifiedR2",
    "DIGITS",
    "certified_r2",
]
