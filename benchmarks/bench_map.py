"""Throughput of the closed-form impact map (issue 2): impacts per second per core.

Measures, in the same run (machines are noisy, so compare ratios):
  * baseline: a Python loop calling the jit-compiled single-orbit ``step`` once per impact;
  * single orbit: ``lax.scan`` over one orbit (``map_orbit``'s kernel);
  * batch: ``jax.vmap`` over many initial conditions (``batch_advance``).

Usage: python benchmarks/bench_map.py [--batch 4096] [--impacts 200] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

import gear_rattle.mapimpl  # noqa: F401
import jax

from gear_rattle.mapimpl import Params
from gear_rattle.mapimpl.batch import batch_advance, states
from gear_rattle.mapimpl.impact_map import iterate, step
from gear_rattle.core.state import make_state


def _time(fn, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def run(batch: int = 4096, impacts: int = 200, params: Params | None = None) -> dict:
    P = params or Params(3.0, 0.1, 0.1, 0.9)
    p = P.arrays()
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    rng = np.random.default_rng(0)
    tau, sd = rng.uniform(0, 2 * np.pi, batch), rng.uniform(0.05, 0.5, batch)

    step_j = jax.jit(step)
    s0 = make_state(tau[0], sd[0])
    step_j(s0, p)[0].sdot.block_until_ready()
    n_base = min(impacts, 200)

    def base():
        s = s0
        for _ in range(n_base):
            s, _ = step_j(s, p)
        s.sdot.block_until_ready()

    it = jax.jit(iterate, static_argnums=2)
    it(s0, p, impacts).states.sdot.block_until_ready()
    sb = states(tau, sd)
    batch_advance(sb, p, impacts).sdot.block_until_ready()

    t_base = _time(base)
    t_single = _time(lambda: it(s0, p, impacts).states.sdot.block_until_ready())
    t_batch = _time(lambda: batch_advance(sb, p, impacts).sdot.block_until_ready(), repeat=2)
    r = {
        "device": str(jax.devices()[0]),
        "cores": cores,
        "params": vars(P),
        "baseline_python_loop_impacts_per_s": n_base / t_base,
        "single_scan_impacts_per_s": impacts / t_single,
        "batch_impacts_per_s": batch * impacts / t_batch,
    }
    r["batch_impacts_per_s_per_core"] = r["batch_impacts_per_s"] / cores
    r["ratio_single_vs_baseline"] = r["single_scan_impacts_per_s"] / r["baseline_python_loop_impacts_per_s"]
    r["ratio_batch_vs_baseline"] = r["batch_impacts_per_s"] / r["baseline_python_loop_impacts_per_s"]
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--batch", type=int, default=4096)
    ap.add_argument("--impacts", type=int, default=200)
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    r = run(a.batch, a.impacts)
    for k, v in r.items():
        print(f"{k:42s} {v:.4g}" if isinstance(v, float) else f"{k:42s} {v}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(r, f, indent=1)


if __name__ == "__main__":
    main()
