"""Periodic orbits and engine runs shared by the crisis analyses.

* the 6-impact period-1 orbit of Fig. 4 (alpha = 3), continued in r through its fold r2 and down its
  saddle branch (the orbit that mediates the interior crisis r1);
* the 4-impact period-1 orbit of Fig. 8 (r = 0.9), continued in alpha down through its fold
  alpha_sn ~ 1.2046 and up its saddle branch (the orbit on the basin boundary of the node that
  mediates the boundary crisis alpha1);
* :func:`engine_run`: every long run of the crisis analyses goes through the many-orbit engine
  (:func:`gear_rattle.mapimpl.engine.driver.run`) with per-orbit parameters, and its cost (impacts,
  wall and CPU seconds) is accumulated in a :class:`Cost`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ....core import _jax  # noqa: F401
import jax
from ....mapimpl.engine.driver import EngineResult, run
from ....core.params import Params
from ....mapimpl.periodic import PeriodicOrbit, find_periodic
from ....core.checks import check_int
from ....core.paper import PAPER_BOX
from ..continuation import Branch, continue_orbit

#: Starting guesses on the attractors of the paper (any nearby guess works).
R2_START = Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.80)      # stable 6-impact orbit (Fig. 4)
ALPHA1_START = Params(alpha=1.30, beta=0.1, gamma=0.1, r=0.9)  # stable 4-impact orbit (Fig. 8)
#: The paper's box of initial conditions (Figs. 9-11): 3 < tau0 < 3.5, 0 < sdot0 < 0.5 (core.paper.PAPER_BOX).
BOX = PAPER_BOX


@dataclass
class Cost:
    """Work of a sequence of engine runs: ``impacts`` (map iterations), ``wall_s`` and ``cpu_s`` (process
    CPU time, all threads: on a shared machine the wall time says little), ``runs``."""

    impacts: int = 0
    wall_s: float = 0.0
    cpu_s: float = 0.0
    runs: int = 0
    parts: list = field(default_factory=list)

    def add(self, label: str, impacts: int, wall: float, cpu: float) -> None:
        self.impacts += int(impacts)
        self.wall_s += wall
        self.cpu_s += cpu
        self.runs += 1
        self.parts.append({"label": label, "impacts": int(impacts), "wall_s": wall, "cpu_s": cpu})

    def as_dict(self) -> dict:
        return {"impacts": self.impacts, "wall_s": self.wall_s, "cpu_s": self.cpu_s, "runs": self.runs,
                "parts": list(self.parts)}


class Timer:
    """Context manager adding the wall and CPU time of a block (no impacts) to a :class:`Cost`."""

    def __init__(self, cost: Cost, label: str):
        self.cost, self.label = cost, label

    def __enter__(self):
        self.w0, self.c0 = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc):
        self.cost.add(self.label, 0, time.perf_counter() - self.w0, time.process_time() - self.c0)
        return False


def engine_run(cost: Cost | None, label: str, theta, sdot, wall, params: dict | Params, observers, cap: int,
               lanes: int | None = None, progress=None) -> EngineResult:
    """:func:`gear_rattle.mapimpl.engine.driver.run` with its cost added to ``cost``.  ``lanes``: default
    as many as there are orbits per device, up to 512 on the CPU and 65536 on an accelerator (these
    runs have few, long orbits; a micro-step has a fixed cost, so wide blocks pay)."""
    if lanes is None:
        lanes = 512 if jax.default_backend() == "cpu" else 65536
    w0, c0 = time.perf_counter(), time.process_time()
    res = run(theta, sdot, wall, params, observers, cap=cap, lanes=lanes, progress=progress, label=label)
    if cost is not None:
        cost.add(label, res.impacts, time.perf_counter() - w0, time.process_time() - c0)
    return res


def per_orbit(base: Params, name: str, values) -> dict:
    """Per-orbit parameter arrays for :func:`engine_run`: ``name`` takes ``values``, the rest ``base``."""
    v = np.asarray(values, np.float64)
    return {**base.as_dict(), name: v}


def box_ics(n: int, seed: int, box=BOX) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``n`` random pre-impact states in ``box`` (``numpy.random.default_rng(seed)``; sdot0 > 0 at s = 0)."""
    n = check_int("n", n, 1, 10_000_000)
    rng = np.random.default_rng(seed)
    th = rng.uniform(box[0], box[1], n)
    sd = rng.uniform(box[2], box[3], n)
    sd = np.where(sd == 0.0, 1e-12, sd)
    return th, sd, np.zeros(n, np.int32)


def attractor_point(params: Params, n: int = 5000, tau0: float = 0.0, sdot0: float = 0.5) -> tuple[float, float]:
    """The pre-impact state ``(theta, sdot)`` after ``n`` impacts from ``(tau0, sdot0)`` (engine run): a
    guess on the attractor."""
    n = check_int("n", n, 1, 100_000_000)
    if not (np.isfinite(tau0) and np.isfinite(sdot0) and sdot0 != 0):
        raise ValueError(f"sdot0={sdot0!r} is out of range: allowed finite, nonzero")
    r = run([tau0], [sdot0], [0 if sdot0 > 0 else -1], params, (), cap=n, lanes=8, devices=1, progress=False)
    return float(r.theta[0]), float(r.sdot[0])


def six_impact_branch(base: Params = R2_START, r_min: float = 0.735, r_max: float = 0.83, ds: float = 2e-3,
                      max_points: int = 200) -> Branch:
    """Continue the 6-impact period-1 orbit of Fig. 4 from ``base`` (r = 0.8) up through its fold r2 and
    down the saddle branch to ``r_min``.  ``branch.folds[0]`` is r2."""
    th, sd = attractor_point(base)
    return continue_orbit(base, "r", th, sd, 6, 1, mu_range=(r_min, r_max), direction=1, ds=ds,
                          max_points=max_points)


def four_impact_branch(base: Params = ALPHA1_START, a_min: float = 1.15, a_max: float = 1.32, ds: float = 2e-3,
                       max_points: int = 200) -> Branch:
    """Continue the 4-impact period-1 orbit of Fig. 8 from ``base`` (alpha = 1.3) down through its fold
    alpha_sn and up the saddle branch to ``a_max``.  ``branch.folds[0]`` is alpha_sn."""
    th, sd = attractor_point(base)
    return continue_orbit(base, "alpha", th, sd, 4, 1, mu_range=(a_min, a_max), direction=-1, ds=ds,
                          max_points=max_points)


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
    mus, taus, sds = a["mu"][sl], a["tau"][sl], a["sdot"][sl]
    if not (mus.min() <= mu <= mus.max()):
        raise ValueError(f"{branch.param}={mu!r} is out of range: allowed [{mus.min()}, {mus.max()}] on the {part} branch")
    j = int(np.argmin(np.abs(mus - mu)))
    params = branch.params.replace(**{branch.param: float(mu)})
    o = find_periodic(params, taus[j], sds[j], branch.impacts, branch.turns)
    if not o.converged:
        raise ValueError(f"Newton did not converge on the {part} branch at {branch.param}={mu!r}")
    return o


def orbit_points(orbits) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pre-impact points ``(theta, sdot, wall)`` of one or several periodic orbits, concatenated (a
    capture target: the wall of a pre-impact state follows the sign of its velocity)."""
    orbits = [orbits] if isinstance(orbits, PeriodicOrbit) else list(orbits)
    th = np.concatenate([np.mod(np.asarray(o.tau, float), 2 * np.pi) for o in orbits])
    sd = np.concatenate([np.asarray(o.sdot, float) for o in orbits])
    return th, sd, np.where(sd > 0, 0, -1).astype(np.int32)
