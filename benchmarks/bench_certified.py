"""The certified track on a chaotic transient of Figs. 9-11 (issue 31 item 1): wall time of
:func:`mapimpl.certified.track.certified_orbit` for N impacts, its precision schedule, the widths of
its bounds in ulps, and the float64 map track on the same orbit timed in the same run (a ratio).

The orbit: alpha = 1.245, beta = gamma = 0.1, r = 0.9 (the float64 values of the printed decimals,
:data:`core.paper.PAPER_PARAMS`) from the pre-impact state (tau0, sdot0) = (3.2, 0.3) in the paper's box.
The report says where the certified orbit is first within ``DELTA`` of the stable 4-impact orbit (the
transient's end, the engine's capture rule; after it the orbit converges and the balls stop growing).
Targets: 1000 impacts in <= 10 s, 10 000 in <= 5 min on 2 cores.  The track runs on one core (python-flint);
on a shared machine the wall time depends on the load, so the report also gives the CPU time of the process
and the 1-minute load average before and after.

Usage: ``python benchmarks/bench_certified.py [--impacts 1000 10000] [--tau0 3.2 --sdot0 0.3] [--alpha 1.245]
[--json FILE]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np

import gear_rattle as gr
from gear_rattle.core.paper import DELTA, PAPER_PARAMS
from gear_rattle.core.params import Params
from gear_rattle.mapimpl.engine.t_post import float64_target
from gear_rattle.mapimpl.certified.track import certified_orbit


def capture_impact(rows: dict, params=PAPER_PARAMS, delta: float = DELTA) -> int | None:
    """The first impact (index) whose float64 pre-impact state is within ``delta`` of the 4-impact orbit
    (sup norm of the wrapped phase and sdot differences, same wall), None if none."""
    tg = float64_target(params)
    imp = rows["kind"] == "impact"
    for i, (th, sd, w) in enumerate(zip(rows["theta"][imp], rows["sdot"][imp], rows["wall"][imp])):
        for a, b, ww in zip(tg.theta, tg.sdot, tg.wall):
            d = abs(th - a)
            if ww == w and max(min(d, 2 * math.pi - d), abs(sd - b)) < delta:
                return i
    return None


def ulp_widths(rows: dict) -> dict:
    """Per column the largest and the mean width of ``[lo, hi]`` in ulps of the value."""
    out = {}
    for col, mid in (("tau", rows["tau"]), ("tau_mod_2pi", rows["theta"]), ("sdot", rows["sdot"])):
        ok = ~np.isnan(mid) & (mid != 0)
        w = (rows[col + "_hi"][ok] - rows[col + "_lo"][ok]) / np.array([math.ulp(x) for x in mid[ok]])
        out[col] = {"max": float(w.max()), "mean": float(w.mean())}
    return out


def run(n: int, tau0: float, sdot0: float, params=PAPER_PARAMS) -> dict:
    gr.orbit(params, tau0, sdot0, n, track="map")  # compile the map track for this length
    t, c = time.perf_counter(), time.process_time()
    gr.orbit(params, tau0, sdot0, n, track="map")
    t_map, c_map = time.perf_counter() - t, time.process_time() - c
    last = [0.0]

    def progress(done, total):
        now = time.perf_counter()
        if now - last[0] > 10 or done == total:
            last[0] = now
            print(f"  ... {done}/{total} impacts at {now - t0:.0f} s", file=sys.stderr, flush=True)

    load0 = os.getloadavg()[0]
    t0, c0 = time.perf_counter(), time.process_time()
    res = certified_orbit(params, tau0, sdot0, n, progress=progress)
    t_cert, c_cert = time.perf_counter() - t0, time.process_time() - c0
    return {
        "alpha": params.alpha,
        "impacts": n,
        "tau0": tau0,
        "sdot0": sdot0,
        "complete": res.complete,
        "status": res.status,
        "seconds": round(t_cert, 2),
        "cpu_seconds": round(c_cert, 2),
        "map_seconds": round(t_map, 4),
        "map_cpu_seconds": round(c_map, 4),
        "ratio_to_map": round(t_cert / t_map, 1),
        "cpu_ratio_to_map": round(c_cert / c_map, 1),
        "load_average": [round(load0, 1), round(os.getloadavg()[0], 1)],
        "precision_bits": res.precision,
        "attempts": [
            {
                "prec": a.prec,
                "reached": a.reached,
                "seconds": round(a.seconds, 2),
                "bits_lost_per_impact": None if math.isnan(a.growth) else round(a.growth, 3),
            }
            for a in res.attempts
        ],
        "capture_impact": capture_impact(res.rows) if params == PAPER_PARAMS else None,
        "ulp_widths": ulp_widths(res.rows),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--impacts", type=int, nargs="+", default=[1000, 10000], help="orbit lengths (default 1000 10000)")
    ap.add_argument("--tau0", type=float, default=3.2)
    ap.add_argument("--sdot0", type=float, default=0.3)
    ap.add_argument(
        "--alpha",
        type=float,
        default=PAPER_PARAMS.alpha,
        help="alpha (beta = gamma = 0.1, r = 0.9; default 1.245, Figs. 9-11; 3: Fig. 3's chaotic attractor, "
        "an orbit that stays chaotic)",
    )
    ap.add_argument("--json", default=None, help="also write the results to this file")
    a = ap.parse_args(argv)
    out = []
    for n in a.impacts:
        r = run(n, a.tau0, a.sdot0, Params(a.alpha, 0.1, 0.1, 0.9))
        out.append(r)
        print(json.dumps(r), flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
