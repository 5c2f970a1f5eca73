"""alpha1: the boundary crisis of Fig. 8 (r = 0.9, beta = gamma = 0.1), from escape times of the
pre-crisis chaotic set.

**Mechanism.**  The stable 4-impact period-1 orbit (the node) is born with a saddle 4-impact orbit in
a fold at alpha_sn ~ 1.2046, well below alpha1, and coexists with the chaotic attractor.  At alpha1
the attractor touches the basin boundary of the node (the stable manifold of the saddle, assumed to
mediate the crisis) and becomes a chaotic saddle: above alpha1 orbits on it escape to the node after
exponentially distributed times of mean ``T(alpha) ~ C (alpha - alpha1)^-g``.

**Initial conditions on the chaotic set.**  Random points of the paper's box are iterated for
``settle`` impacts at ``alpha_ref`` (below alpha1, where the attractor and the node coexist); those
not captured by the node (:class:`~gear_rattle.mapimpl.engine.observers.Capture`) are on the chaotic
attractor and their end states are the initial conditions of every later run (:func:`attractor_ics`).
Box points mixed with points that stick or lie in the node's basin would bias the lifetimes.

**Escape.**  The first impact within ``DELTA`` (sup norm) of the node (:func:`lifetimes`; one engine run
over all alpha values, per-orbit parameters; the target is the union of the nodes of all alpha values
of the run, which is safe because the chaotic set keeps more than ``APPROACH`` away from every node:
the run records the first impact within ``APPROACH`` too, and every capture passes from ``APPROACH``
to ``DELTA`` within a few tens of impacts, reported as ``approach_lag_max``).  Counting starts at
impact ``N0`` (left truncation: the first impacts relax the states from ``alpha_ref`` onto the set at
alpha); the mean lifetime is the censored maximum-likelihood estimate
(:func:`~.stats.censored_lifetimes`: total exposure / escapes, exact Poisson interval).

**Location** (:func:`locate_alpha1`): a coarse scan, a fit, a fine scan at offsets above the first
estimate, then the fits of the crisis law (exponent free, and fixed to the GOY exponent of the saddle
4-impact orbit) with the fit-range systematic, and a bracket by direct observation: escapes seen at
``a`` (so alpha1 < a), none in ``N x L`` impacts at ``b`` (so ``T(b) > N L / 3`` at 95 %: alpha1 > b
up to the distance at which the law gives that lifetime).  Finally the mean lifetime at the paper's
alpha = 1.24370 and the alpha at which it equals the length of a finite bifurcation diagram.
"""

from __future__ import annotations

import math

import numpy as np

from ....core import jax_config  # noqa: F401
from ....mapimpl.engine.observers import Capture
from ....core.params import Params
from ....core.status import Status
from ....mapimpl.branches import ALPHA1_START, four_impact_branch, orbit_on_branch
from .orbits import Cost, Timer, box_ics, engine_run, orbit_points, per_orbit
from ....core.checks import check_int
from ...profiles import get_profile, label as _label
from .results import Alpha1Result, located_fields
from .stats import LEVEL, bracket, censored_lifetimes, fit_crisis, goy_exponent, locate, next_probes, range_systematic
from ....core.paper import DELTA, PAPER_PARAMS
from ...paper import PAPER

#: The paper's value (Section 4): "alpha1 ~ 1.24370".
PAPER_ALPHA1 = float(PAPER["alpha1"].value)
#: The wider approach distance recorded beside the capture distance (core.paper.DELTA, as in Figs. 9-11).
APPROACH = 2e-2
#: Counting starts at this impact (left truncation).
N0 = 100
#: Length (transient + recorded impacts) of a bifurcation diagram like Fig. 8's in this project's
#: paper report (validation/report/sec_dynamics.py: 5000 discarded, 400 recorded).
DIAGRAM_IMPACTS = 5400


#: The deep probe is placed where the fitted law predicts this multiple of ``T_deep``: the law is
#: extrapolated there, and aiming at ``T_deep`` itself measured 4.6e5 and 5.2e5 (paper profile).
DEEP_AIM = 1.5


def nodes(branch, alphas) -> list:
    """The stable 4-impact orbit (node branch) at each alpha."""
    return [orbit_on_branch(branch, float(a), "node") for a in np.atleast_1d(alphas)]


