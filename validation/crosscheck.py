"""Agreement statistics between the three tracks (closed-form map, scipy, diffrax), for the report.

* :func:`one_step_agreement`: from the same random pre-impact states, the next impact (wall, tau,
  sdot) on each track; near-grazing impacts (within ``graze_depth`` of a tangency, where hit-or-miss
  itself is ill-conditioned) are counted and left out of the error statistics.
* :func:`jacobian_agreement`: the one-step Jacobian by three routes, each track's
  ``step_jacobian`` (:class:`core.results.Track`) -- analytic (implicit differentiation,
  :mod:`mapimpl.impact_map`), variational flow x saltation matrix (scipy) and ``jax.jacfwd``
  through the diffrax event solve.

States are drawn from the declared domain with a seeded generator, so the numbers are reproducible.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..mapimpl import Params
from ..mapimpl.forcing import forcing
from ..core.params import PARAM_NAMES
from ..core.status import Status

#: The declared cross-validation domain (issue 3).
DOMAIN = {"alpha": (0.0, 5.0), "beta": (0.01, 1.0), "gamma": (-0.5, 0.5), "r": (0.3, 1.0), "sdot": (0.05, 3.0)}


def random_cases(n: int, seed: int) -> list[tuple[Params, float, float]]:
    """``n`` (params, tau, sdot) cases drawn uniformly from :data:`DOMAIN` (sign of sdot random)."""
    if int(n) < 1:
        raise ValueError(f"n={n!r} is out of range: allowed n >= 1")
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(int(n)):
        p = Params(*(rng.uniform(*DOMAIN[k]) for k in PARAM_NAMES))
        sd = rng.uniform(*DOMAIN["sdot"]) * rng.choice([-1.0, 1.0])
        out.append((p, float(rng.uniform(0, 2 * np.pi)), float(sd)))
    return out


def _near_graze(theta: float, v: float, wall: int, p: Params, depth: float) -> bool:
    a = float(forcing(theta, p.alpha, p.beta, p.gamma)) - p.beta * v
    d = 1.0 if wall == 0 else -1.0
    return d * a < 0.0 and v * v / (2.0 * abs(a)) < depth


@dataclass
class OneStep:
    """Per track: max and median ``|tau error|``, max ``|sdot error|`` (vs the map), wall/kind mismatches,
    cases compared and cases left out as near-grazing."""

    track: str
    compared: int
    near_graze: int
    mismatched: int
    tau_max: float
    tau_median: float
    sdot_max: float


@dataclass
class _Tally:
    """One track's tally in :func:`one_step_agreement`: the deviations of its compared impacts, the
    states whose outcome differed from the map's (``mis``) and those skipped near a graze."""

    tau: list[float] = field(default_factory=list)
    sdot: list[float] = field(default_factory=list)
    mis: int = 0
    graze: int = 0


def one_step_agreement(
    n: int = 20, seed: int = 1, graze_depth: float = 1e-6, tracks=("scipy", "diffrax")
) -> list[OneStep]:
    """Next impact from ``n`` random pre-impact states on the map and on the numerical tracks."""
    from ..mapimpl.tracks import orbit

    cases = random_cases(n, seed)
    res = {t: _Tally() for t in tracks}
    for p, tau, sd in cases:
        m = orbit(p, tau, sd, 1, track="map")
        graze = m.status == Status.ACTIVE.label and _near_graze(
            float(m.theta[-1]), float(m.sdot[-1]), int(m.wall[-1]), p, graze_depth
        )
        for t in tracks:
            if graze:
                res[t].graze += 1
                continue
            o = orbit(p, tau, sd, 1, track=t)
            if o.status != m.status or list(o.kind) != list(m.kind) or not np.array_equal(o.wall, m.wall):
                res[t].mis += 1
                continue
            imp = (m.kind == "impact") & (m.n >= 1)  # impact 0 is the shared initial state
            res[t].tau.extend(np.abs(o.tau - m.tau)[imp].tolist())
            res[t].sdot.extend(np.abs(o.sdot - m.sdot)[imp].tolist())
    out = []
    for t in tracks:
        ta, sa = np.array(res[t].tau), np.array(res[t].sdot)
        out.append(
            OneStep(
                t,
                len(cases) - res[t].graze,
                res[t].graze,
                res[t].mis,
                float(ta.max()) if ta.size else float("nan"),
                float(np.median(ta)) if ta.size else float("nan"),
                float(sa.max()) if sa.size else float("nan"),
            )
        )
    return out


@dataclass
class JacobianCheck:
    """Max relative differences ``||J_route - J_analytic|| / ||J_analytic||`` over the compared states."""

    compared: int
    skipped: int
    scipy_max: float
    diffrax_max: float


def jacobian_agreement(n: int = 8, seed: int = 2, graze_depth: float = 1e-4) -> JacobianCheck:
    """The step Jacobian by three routes at ``n`` random states (sticking and near-grazing steps
    skipped): each track's :meth:`~core.results.Track.step_jacobian` -- the map's analytic one
    (implicit differentiation of Eqs. 12-13), scipy's variational flow x saltation matrix and
    ``jax.jacfwd`` through the diffrax event solve."""
    from ..mapimpl.tracks import get

    ref, routes = get("map"), {t: get(t) for t in ("scipy", "diffrax")}
    err: dict[str, list[float]] = {t: [] for t in routes}
    skipped = 0
    for p, tau, sd in random_cases(n, seed):
        m = ref.step_jacobian(p, tau, sd)
        if (
            m.stuck
            or m.status != Status.ACTIVE.label
            or _near_graze(float(np.mod(m.tau, 2 * np.pi)), m.sdot, m.wall, p, graze_depth)
        ):
            skipped += 1
            continue
        J = np.asarray(m.jac)
        nJ = np.linalg.norm(J)
        for t, track in routes.items():
            err[t].append(float(np.linalg.norm(np.asarray(track.step_jacobian(p, tau, sd).jac) - J) / nJ))
    cs, cd = err["scipy"], err["diffrax"]
    return JacobianCheck(
        len(cs), skipped, float(max(cs)) if cs else float("nan"), float(max(cd)) if cd else float("nan")
    )


__all__ = [
    "DOMAIN",
    "random_cases",
    "OneStep",
    "one_step_agreement",
    "JacobianCheck",
    "jacobian_agreement",
]
