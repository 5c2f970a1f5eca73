"""The catalogue of shipped orbit records: the periodic orbits and bifurcation points of
``validation/golden/orbits`` (:data:`CASES`), found in float64 first (our :func:`mapimpl.periodic.find_periodic`,
the continuation and its fold/flip location of :mod:`mapimpl.continuation`: the *seed*,
:func:`float64_seeds`), then proven by :mod:`mapimpl.certified.periodic` (Krawczyk operator, flights,
multipliers: :func:`certify_case`) and made a record (:mod:`.orbit_records`), proven again from its own
decimal intervals (:func:`build`).  The float64 seeds never feed the numbers, only the guess:
:func:`certify_case` from any guess that Newton takes to the same zero gives the same record.
"""

from __future__ import annotations

import math
from pathlib import Path

from ....core.paper import PAPER_FIG2, PAPER_PARAMS
from ....core.params import Params
from ....mapimpl.certified.periodic import certify_bifurcation, certify_periodic_orbit
from ..paths import DEFAULT_ORBITS
from ..formats.orbits import load_records
from .orbit_records import OrbitCase, dumps, loads_exact, record, verify_record

__all__ = ["CASES", "CASE_IDS", "canonical", "float64_seeds", "seeds_from_records", "certify_case", "build"]

_FIG4 = Params(3.0, 0.1, 0.1, 0.8)  # Fig. 4's window: the 6-impact period-1 orbit (alpha = 3)
_FIG11 = PAPER_PARAMS  # Figs. 9-11: the capture target, a 4-impact period-1 orbit
_AT11 = f"alpha{_FIG11.alpha:g}-r{_FIG11.r:g}"
_FIG2 = PAPER_FIG2  # Fig. 2: regular motion, a 3-impact period-1 orbit

CASES = (
    OrbitCase(
        "orbit-6-impact-stable-alpha3-r0.8",
        "periodic-orbit",
        "the stable 6-impact period-1 orbit of Fig. 4 (alpha = 3, r = 0.8, below r2)",
        _FIG4,
        6,
    ),
    OrbitCase(
        "orbit-6-impact-saddle-alpha3-r0.8",
        "periodic-orbit",
        "its saddle partner (born with it at the fold r2; mediates the interior crisis r1)",
        _FIG4,
        6,
    ),
    OrbitCase(
        f"orbit-4-impact-stable-{_AT11}",
        "periodic-orbit",
        f"the stable 4-impact period-1 orbit, capture target of Figs. 9-11 (alpha = {_FIG11.alpha:g}, "
        f"r = {_FIG11.r:g})",
        _FIG11,
        4,
    ),
    OrbitCase(
        f"orbit-4-impact-saddle-{_AT11}",
        "periodic-orbit",
        "its saddle partner (on the basin boundary; mediates the boundary crisis alpha1)",
        _FIG11,
        4,
    ),
    OrbitCase(
        "orbit-3-impact-fig2-alpha0.5-r0.9",
        "periodic-orbit",
        "the regular 3-impact period-1 orbit of Fig. 2 (alpha = 0.5, r = 0.9)",
        _FIG2,
        3,
    ),
    OrbitCase(
        "fold-r2-6-impact-alpha3",
        "fold",
        "r2: the saddle-node (fold) where the 6-impact period-1 orbit is born (alpha = 3; Figs. 4-5)",
        _FIG4,
        6,
        parameter="r",
    ),
    OrbitCase(
        "period-doubling-6-impact-alpha3",
        "period-doubling",
        "the first period doubling of the stable 6-impact orbit as r decreases from r2 (alpha = 3; Fig. 4)",
        _FIG4,
        6,
        parameter="r",
    ),
    OrbitCase(
        "fold-alpha-sn-4-impact-r0.9",
        "fold",
        "alpha_sn: the saddle-node where the 4-impact period-1 orbit is born (r = 0.9; Fig. 8)",
        _FIG11,
        4,
        parameter="alpha",
    ),
)
CASE_IDS = tuple(c.id for c in CASES)


def canonical(theta, sdot, walls=None):
    """The points of one period (phases ``theta``, or times: reduced mod 2 pi) rotated to start at the
    smallest phase (the records' convention)."""
    th = [float(t) % (2 * math.pi) for t in theta]
    k = min(range(len(th)), key=th.__getitem__)
    return th[k:] + th[:k], [float(v) for v in sdot[k:]] + [float(v) for v in sdot[:k]]