def attractor_ics(
    branch, alpha_ref: float, n: int, settle: int, seed: int = 0, cost: Cost | None = None, base: Params = ALPHA1_START
) -> dict:
    """``n`` states on the chaotic attractor at ``alpha_ref`` (< alpha1): end states of box orbits that
    the node did not capture in ``settle`` impacts.  Returns ``theta, sdot, wall`` and ``drawn``,
    ``captured`` (box orbits captured by the node: its basin)."""
    th, sd, w = orbit_points(nodes(branch, [alpha_ref]))
    obs = Capture(th, sd, w, np.array([DELTA]))
    out_th: list[float] = []
    out_sd: list[float] = []
    out_w: list[int] = []
    drawn = captured = 0
    for attempt in range(6):
        m = int(math.ceil(1.3 * (n - len(out_th)))) + 8
        t0, s0, w0 = box_ics(m, seed + 1000 * attempt)
        r = engine_run(
            cost, "alpha1: settle on the attractor", t0, s0, w0, base.replace(alpha=alpha_ref), obs, cap=settle
        )
        ok = r.status == Status.CAPPED
        drawn += m
        captured += int(np.sum(r.status == Status.STOPPED))
        out_th += list(r.theta[ok])
        out_sd += list(r.sdot[ok])
        out_w += list(r.wall[ok])
        if len(out_th) >= n:
            break
    else:
        raise RuntimeError(
            f"only {len(out_th)} of {drawn} box orbits stayed off the node at alpha_ref={alpha_ref} "
            f"(is alpha_ref below alpha1?)"
        )
    return {
        "theta": np.array(out_th[:n]),
        "sdot": np.array(out_sd[:n]),
        "wall": np.array(out_w[:n], np.int32),
        "drawn": drawn,
        "captured": captured,
        "alpha_ref": float(alpha_ref),
        "settle": int(settle),
    }


def _first(ics: dict, n: int) -> dict:
    """The first ``n`` initial conditions of :func:`attractor_ics`' result (its bookkeeping kept)."""
    return {k: (v[:n] if k in ("theta", "sdot", "wall") else v) for k, v in ics.items()}


def lifetimes(
    alphas,
    ics: dict,
    branch,
    cap: int,
    n0: int = N0,
    cost: Cost | None = None,
    label: str = "alpha1: lifetimes",
    base: Params = ALPHA1_START,
    level: float = LEVEL,
) -> list[dict]:
    """Mean escape time from the chaotic set at each alpha: every initial condition of ``ics`` at every
    alpha, one engine run, capped at ``cap`` impacts.  Per alpha: ``alpha``, ``rate``
    (:class:`~.stats.MeanTime`), ``dropped`` (escaped before ``n0``), ``approach_lag_max`` (largest
    number of impacts from the first approach within ``APPROACH`` of a node to the capture)."""
    alphas = np.atleast_1d(np.asarray(alphas, float))
    m = ics["theta"].size
    th, sd, w = orbit_points(nodes(branch, alphas))
    A = np.repeat(alphas, m)
    r = engine_run(
        cost,
        label,
        np.tile(ics["theta"], alphas.size),
        np.tile(ics["sdot"], alphas.size),
        np.tile(ics["wall"], alphas.size),
        per_orbit(base, "alpha", A),
        Capture(th, sd, w, np.array([APPROACH, DELTA])),
        cap=cap,
    )
    hit = r.obs[0]["hit"]
    out = []
    for i, a in enumerate(alphas):
        sl = slice(i * m, (i + 1) * m)
        h = hit[sl]
        captured = h[:, 1] >= 0
        ended = (r.status[sl] != Status.CAPPED) & ~captured  # stuck forever / no impact: censored where they ended
        rate, dropped = censored_lifetimes(h[:, 1], r.n[sl], n0, level)
        lag = int(np.max(h[captured, 1] - h[captured, 0])) if captured.any() else 0
        out.append(
            {
                "alpha": float(a),
                "rate": rate,
                "dropped": dropped,
                "approach_lag_max": lag,
                "other_end": int(ended.sum()),
            }
        )
    return out


