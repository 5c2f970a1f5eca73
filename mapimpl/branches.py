"""The paper's period-1 orbits, continued in a parameter through their folds (numerical methods that
several layers use: the crisis analyses and the golden suite's orbit records).

* the 6-impact period-1 orbit of Fig. 4 (alpha = 3), continued in r through its fold r2 and down its
  saddle branch (the orbit that mediates the interior crisis r1): :func:`six_impact_branch`;
* the 4-impact period-1 orbit of Fig. 8 (r = 0.9), continued in alpha down through its fold
  alpha_sn ~ 1.2046 and up its saddle branch (the orbit on the basin boundary of the node that
  mediates the boundary crisis alpha1): :func:`four_impact_branch`;
* :func:`attractor_point`, a guess on an attractor (an engine run), and :func:`orbit_on_branch`, the
  Newton-refined orbit of a branch at a parameter value.
"""

from __future__ import annotations

import numpy as np

from ..core.checks import check_int
from ..core.params import Params
from .continuation import Branch, continue_orbit
from .engine.driver import run
from .engine.options import Execution
from .periodic import PeriodicOrbit, find_periodic

#: Starting guesses on the attractors of the paper (any nearby guess works).
R2_START = Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.80)  # stable 6-impact orbit (Fig. 4)
ALPHA1_START = Params(alpha=1.30, beta=0.1, gamma=0.1, r=0.9)  # stable 4-impact orbit (Fig. 8)


def attractor_point(params: Params, n: int = 5000, tau0: float = 0.0, sdot0: float = 0.5) -> tuple[float, float]:
    """The pre-impact state ``(theta, sdot)`` after ``n`` impacts from ``(tau0, sdot0)`` (engine run): a
    guess on the attractor."""
    n = check_int("n", n, 1, 100_000_000)
    if not (np.isfinite(tau0) and np.isfinite(sdot0) and sdot0 != 0):
        raise ValueError(f"sdot0={sdot0!r} is out of range: allowed finite, nonzero")
    one = Execution(lanes=8, devices=1)
    r = run([tau0], [sdot0], [0 if sdot0 > 0 else -1], params, (), cap=n, execution=one, progress=False)
    return float(r.theta[0]), float(r.sdot[0])


def six_impact_branch(
    base: Params = R2_START, r_min: float = 0.735, r_max: float = 0.83, ds: float = 2e-3, max_points: int = 200
) -> Branch:
    """Continue the 6-impact period-1 orbit of Fig. 4 from ``base`` (r = 0.8) up through its fold r2 and
    down the saddle branch to ``r_min``.  ``branch.folds[0]`` is r2."""
    th, sd = attractor_point(base)
    return continue_orbit(base, "r", th, sd, 6, 1, mu_range=(r_min, r_max), direction=1, ds=ds, max_points=max_points)


def four_impact_branch(
    base: Params = ALPHA1_START, a_min: float = 1.15, a_max: float = 1.32, ds: float = 2e-3, max_points: int = 200
) -> Branch:
    """Continue the 4-impact period-1 orbit of Fig. 8 from ``base`` (alpha = 1.3) down through its fold
    alpha_sn and up the saddle branch to ``a_max``.  ``branch.folds[0]`` is alpha_sn."""
    th, sd = attractor_point(base)
    return continue_orbit(
        base, "alpha", th, sd, 4, 1, mu_range=(a_min, a_max), direction=-1, ds=ds, max_points=max_points
    )


def orbit_on_branch(branch: Branch, mu: float, part: str = "saddle") -> PeriodicOrbit:
    """Newton-refined orbit of ``branch`` at parameter ``mu``: ``part="saddle"`` (after the first fold)
    or ``"node"`` (before it)."""
    if part not in ("saddle", "node"):
        raise ValueError(f"part={part!r} is out of range: allowed 'saddle' or 'node'")
    a = branch.arrays()
    if a["mu"].size < 2:
        raise ValueError("the branch has fewer than 2 points")
    k = int(np.argmax(a["mu"])) if branch.param == "r" else int(np.argmin(a["mu"]))
    sl = slice(k, None) if part == "saddle" else slice(0, k + 1)
    mus, thetas, sds = a["mu"][sl], a["tau"][sl], a["sdot"][sl]  # "tau": the arrays' key of the phases
    if not (mus.min() <= mu <= mus.max()):
        raise ValueError(
            f"{branch.param}={mu!r} is out of range: allowed [{mus.min()}, {mus.max()}] on the {part} branch"
        )
    j = int(np.argmin(np.abs(mus - mu)))
    params = branch.params.replace(**{branch.param: float(mu)})
    o = find_periodic(params, thetas[j], sds[j], branch.impacts, branch.turns)
    if not o.converged:
        raise ValueError(f"Newton did not converge on the {part} branch at {branch.param}={mu!r}")
    return o


__all__ = [
    "R2_START",
    "ALPHA1_START",
    "attractor_point",
    "six_impact_branch",
    "four_impact_branch",
    "orbit_on_branch",
]