def float64_seeds() -> dict:
    """The float64 guesses of every case, found as the paper's analyses find them (slow: engine runs
    to the attractors and the continuation of both branches; JAX compilation included, ~1-2 min):
    ``{id: (theta, sdot, mu or None, note)}`` (the phases and velocities of one period)."""
    from ....mapimpl.periodic import find_periodic
    from ....mapimpl.branches import attractor_point, four_impact_branch, orbit_on_branch, six_impact_branch
    from ....mapimpl.continuation import continue_orbit, orbit_states

    seeds = {}

    def orbit_seed(o, note):
        if not o.converged:
            raise RuntimeError(f"float64 seed did not converge: {note}")
        return (*canonical(o.theta, o.sdot), None, note)

    def point_seed(base, f, impacts, note):
        if not f.converged:
            raise RuntimeError(f"float64 seed did not converge: {note}")
        th, sd = orbit_states(base.replace(**{f.param: f.mu}), f.theta, f.sdot, impacts)
        return (*canonical(th, sd), f.mu, note)

    th, sd = attractor_point(_FIG4)
    stable6 = find_periodic(_FIG4, th, sd, 6)
    seeds[CASES[0].id] = orbit_seed(stable6, "find_periodic from the attractor (5000 impacts from (0, 0.5))")
    b6 = six_impact_branch()
    seeds[CASES[1].id] = orbit_seed(orbit_on_branch(b6, 0.8, "saddle"), "continuation in r through r2, saddle branch")
    b4 = four_impact_branch()
    seeds[CASES[2].id] = orbit_seed(
        orbit_on_branch(b4, _FIG11.alpha, "node"), "continuation in alpha from 1.3, node branch"
    )
    seeds[CASES[3].id] = orbit_seed(
        orbit_on_branch(b4, _FIG11.alpha, "saddle"), "continuation in alpha through alpha_sn, saddle branch"
    )
    th, sd = attractor_point(_FIG2)
    seeds[CASES[4].id] = orbit_seed(find_periodic(_FIG2, th, sd, 3), "find_periodic from the attractor")
    seeds[CASES[5].id] = point_seed(_FIG4, b6.folds[0], 6, "continuation in r: the fold located on the extended system")
    down = continue_orbit(_FIG4, "r", stable6.theta[0], stable6.sdot[0], 6, 1, mu_range=(0.74, 0.8), direction=-1)
    if not down.flips:
        raise RuntimeError("no period doubling on the stable 6-impact branch in 0.74 <= r <= 0.8")
    seeds[CASES[6].id] = point_seed(_FIG4, down.flips[0], 6, "continuation in r down from 0.8: the first flip")
    seeds[CASES[7].id] = point_seed(_FIG11, b4.folds[0], 4, "continuation in alpha: the fold on the extended system")
    return seeds


def seeds_from_records(folder: str | Path = DEFAULT_ORBITS) -> dict:
    """Guesses from committed records (their midpoints; the record's seed note is kept): regenerates
    the records without the float64 runs, e.g. after a change of the record layout."""
    seeds = {}
    for rec in load_records(folder):
        mu = float(sum(rec.value) / 2) if rec.value is not None else None
        seeds[rec.id] = (
            [float(sum(p[:2]) / 2) for p in rec.points],
            [float(sum(p[2:]) / 2) for p in rec.points],
            mu,
            rec.data["provenance"]["seed"],
        )
    return seeds


def certify_case(case: OrbitCase, theta, sdot, mu=None):
    """The certified orbit or bifurcation point of ``case`` from the guess ``(theta, sdot[, mu])`` (the
    phases and velocities of one period)."""
    if case.kind == "periodic-orbit":
        return certify_periodic_orbit(case.params, theta, sdot, case.turns)
    assert case.parameter is not None, "a bifurcation case names its parameter (OrbitCase)"
    return certify_bifurcation(case.kind, case.params, case.parameter, theta, sdot, mu, case.turns)


def build(case: OrbitCase, seed) -> str:
    """The record text of ``case`` from ``seed`` ``(theta, sdot, mu, note)``, proven again from its text."""
    theta, sdot, mu, note = seed
    text = dumps(record(case, certify_case(case, theta, sdot, mu), note))
    verify_record(loads_exact(text))
    return text
