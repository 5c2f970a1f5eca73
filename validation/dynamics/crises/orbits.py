"""Engine runs shared by the crisis analyses.

* :func:`engine_run`: every long run of the crisis analyses goes through the many-orbit engine
  (:func:`gear_rattle.mapimpl.engine.driver.run`) with per-orbit parameters, and its cost (impacts,
  wall and CPU seconds) is accumulated in a :class:`Cost`;
* :func:`box_ics`, :func:`per_orbit`, :func:`orbit_points`: initial conditions, per-orbit parameters
  and capture targets of those runs.

The periodic orbits they start from (the 6-impact orbit of Fig. 4 continued in r through r2, the
4-impact orbit of Fig. 8 continued in alpha through alpha_sn) are the library's
(:mod:`gear_rattle.mapimpl.branches`): the golden suite's orbit records use them too.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ....core import jax_config  # noqa: F401
import jax
from ....mapimpl.engine.driver import EngineResult, run
from ....mapimpl.engine.options import Execution
from ....core.params import ParamArrays, Params, param_arrays
from ....mapimpl.periodic import PeriodicOrbit
from ....core.checks import check_int
from ....core.paper import PAPER_BOX

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
        return {
            "impacts": self.impacts,
            "wall_s": self.wall_s,
            "cpu_s": self.cpu_s,
            "runs": self.runs,
            "parts": list(self.parts),
        }


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


def engine_run(
    cost: Cost | None,
    label: str,
    theta,
    sdot,
    wall,
    params: Params | ParamArrays,
    observers,
    cap: int,
    lanes: int | None = None,
    progress=None,
) -> EngineResult:
    """:func:`gear_rattle.mapimpl.engine.driver.run` with its cost added to ``cost``.  ``lanes``: default
    as many as there are orbits per device, up to 512 on the CPU and 65536 on an accelerator (these
    runs have few, long orbits; a micro-step has a fixed cost, so wide blocks pay)."""
    if lanes is None:
        lanes = 512 if jax.default_backend() == "cpu" else 65536
    w0, c0 = time.perf_counter(), time.process_time()
    execution = Execution(lanes=lanes)
    res = run(theta, sdot, wall, params, observers, cap=cap, execution=execution, progress=progress, label=label)
    if cost is not None:
        cost.add(label, res.impacts, time.perf_counter() - w0, time.process_time() - c0)
    return res


def per_orbit(base: Params, name: str, values) -> ParamArrays:
    """Per-orbit parameters for :func:`engine_run` (:func:`gear_rattle.core.params.param_arrays`):
    ``name`` (``"alpha"`` or ``"r"``) takes ``values``, the rest ``base``."""
    return param_arrays(base, name, values)


def box_ics(n: int, seed: int, box=BOX) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``n`` random pre-impact states in ``box`` (``numpy.random.default_rng(seed)``; sdot0 > 0 at s = 0)."""
    n = check_int("n", n, 1, 10_000_000)
    rng = np.random.default_rng(seed)
    th = rng.uniform(box[0], box[1], n)
    sd = rng.uniform(box[2], box[3], n)
    sd = np.where(sd == 0.0, 1e-12, sd)
    return th, sd, np.zeros(n, np.int32)


def orbit_points(orbits) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pre-impact points ``(theta, sdot, wall)`` of one or several periodic orbits, concatenated (a
    capture target: the wall of a pre-impact state follows the sign of its velocity)."""
    orbits = [orbits] if isinstance(orbits, PeriodicOrbit) else list(orbits)
    th = np.concatenate([np.mod(np.asarray(o.theta, float), 2 * np.pi) for o in orbits])
    sd = np.concatenate([np.asarray(o.sdot, float) for o in orbits])
    return th, sd, np.where(sd > 0, 0, -1).astype(np.int32)


__all__ = [
    "BOX",
    "Cost",
    "Timer",
    "engine_run",
    "per_orbit",
    "box_ics",
    "orbit_points",
]
