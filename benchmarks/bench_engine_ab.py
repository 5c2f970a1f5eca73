"""The engine's throughput against another checkout's, in one process: interleaved runs, median ratio.

``python benchmarks/bench_engine_ab.py --other /path/to/checkout`` imports the other checkout's library
(its ``core/`` and ``mapimpl/``, as the package ``gear_rattle_other``) beside this one's, compiles both
engines, then alternates them ``--repeats`` times on the Fig. 11 grid (``engine.run`` with a ``Capture``
observer and ``stop_at_stick``, the work of ``transient_times``) and prints the impacts per second of
each run, the median ratio this/other of wall time and of process CPU time, and whether every output
array was bit-identical.  Both run in the same process on the same devices, so a machine shared with
other work slows both alike; the ratio of medians is what to read.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import sys
import tempfile
import time

import numpy as np

import gear_rattle

gear_rattle.use_cpu_devices()


def _other_package(root: str) -> str:
    """Make the checkout at ``root`` importable as ``gear_rattle_other`` (links in a temporary folder)."""
    top = tempfile.mkdtemp(prefix="bench_ab_")
    pkg = os.path.join(top, "gear_rattle_other")
    os.mkdir(pkg)
    with open(os.path.join(pkg, "__init__.py"), "w") as fh:
        fh.write('"""Another checkout of the library, for comparison."""\n')
    for sub in ("core", "mapimpl"):
        os.symlink(os.path.abspath(os.path.join(root, sub)), os.path.join(pkg, sub))
    sys.path.insert(0, top)
    return "gear_rattle_other"


def _engine(pkg: str):
    """``run_once(tau, sdot) -> (EngineResult, wall s, cpu s)`` with the package ``pkg``'s engine."""
    mod = lambda name: importlib.import_module(f"{pkg}.{name}")  # noqa: E731
    P = mod("core.paper").PAPER_PARAMS
    run = mod("mapimpl.engine.driver").run
    target = mod("mapimpl.engine.transients").periodic_target(P)
    cap_obs = mod("mapimpl.engine.observers").Capture(target.theta, target.sdot, target.wall, np.array([1e-3]))

    def run_once(tau, sd, cap):
        w0, c0 = time.perf_counter(), time.process_time()
        res = run(tau, sd, np.where(sd > 0, 0, -1), P, (cap_obs,), cap=cap, stop_at_stick=True, progress=False)
        return res, time.perf_counter() - w0, time.process_time() - c0

    return run_once


def _arrays(res) -> dict:
    out = {
        f: np.asarray(getattr(res, f))
        for f in ("n", "status", "nstick", "first_stick", "theta", "sdot", "wall", "cycles")
    }
    out.update({f"obs.{k}": np.asarray(v) for k, v in res.obs[0].items()})
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--other", required=True, help="the other checkout's root (holding core/ and mapimpl/)")
    ap.add_argument("--n", type=int, default=64, help="grid points per axis of the Fig. 11 box")
    ap.add_argument("--cap", type=int, default=5000)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args(argv)
    for name, v in (("n", a.n), ("cap", a.cap), ("repeats", a.repeats)):
        if v < 1:
            print(f"bench_engine_ab: --{name}={v} is out of range: allowed >= 1", file=sys.stderr)
            return 2
    if not os.path.isdir(os.path.join(a.other, "mapimpl", "engine")):
        print(
            f"bench_engine_ab: --other={a.other!r} is out of range: allowed a checkout with mapimpl/engine/",
            file=sys.stderr,
        )
        return 2
    from gear_rattle.core.paper import PAPER_BOX
    from gear_rattle.mapimpl.engine.transients import grid

    T, S = grid(PAPER_BOX, a.n, a.n)
    tau, sd = T.ravel(), S.ravel()
    engines = {"this": _engine("gear_rattle"), "other": _engine(_other_package(a.other))}
    first = {}
    for name, eng in engines.items():  # compile (excluded from the timings)
        res, wall, _ = eng(tau, sd, a.cap)
        first[name] = _arrays(res)
        print(f"{name}: first run (with compilation) {wall:.1f} s", file=sys.stderr)
    same = all(np.array_equal(first["this"][k], first["other"][k]) for k in first["this"])
    runs: dict[str, list] = {"this": [], "other": []}
    for rep in range(a.repeats):
        for name in ("this", "other") if rep % 2 == 0 else ("other", "this"):
            res, wall, cpu = engines[name](tau, sd, a.cap)
            runs[name].append(
                {"impacts": res.impacts, "wall_s": wall, "cpu_s": cpu, "impacts_per_s": res.impacts / wall}
            )
            print(f"{name}: {res.impacts / wall:.3e} impacts/s (wall {wall:.2f} s, cpu {cpu:.2f} s)", file=sys.stderr)
    med = {
        name: {k: float(np.median([r[k] for r in rs])) for k in ("wall_s", "cpu_s", "impacts_per_s")}
        for name, rs in runs.items()
    }
    out = {
        "grid": [a.n, a.n],
        "cap": a.cap,
        "repeats": a.repeats,
        "bit_identical": bool(same),
        "runs": runs,
        "median": med,
        "ratio_this_over_other": {
            "throughput_wall": med["this"]["impacts_per_s"] / med["other"]["impacts_per_s"],
            "cpu_time": med["this"]["cpu_s"] / med["other"]["cpu_s"],
        },
    }
    print(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
