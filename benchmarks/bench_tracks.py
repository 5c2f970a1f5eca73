"""Cost per impact of each track, measured in the same run (issue 3).

Tracks: the closed-form map batched (``mapimpl.batch.batch_iterate``, vmapped), the map single-orbit
(``map_orbit``), scipy (``reference.scipy_track.orbit``) and diffrax (``reference.diffrax_track.orbit``)
on the paper's parameters (alpha = 3, beta = gamma = 0.1, r = 0.9).  Compilation is excluded (one
warm-up call each).  Usage: ``python benchmarks/bench_tracks.py [--impacts N] [--batch B]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gear_rattle.core import jax_config  # noqa: F401
import jax

from gear_rattle.mapimpl.batch import batch_iterate, states
from gear_rattle.mapimpl.orbit import map_orbit
from gear_rattle.core.params import Params
from gear_rattle.reference import diffrax_track, scipy_track


def _time(fn, repeat: int = 1) -> float:
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        jax.block_until_ready(fn())
        best = min(best, time.perf_counter() - t)
    return best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--impacts", type=int, default=200, help="impacts per orbit (default 200)")
    ap.add_argument("--batch", type=int, default=64, help="orbits in the map batch (default 64)")
    a = ap.parse_args(argv)
    if a.impacts < 1 or a.batch < 1:
        raise SystemExit("--impacts and --batch must be >= 1")
    p = Params(3.0, 0.1, 0.1, 0.9)
    n = a.impacts
    rng = np.random.default_rng(0)
    tau = rng.uniform(0, 2 * np.pi, a.batch)
    sd = rng.uniform(0.1, 1.0, a.batch)
    st = states(tau, sd)
    pa = p.arrays()
    rows = []
    batch_iterate(st, pa, n)  # compile
    rows.append(("map batch (vmap)", _time(lambda: batch_iterate(st, pa, n), 3) / (n * a.batch)))
    map_orbit(p, 0.0, 0.5, n)
    rows.append(("map single", _time(lambda: map_orbit(p, 0.0, 0.5, n).tau, 3) / n))
    rows.append(("scipy DOP853", _time(lambda: scipy_track.orbit(p, 0.0, 0.5, n).tau) / n))
    diffrax_track.orbit(p, 0.0, 0.5, n)
    rows.append(("diffrax Dopri8", _time(lambda: diffrax_track.orbit(p, 0.0, 0.5, n).tau, 2) / n))
    base = rows[0][1]
    print(f"cost per impact, {n} impacts/orbit, map batch of {a.batch} orbits (alpha=3, beta=gamma=0.1, r=0.9)")
    print(f"{'track':<20}{'us/impact':>12}{'x map batch':>14}{'x map single':>14}")
    for name, c in rows:
        print(f"{name:<20}{c * 1e6:>12.2f}{c / base:>14.1f}{c / rows[1][1]:>14.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
