"""Throughput of the transient engine (issue 5) against a per-orbit baseline, in the same run.

Measures map iterations (impacts) per second:

* engine: :func:`mapimpl.engine.transients.transient_times` on random ICs of the paper's box,
  once on all devices of the default backend (on the CPU one XLA device per core, see
  ``core/jax_config.py``) and once on one device (steady state: compilation is done by a warm-up on
  the same shapes);
* baseline: ``jax.jit(mapimpl.impact_map.step)`` in a Python loop, one orbit at a time (one core).

Per core = per wall second / devices used (on the CPU); ``cpu_s`` is ``time.process_time`` (all
threads of this process).  Paper scale (Fig. 11): ``gear-rattle transients --profile paper``.

    python benchmarks/bench_transients.py [--n-ic 16384] [--cap 3000] [--baseline-impacts 3000]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import jax

from gear_rattle import use_cpu_devices

use_cpu_devices()

from gear_rattle.mapimpl.impact_map import step
from gear_rattle.core.state import make_state
from gear_rattle.mapimpl.engine.options import Execution
from gear_rattle.mapimpl.engine.transients import periodic_target, transient_times
from gear_rattle.core.paper import PAPER_PARAMS


def bench_engine(n_ic, cap, lanes, devices=None, seed=0):
    rng = np.random.default_rng(seed)
    tau, sd = rng.uniform(3.0, 3.5, n_ic), rng.uniform(1e-9, 0.5, n_ic)
    tg = periodic_target()
    ex = Execution(lanes=lanes, devices=devices)
    ndev = len(ex.device_list())
    # compile the same shapes (tail blocks included) first
    transient_times(None, tau, sd, cap=cap, execution=ex, progress=False, target=tg)
    c0, w0 = time.process_time(), time.perf_counter()
    r = transient_times(None, tau, sd, cap=cap, execution=ex, progress=False, target=tg)
    c, w = time.process_time() - c0, time.perf_counter() - w0
    return {
        "devices": ndev,
        "impacts": r.impacts,
        "cpu_s": c,
        "wall_s": w,
        "per_wall_s": r.impacts / w,
        "per_cpu_s": r.impacts / c,
        "per_core": r.impacts / w / ndev,
    }


def bench_baseline(n_impacts):
    p = PAPER_PARAMS.arrays()
    f = jax.jit(step)
    s = make_state(3.2, 0.3)
    s, _ = f(s, p)
    jax.block_until_ready(s)
    c0, w0 = time.process_time(), time.perf_counter()
    for _ in range(n_impacts):
        s, _ = f(s, p)
    jax.block_until_ready(s)
    c, w = time.process_time() - c0, time.perf_counter() - w0
    return {"impacts": n_impacts, "cpu_s": c, "wall_s": w, "per_cpu_s": n_impacts / c, "per_wall_s": n_impacts / w}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-ic", type=int, default=16384)
    ap.add_argument("--cap", type=int, default=3000)
    ap.add_argument("--lanes", type=int, default=None)
    ap.add_argument("--baseline-impacts", type=int, default=3000)
    a = ap.parse_args(argv)
    eng = bench_engine(a.n_ic, a.cap, a.lanes)
    one = bench_engine(a.n_ic, a.cap, a.lanes, devices=1)
    base = bench_baseline(a.baseline_impacts)
    out = {
        "backend": jax.default_backend(),
        "engine_all_devices": eng,
        "engine_one_device": one,
        "baseline_jit_step_loop": base,
        "ratio_per_core_vs_baseline": eng["per_core"] / base["per_wall_s"],
        "ratio_all_devices_vs_baseline": eng["per_wall_s"] / base["per_wall_s"],
        "target_per_core": 1e6,
    }
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