def _arrays(rows: list[dict]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a = np.array([x["alpha"] for x in rows])
    k = np.array([x["rate"].events for x in rows], float)
    E = np.array([x["rate"].exposure for x in rows], float)
    return a, k, E


def _fits(rows, g):
    a, k, E = _arrays(rows)
    goy = fit_crisis(a, k, E, "above", g=g)
    free = fit_crisis(a, k, E, "above")
    syst_goy, sub_goy = range_systematic(a, k, E, "above", g=g)
    syst_free, sub_free = range_systematic(a, k, E, "above")
    return goy, free, syst_goy, sub_goy, syst_free, sub_free


def _scans(pr: dict, br, ics: dict, cost: Cost):
    """The coarse scan, a first GOY fit, the fine scan above it: the rows, the GOY exponent ``g`` of the
    saddle at the refitted crisis, that saddle and the GOY fit."""
    rows = lifetimes(pr["coarse"], ics, br, pr["cap"], cost=cost, label="alpha1: coarse scan")
    sad0 = orbit_on_branch(br, float(np.min(pr["coarse"])), "saddle")
    g0 = goy_exponent(sad0.multipliers)
    first = fit_crisis(*_arrays(rows), "above", g=g0)
    fine = np.round(first.mu_c + np.asarray(pr["fine"]), 9)
    rows += lifetimes(fine, ics, br, pr["cap"], cost=cost, label="alpha1: fine scan")
    # GOY exponent of the saddle at the (refitted) crisis
    a1 = fit_crisis(*_arrays(rows), "above", g=g0).mu_c
    sad = orbit_on_branch(br, a1, "saddle")
    g = goy_exponent(sad.multipliers)
    return rows, g, sad, fit_crisis(*_arrays(rows), "above", g=g)


def _bracket_runs(pr: dict, br, probe_ics: dict, rows: list, g: float, goy, strong: float, cost: Cost):
    """Bracket runs (N x probe_cap impacts each): a bisection started from the fit, and a run where the
    law predicts DEEP_AIM x T_deep unless a mean lifetime >= T_deep was measured.  Appends to ``rows``."""
    for _ in range(int(pr["max_probes"])):
        a, k, E = _arrays(rows)
        err = math.hypot(goy.err, range_systematic(a, k, E, "above", g=g)[0])
        deep = None
        if not np.any((k > 0) & (E >= pr["T_deep"] * np.maximum(k, 1))):
            deep = goy.mu_at(DEEP_AIM * pr["T_deep"])
        probes = next_probes(a, k, E, "above", goy.mu_c, max(2 * err, pr["target"] / 2), pr["target"], strong, deep)
        if not probes:
            break
        rows += lifetimes(np.round(probes, 9), probe_ics, br, pr["probe_cap"], cost=cost, label="alpha1: bracket runs")
        goy = fit_crisis(*_arrays(rows), "above", g=g)


def _lifetime_table(rows: list) -> list[dict]:
    """Per alpha (sorted): the mean lifetime ``T`` with its 95 % interval and the bookkeeping."""
    table = []
    for x in sorted(rows, key=lambda x: x["alpha"]):
        rt = x["rate"]
        table.append(
            {
                "alpha": x["alpha"],
                "T": rt.T,
                "lo": rt.lo,
                "hi": rt.hi,
                "events": rt.events,
                "exposure": rt.exposure,
                "orbits": rt.orbits,
                "dropped": x["dropped"],
                "approach_lag_max": x["approach_lag_max"],
                "other_end": x["other_end"],
            }
        )
    return table


def _at_paper_alpha1(table: list[dict], goy) -> dict:
    """The measured mean lifetime at the paper's alpha1 (the scan row nearest to it) and the law's."""
    row = min(table, key=lambda x: abs(x["alpha"] - PAPER_ALPHA1))
    return {
        "alpha": PAPER_ALPHA1,
        "measured_at": row["alpha"],
        "T": row["T"],
        "lo": row["lo"],
        "hi": row["hi"],
        "diagram_impacts_equal": row["T"],
        "T_law": float(goy.T(PAPER_ALPHA1)),
    }


def locate_alpha1(
    profile: str = "quick", branch=None, progress=None, seed: int = 0, *, sizes: dict | None = None
) -> Alpha1Result:
    """Locate the boundary crisis alpha1 (Fig. 8, r = 0.9) from escape times of the pre-crisis chaotic
    set (the module docstring).

    Parameters
    ----------
    profile : {"quick", "paper"}, optional
        Run sizes: :data:`validation.profiles.PROFILES` ``[profile]["alpha1"]``.
    branch : Branch, optional
        The 4-impact branch (default :func:`gear_rattle.mapimpl.branches.four_impact_branch`): its fold alpha_sn, the saddle
        orbit at alpha1 and the stable orbit that captures the escapes.
    progress : optional
        Unused (the engine runs show their own progress where stderr is a terminal).
    seed : int, optional
        Seed of the initial conditions drawn on the chaotic attractor below alpha1.
    sizes : dict, optional
        Run sizes that replace the profile's (keys of :data:`validation.profiles.PROFILES` ``[profile]["alpha1"]``;
        the result's ``profile`` is then ``"<profile>+sizes"``).

    Returns
    -------
    Alpha1Result
        alpha1 and its error (the crisis-law fit or the bracket), the fits, the bracket and the lifetimes
        (:class:`~.results.Alpha1Result`).

    Examples
    --------
    With tiny run sizes (a rough estimate; the paper profile, docs/dynamics.md):

    >>> from gear_rattle.validation.dynamics.crises.alpha1 import locate_alpha1
    >>> tiny = {
    ...     "ics": 8,
    ...     "settle": 500,
    ...     "coarse": [1.2442, 1.2465],
    ...     "fine": [1.5e-5],
    ...     "cap": 4000,
    ...     "probe_cap": 4000,
    ...     "max_probes": 1,
    ...     "T_deep": 1e3,
    ... }
    >>> res = locate_alpha1(sizes=tiny)
    >>> bool(1.2420 < res.value < 1.2450), bool(res.alpha_sn < res.value)
    (True, True)
    """
    pr = get_profile(profile, "alpha1", sizes)
    seed = check_int("seed", seed, 0, 2**32 - 1)
    cost = Cost()
    with Timer(cost, "alpha1: 4-impact branch"):
        br = branch or four_impact_branch()
    if not br.folds:
        raise RuntimeError("the 4-impact branch has no fold in its range")
    n_probe = int(pr.get("probe_ics", pr["ics"]))
    probe_ics = attractor_ics(br, pr["alpha_ref"], max(pr["ics"], n_probe), pr["settle"], seed=seed, cost=cost)
    ics = _first(probe_ics, pr["ics"])  # the scans use the first ``ics`` of them
    probe_ics = _first(probe_ics, n_probe)
    rows, g, sad, goy = _scans(pr, br, ics, cost)
    strong = probe_ics["theta"].size * (pr["probe_cap"] - N0)
    _bracket_runs(pr, br, probe_ics, rows, g, goy, strong, cost)
    with Timer(cost, "alpha1: fits"):
        goy, free, syst_goy, sub_goy, syst_free, sub_free = _fits(rows, g)
        a, k, E = _arrays(rows)
        brk = bracket(a, k, E, "above", min_exposure=strong)
        margin = goy.distance_at(brk.clear_bound) if np.isfinite(brk.clear) else math.nan
        node = orbit_on_branch(br, PAPER_PARAMS.alpha, "node")
    total = math.hypot(goy.err, syst_goy)
    where = locate(goy.mu_c, total, brk, margin if np.isfinite(margin) else 0.0)
    table = _lifetime_table(rows)
    finite_T = [x["T"] for x in table if x["events"] > 0]
    return Alpha1Result(
        **located_fields(where, goy, free, syst_goy, syst_free),
        subranges_goy=sub_goy,
        subranges_free=sub_free,
        goy_exponent=g,
        saddle=sad,
        alpha_sn=br.folds[0].mu,
        node=node,
        branch=br,
        bracket=brk,
        bracket_margin=margin,
        consistent=where.outside <= 1.0 and np.isfinite(brk.clear),
        lifetimes=table,
        T_max_measured=float(max(finite_T)) if finite_T else math.nan,
        paper=_at_paper_alpha1(table, goy),
        diagram={"impacts": DIAGRAM_IMPACTS, "alpha_apparent": goy.mu_at(DIAGRAM_IMPACTS)},
        ics={k_: ics[k_] for k_ in ("alpha_ref", "settle", "drawn", "captured")}
        | {"n": int(ics["theta"].size), "probe_n": int(probe_ics["theta"].size)},
        cost=cost.as_dict(),
        profile=_label(profile, sizes),
    )


__all__ = [
    "PAPER_ALPHA1",
    "APPROACH",
    "N0",
    "DIAGRAM_IMPACTS",
    "DEEP_AIM",
    "nodes",
    "attractor_ics",
    "lifetimes",
    "locate_alpha1",
]
