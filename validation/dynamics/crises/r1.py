"""r1: the interior crisis of Fig. 4 (alpha = 3, beta = gamma = 0.1), from band hops.

**Mechanism** (Section 3, Figs. 4 and 7).  For r > r1 the attractor has six bands visited in turn
once per driving period; at r1 they collide with the saddle 6-impact period-1 orbit born at the fold
r2 (continued down its saddle branch, :func:`gear_rattle.mapimpl.branches.six_impact_branch`) and merge.  Below r1 the orbit
stays in the former bands for long stretches and hops out (crisis-induced intermittency) with a mean
time between hops ``T(r) ~ C (r1 - r)^-g``; the GOY exponent of the mediating saddle gives ``g``.

**Hops.**  The :class:`~gear_rattle.mapimpl.engine.observers.BandEscape` observer in counting mode: an
impact is *out* when its 6-impact return time ``tau_n - tau_{n-6}`` differs from ``2 pi`` by more than
0.6 (inside the bands it never does: at most ~0.47 on the attractor at r = 0.7416), and a hop is an
out impact after at least 60 impacts in.  Counted from impact ``N0``.

**Initial conditions** on the 6-band attractor: box orbits settled at ``r_ref`` (> r1) whose last 13
impacts (:class:`~gear_rattle.mapimpl.engine.observers.Sample`) are all inside the bands and that
hopped never after the first half of the settling run (:func:`band_ics`).

**Location** (:func:`locate_r1`): mean time between hops (total exposure / hops, quasi-Poisson interval
with the Pearson dispersion of the per-orbit counts) on a coarse scan of r, a first fit, a fine scan at
offsets below the first estimate, the fits of the crisis law (GOY exponent fixed, and free) with the
fit-range systematic, and a bracket by direct observation refined by bisection: hops seen at ``r_a``
(so r1 > r_a), none in >= ``probe_orbits x probe_cap`` impacts at ``r_b``.  No hop at ``r_b`` could
also mean a periodic window (the orbits settle on a stable cycle inside the bands); the largest
Lyapunov exponent of band orbits at ``r_b`` (:func:`lyapunov_at`) rules that out: only with it positive
on every orbit is ``r_b`` the bracket's upper end.
"""

from __future__ import annotations

import math

import numpy as np

from ....core import jax_config  # noqa: F401
from ....mapimpl.engine.exponents import exponents
from ....mapimpl.engine.observers import BandEscape, Sample, Tangent
from ....core.params import Params
from ....mapimpl.branches import R2_START, orbit_on_branch, six_impact_branch
from .orbits import Cost, Timer, box_ics, engine_run, per_orbit
from ....core.checks import check_int
from ...profiles import get_profile, label as _label
from .results import R1Result, located_fields
from .stats import LEVEL, Bracket, bracket, fit_crisis, goy_exponent, locate, mean_time, next_probes, range_systematic
from ...paper import PAPER

#: The paper's Fig. 7: r = 0.74001 "<~ r1".
PAPER_R1_FIG7 = float(PAPER["r1"].value)
#: Band-hop criterion (BandEscape): 6 bands once per period, threshold on the return time, impacts in.
BANDS, THRESHOLD, MIN_INSIDE = 6, 0.6, 60
#: Counting starts at this impact.
N0 = 500


def _hops_observer() -> BandEscape:
    return BandEscape(p=BANDS, m=1, threshold=THRESHOLD, min_inside=MIN_INSIDE, n_start=N0)


def band_ics(
    r_ref: float, n: int, settle: int, seed: int = 1, cost: Cost | None = None, base: Params = R2_START
) -> dict:
    """``n`` states on the 6-band attractor at ``r_ref`` (> r1): end states of box orbits whose last 13
    impacts lie inside the bands and that did not hop after impact ``settle // 2``."""
    out: dict[str, list] = {"theta": [], "sdot": [], "wall": []}
    drawn = rejected = 0
    keep = 13
    obs = (
        BandEscape(p=BANDS, m=1, threshold=THRESHOLD, min_inside=MIN_INSIDE, n_start=settle // 2),
        Sample(keep=keep, n_start=settle - keep + 1),
    )
    for attempt in range(4):
        m = int(math.ceil(1.2 * (n - len(out["theta"])))) + 8
        t0, s0, w0 = box_ics(m, seed + 1000 * attempt)
        r = engine_run(cost, "r1: settle on the 6 bands", t0, s0, w0, base.replace(r=r_ref), obs, cap=settle)
        s = r.obs[1]
        tau = 2 * np.pi * s["cycles"] + s["theta"]
        ret = tau[:, BANDS:] - tau[:, :-BANDS]
        ok = (r.obs[0]["bursts"] == 0) & (r.n == settle) & np.all(np.abs(ret - 2 * np.pi) <= THRESHOLD, axis=1)
        drawn += m
        rejected += int(np.sum(~ok))
        for key, v in (("theta", r.theta), ("sdot", r.sdot), ("wall", r.wall)):
            out[key] += list(v[ok])
        if len(out["theta"]) >= n:
            break
    else:
        raise RuntimeError(
            f"only {len(out['theta'])} of {drawn} box orbits settled in the 6 bands at r_ref={r_ref} "
            "(is r_ref above r1?)"
        )
    return {
        "theta": np.array(out["theta"][:n]),
        "sdot": np.array(out["sdot"][:n]),
        "wall": np.array(out["wall"][:n], np.int32),
        "drawn": drawn,
        "rejected": rejected,
        "r_ref": float(r_ref),
        "settle": int(settle),
    }


def hop_counts(
    r_values,
    ics: dict,
    orbits: int,
    cap: int,
    cost: Cost | None = None,
    label: str = "r1: hops",
    base: Params = R2_START,
    level: float = LEVEL,
) -> list[dict]:
    """Band hops at each r: ``orbits`` orbits per value (from the first ``orbits`` states of ``ics``,
    reused cyclically), ``cap`` impacts each, one engine run.  Per r: ``r``, ``rate``
    (:class:`~.stats.MeanTime` with the Pearson dispersion), ``hops``, ``exposure`` (per-orbit arrays)."""
    r_values = np.atleast_1d(np.asarray(r_values, float))
    idx = np.arange(orbits) % ics["theta"].size
    R = np.repeat(r_values, orbits)
    res = engine_run(
        cost,
        label,
        np.tile(ics["theta"][idx], r_values.size),
        np.tile(ics["sdot"][idx], r_values.size),
        np.tile(ics["wall"][idx], r_values.size),
        per_orbit(base, "r", R),
        _hops_observer(),
        cap=cap,
    )
    b = res.obs[0]["bursts"].reshape(r_values.size, orbits)
    e = res.obs[0]["exposure"].reshape(r_values.size, orbits)
    return [
        {"r": float(rv), "rate": mean_time(bb, ee, overdispersed=True, level=level), "hops": bb, "exposure": ee}
        for rv, bb, ee in zip(r_values, b, e)
    ]


def lyapunov_at(
    r: float, ics: dict, orbits: int, n: int, cost: Cost | None = None, transient: int = 1000, base: Params = R2_START
) -> dict:
    """Largest Lyapunov exponent (per impact, QR method on the engine's
    :class:`~gear_rattle.mapimpl.engine.observers.Tangent`, turned into exponents by
    :func:`~gear_rattle.mapimpl.engine.exponents.exponents`) of ``orbits`` band orbits (the first states
    of ``ics``) at ``r``, over ``n`` impacts after ``transient``: positive on every orbit means a chaotic
    attractor, not a periodic window.  Returns ``r``, ``lam1_min``, ``lam1_mean``, ``lam1_max`` (of the
    free steps; NaN where an orbit ended early: it has no exponent), ``orbits``, ``n``, ``stuck``
    (sticking steps), ``ended`` (orbits that ended early), ``chaotic`` (every orbit ran to the end, none
    stuck, and ``lam1_min > 0``)."""
    idx = np.arange(orbits) % ics["theta"].size
    res = engine_run(
        cost,
        "r1: Lyapunov at the bracket's upper end",
        ics["theta"][idx],
        ics["sdot"][idx],
        ics["wall"][idx],
        base.replace(r=float(r)),
        Tangent(n_start=transient),
        cap=transient + n,
    )
    ex = exponents(res)
    lam1 = ex.lam_free[:, 0]
    return {
        "r": float(r),
        "lam1_min": float(lam1.min()),
        "lam1_mean": float(lam1.mean()),
        "lam1_max": float(lam1.max()),
        "orbits": int(orbits),
        "n": int(n),
        "stuck": int(ex.n_stuck.sum()),
        "ended": ex.ended,
        "chaotic": bool(np.all(ex.lam[:, 0] > 0.0)),
    }


def _arrays(rows):
    r = np.array([x["r"] for x in rows])
    k = np.array([x["rate"].events for x in rows], float)
    E = np.array([x["rate"].exposure for x in rows], float)
    phi = np.array([x["rate"].dispersion for x in rows], float)
    return r, k, E, phi


def locate_r1(
    profile: str = "quick", branch=None, progress=None, seed: int = 1, *, sizes: dict | None = None
) -> R1Result:
    """Locate the interior crisis r1 (alpha = 3, Figs. 6-7) from band hops (the module docstring).

    Parameters
    ----------
    profile : {"quick", "paper"}, optional
        Run sizes: :data:`validation.profiles.PROFILES` ``[profile]["r1"]``.
    branch : Branch, optional
        The 6-impact branch (default :func:`gear_rattle.mapimpl.branches.six_impact_branch`): the saddle orbit at r1 gives the
        crisis exponent.
    progress : optional
        Unused (the engine runs show their own progress where stderr is a terminal).
    seed : int, optional
        Seed of the initial conditions drawn on the 6-band attractor.
    sizes : dict, optional
        Run sizes that replace the profile's (keys of :data:`validation.profiles.PROFILES` ``[profile]["r1"]``;
        the result's ``profile`` is then ``"<profile>+sizes"``).

    Returns
    -------
    R1Result
        r1 and its error (the crisis-law fit or the bracket), the fits, the bracket by direct observation
        and the hop counts (:class:`~.results.R1Result`).

    Examples
    --------
    With tiny run sizes (a rough estimate; the paper profile locates r1 to ~1e-6, docs/dynamics.md):

    >>> from gear_rattle.validation.dynamics.crises.r1 import locate_r1
    >>> tiny = {
    ...     "ics": 8,
    ...     "settle": 500,
    ...     "coarse": [0.7410, 0.7413],
    ...     "fine": [2e-5],
    ...     "orbits": 8,
    ...     "cap": 4000,
    ...     "probe_orbits": 8,
    ...     "probe_cap": 4000,
    ...     "max_probes": 1,
    ...     "lyap_orbits": 2,
    ...     "lyap_n": 1000,
    ... }
    >>> res = locate_r1(sizes=tiny)
    >>> bool(0.740 < res.value < 0.742), res.method in ("fit", "bracket"), len(res.hops) >= 3
    (True, True, True)
    """
    pr = get_profile(profile, "r1", sizes)
    seed = check_int("seed", seed, 0, 2**32 - 1)
    cost = Cost()
    with Timer(cost, "r1: 6-impact branch"):
        br = branch or six_impact_branch()
    ics = band_ics(pr["r_ref"], pr["ics"], pr["settle"], seed=seed, cost=cost)
    rows = hop_counts(pr["coarse"], ics, pr["orbits"], pr["cap"], cost=cost, label="r1: coarse scan")
    sad0 = orbit_on_branch(br, float(np.max(pr["coarse"])), "saddle")
    g0 = goy_exponent(sad0.multipliers)
    r, k, E, phi = _arrays(rows)
    first = fit_crisis(r, k, E, "below", g=g0, dispersion=phi)
    rows += hop_counts(
        np.round(first.mu_c - np.asarray(pr["fine"]), 10),
        ics,
        pr["orbits"],
        pr["cap"],
        cost=cost,
        label="r1: fine scan",
    )
    r, k, E, phi = _arrays(rows)
    sad = orbit_on_branch(br, fit_crisis(r, k, E, "below", g=g0, dispersion=phi).mu_c, "saddle")
    g = goy_exponent(sad.multipliers)
    goy = fit_crisis(r, k, E, "below", g=g, dispersion=phi)
    # bracket runs (probe_orbits x probe_cap impacts each): start beside the fit, then bisect; one run
    # on the hop side near r1 for the mean time between hops there
    strong = pr["probe_orbits"] * (pr["probe_cap"] - N0)
    for _ in range(int(pr["max_probes"])):
        r, k, E, phi = _arrays(rows)
        err = math.hypot(goy.err, range_systematic(r, k, E, "below", g=g, dispersion=phi)[0])
        step = max(2 * err, pr["target"] / 2)
        probes = next_probes(r, k, E, "below", goy.mu_c, step, pr["target"], strong, goy.mu_c - pr["target"] / 2)
        if not probes:
            break
        rows += hop_counts(
            np.round(probes, 10), ics, pr["probe_orbits"], pr["probe_cap"], cost=cost, label="r1: bracket runs"
        )
        r, k, E, phi = _arrays(rows)
        goy = fit_crisis(r, k, E, "below", g=g, dispersion=phi)
    with Timer(cost, "r1: fits"):
        r, k, E, phi = _arrays(rows)
        goy = fit_crisis(r, k, E, "below", g=g, dispersion=phi)
        free = fit_crisis(r, k, E, "below", dispersion=phi)
        syst_goy, sub_goy = range_systematic(r, k, E, "below", g=g, dispersion=phi)
        syst_free, sub_free = range_systematic(r, k, E, "below", dispersion=phi)
        brk = bracket(r, k, E, "below", min_exposure=strong)
        margin = goy.distance_at(brk.clear_bound) if np.isfinite(brk.clear) else math.nan
    window = lyapunov_at(brk.clear, ics, pr["lyap_orbits"], pr["lyap_n"], cost=cost) if np.isfinite(brk.clear) else None
    total = math.hypot(goy.err, syst_goy)
    # a window at the upper end would not bound r1: then the fit alone
    used = brk if window is None or window["chaotic"] else Bracket("below", brk.seen, math.nan, 0.0, 0.0, brk.level)
    where = locate(goy.mu_c, total, used, margin if np.isfinite(margin) else 0.0)
    table = [
        {"r": x["r"], **{kk: v for kk, v in x["rate"].as_dict().items() if kk != "level"}}
        for x in sorted(rows, key=lambda x: x["r"])
    ]
    seen = [x for x in rows if x["r"] == brk.seen]
    near_rate = mean_time(
        np.concatenate([x["hops"] for x in seen]), np.concatenate([x["exposure"] for x in seen]), overdispersed=True
    )
    return R1Result(
        **located_fields(where, goy, free, syst_goy, syst_free),
        subranges_goy=sub_goy,
        subranges_free=sub_free,
        goy_exponent=g,
        saddle=sad,
        bracket=brk,
        bracket_margin=margin,
        lower_bound=brk.seen,
        upper_bound=brk.clear,
        consistent=where.outside <= 1.0 and np.isfinite(brk.clear),
        clear_lyapunov=window,
        near={"r": brk.seen, **near_rate.as_dict()},
        hops=table,
        paper_fig7={"r": PAPER_R1_FIG7, "below_r1_by": where.value - PAPER_R1_FIG7},
        ics={k_: ics[k_] for k_ in ("r_ref", "settle", "drawn", "rejected")} | {"n": int(ics["theta"].size)},
        cost=cost.as_dict(),
        profile=_label(profile, sizes),
    )


__all__ = [
    "PAPER_R1_FIG7",
    "BANDS",
    "THRESHOLD",
    "MIN_INSIDE",
    "N0",
    "band_ics",
    "hop_counts",
    "lyapunov_at",
    "locate_r1",
]
