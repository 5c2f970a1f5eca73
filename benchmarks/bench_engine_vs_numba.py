"""The transient engine against a numba reference kernel of the same method (issue 12), in one run.

Workload: the paper's Fig. 11 setting (alpha = 1.245, beta = gamma = 0.1, r = 0.9), an ``n`` x ``n``
cell-centred grid of pre-impact initial states over 3.0 < tau0 < 3.5, 0 < sdot0 < 0.5 (default
200 x 200), cap 20000, capture within delta = 1e-3 of the stable 4-impact orbit.  Measured, with
compilation excluded (numba: a call on a few ICs first; engine: a full warm-up run on the same
shapes, as ``bench_transients.py`` does):

* ``numba``: :func:`numba_kernel.numba_transients` (``prange`` over the ICs, all numba threads =
  cores) and the ``engine``: :func:`gear_rattle.mapimpl.engine.transients.transient_times` (one XLA
  CPU device per core, ``gear_rattle.use_cpu_devices()``), alternating, ``--repeats`` times each; the
  ratio engine / numba of impacts per wall second of each repeat pair, its median and spread;
* per core: both on one core (numba 1 thread, engine 1 device) on every ``--stride``-th IC of the grid;
* where the time goes: flight evaluations per impact (counted by the numba kernel; the engine makes
  the same decisions, so the same count up to chaotic sampling), the cost per impact and per
  evaluation, and (best effort, it uses the engine's internals) the engine's steady-state costs on one
  core: per impact in its block loop, per lane for a search micro-step, an arrival pass, a flight
  evaluation and the sin/cos kernel;
* agreement: durations equal per IC (all, and short transients < 50 impacts on a sample of the Fig. 9
  window, where the tongues of short transients are), and the two survival samples of the orbits that
  never stick (two-sample KS test, means with standard errors).  The orbits that stick (17.6% of the
  Fig. 11 box) all continue on one post-release orbit from the canonical release phase, so their
  durations share one chaotic sample, which ulp-level differences of the arithmetic change: they are
  reported apart (``sticking_durations_*``).

The machine is shared: the load average before each timed run is recorded, and CPU times
(``cpu_s``, all threads of the process) are reported beside the wall times.

    pip install -e ".[bench]"
    python benchmarks/bench_engine_vs_numba.py [--n 200] [--cap 20000] [--repeats 3] [--stride 4] [--out FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

from gear_rattle import use_cpu_devices

NCORES = use_cpu_devices()  # before JAX starts: one XLA CPU device per core

import jax
import jax.numpy as jnp
import numba
from scipy import stats

from gear_rattle.mapimpl.engine.options import Execution
from gear_rattle.mapimpl.engine.transients import grid, periodic_target, transient_times
from gear_rattle.core.paper import PAPER_BOX, PAPER_PARAMS

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from numba_kernel import STATUS_NAMES, numba_transients

P = PAPER_PARAMS
SHORT = 50  # transients shorter than this end identically (no chaotic amplification of ulps)


def _load() -> float:
    return os.getloadavg()[0]


_COMPILE_S = [0.0]


def _on_event(event: str, duration: float, **_kw) -> None:
    if event.startswith("/jax/core/compile/"):
        _COMPILE_S[0] += duration


jax.monitoring.register_event_duration_secs_listener(_on_event)


def run_numba(tau, sd, target, deltas, cap, threads):
    numba.set_num_threads(threads)
    load = _load()
    c0, w0 = time.process_time(), time.perf_counter()
    r = numba_transients(tau, sd, P, target.theta, target.sdot, target.wall, deltas, cap)
    c, w = time.process_time() - c0, time.perf_counter() - w0
    imp = int(r["n"].sum())
    return r, {
        "threads": threads,
        "impacts": imp,
        "evaluations": int(r["evals"].sum()),
        "wall_s": w,
        "cpu_s": c,
        "impacts_per_s": imp / w,
        "per_core": imp / w / threads,
        "load_avg_before": load,
    }


def run_engine(tau, sd, deltas, delta, cap, devices=None):
    load = _load()
    comp0 = _COMPILE_S[0]
    c0, w0 = time.process_time(), time.perf_counter()
    ex = Execution(devices=devices)
    r = transient_times(P, tau, sd, cap=cap, delta=delta, deltas=deltas, progress=False, execution=ex)
    c, w = time.process_time() - c0, time.perf_counter() - w0
    ndev = int(r.meta.get("devices", NCORES if devices is None else devices))
    imp = int(r.n.sum())
    # JAX compilations seen during the run (thread time, summed over devices): 0 when the warm-up
    # compiled every shape the run needs
    return r, {
        "devices": ndev,
        "lanes": r.meta.get("lanes"),
        "impacts": imp,
        "wall_s": w,
        "cpu_s": c,
        "impacts_per_s": imp / w,
        "per_core": imp / w / ndev,
        "load_avg_before": load,
        "jax_compile_s_during_run": _COMPILE_S[0] - comp0,
    }


def _spread(xs):
    xs = np.asarray(xs, float)
    return {
        "median": float(np.median(xs)),
        "min": float(xs.min()),
        "max": float(xs.max()),
        "rel_spread": float((xs.max() - xs.min()) / np.median(xs)),
    }


def engine_hit(re, col: int) -> np.ndarray:
    """The engine's durations within ``re.deltas[col]`` (-1: censored), the orbits that stick composed with
    its own post-release orbit (``TransientResult.duration``; ``re.hit`` holds the raw first hits)."""
    dur, censored = re.duration(re.deltas[col])
    return np.where(censored, -1, dur)


def agreement(rn: dict, re, cap: int, col: int) -> dict:
    """Per-IC equality and statistical agreement of the durations (censored orbits count as ``cap``).

    The orbits that stick are not independent samples: every one of them is released at the
    canonical release phase with ``sdot = 0`` and continues on *one* post-release orbit (bit for bit,
    in each implementation), so their durations are (iterations before sticking) + one shared chaotic
    duration -- a single sample, which ulp-level differences of the two implementations' arithmetic
    (libm vs the engine's fdlibm sin/cos) change completely.  The statistical comparison is therefore
    made on the orbits that never stick (in both); the shared post-release durations are reported.
    """
    hn, he = rn["hit"][:, col], engine_hit(re, col)
    dn, de = np.where(hn < 0, cap, hn), np.where(he < 0, cap, he)
    short = (de < SHORT) | (dn < SHORT)
    free = (rn["nstick"] == 0) & (re.nstick == 0)
    ks = stats.ks_2samp(dn[free], de[free])
    se = lambda d: float(d.std(ddof=1) / np.sqrt(d.size))  # noqa: E731
    mn, me = dn[free], de[free]
    stuck = ~free
    return {
        "n_ic": int(dn.size),
        "identical_fraction": float(np.mean(dn == de)),
        "short_transients": int(short.sum()),
        "short_identical_fraction": float(np.mean(dn[short] == de[short])) if short.any() else None,
        "non_sticking_ics": int(free.sum()),
        "mean_numba": float(mn.mean()),
        "se_numba": se(mn),
        "mean_engine": float(me.mean()),
        "se_engine": se(me),
        "mean_diff_in_se": float((mn.mean() - me.mean()) / np.hypot(se(mn), se(me))),
        "ks_statistic": float(ks.statistic),
        "ks_pvalue": float(ks.pvalue),
        "sticking_ics": int(stuck.sum()),
        "sticking_durations_numba_min_median_max": [int(x) for x in np.percentile(dn[stuck], [0, 50, 100])]
        if stuck.any()
        else None,
        "sticking_durations_engine_min_median_max": [int(x) for x in np.percentile(de[stuck], [0, 50, 100])]
        if stuck.any()
        else None,
        "mean_all_numba": float(dn.mean()),
        "mean_all_engine": float(de.mean()),
        "censored_numba": int(np.sum(hn < 0)),
        "censored_engine": int(np.sum(he < 0)),
        "nstick_identical_fraction": float(np.mean(rn["nstick"] == re.nstick)),
        "status_numba": {STATUS_NAMES[s]: int(np.sum(rn["status"] == s)) for s in np.unique(rn["status"])},
        "orbits_sticking_numba": int(np.sum(rn["nstick"] > 0)),
        "orbits_sticking_engine": int(np.sum(re.nstick > 0)),
    }


def short_check(target, deltas, delta, n_ic=4000, cap=300, seed=0) -> dict:
    """Exact agreement of short transients: random ICs over the Fig. 9 window (0 < tau0 < 2 pi,
    0 < sdot0 < 0.5), whose tongues hold many of them (the Fig. 11 box holds almost none)."""
    rng = np.random.default_rng(seed)
    tau, sd = rng.uniform(0.0, 2 * np.pi, n_ic), rng.uniform(1e-9, 0.5, n_ic)
    rn = numba_transients(tau, sd, P, target.theta, target.sdot, target.wall, deltas, cap)
    re = transient_times(P, tau, sd, cap=cap, delta=delta, deltas=deltas, progress=False)
    out = {"n_ic": n_ic, "cap": cap, "seed": seed}
    for j, d in enumerate(re.deltas):
        hn, he = rn["hit"][:, j], engine_hit(re, j)
        short = ((he >= 0) & (he < SHORT)) | ((hn >= 0) & (hn < SHORT))
        out[f"delta={d:g}"] = {
            "short": int(short.sum()),
            "short_identical": int(np.sum(hn[short] == he[short])),
            "all_identical_fraction": float(np.mean(hn == he)),
        }
    return out


def engine_split(tau, sd, target, deltas, cap, lanes=256, blocks=40) -> dict:
    """Steady-state costs of the engine's kernel on one device (one core), and of its parts, per lane:
    a block loop (``run_blocks``: search micro-steps, an arrival pass every ``ARRIVE_EVERY`` of them, the
    refills), the search micro-step alone, the arrival pass alone, the flight evaluation alone and the
    sin/cos kernel alone.  Uses the engine's internals (``mapimpl.engine.kernel``): best effort."""
    from gear_rattle.mapimpl.engine import kernel as K
    from gear_rattle.mapimpl.engine.fastmath import sincos
    from gear_rattle.mapimpl.engine.observers import Capture
    from gear_rattle.core.status import Status

    dev = jax.devices()[0]
    obs = (Capture(target.theta, target.sdot, target.wall, np.asarray(deltas, np.float64)),)
    perm = np.random.default_rng(0).permutation(tau.size)  # a steady mix of short and long orbits
    q = K.prepare_queue(tau[perm], sd[perm], np.zeros(tau.size, np.int32), P.arrays())
    k = K.make_consts(cap, obs, True, params=P.arrays())
    carry = (K.idle_lanes(lanes, obs), K.empty_results(tau.size, obs), jnp.asarray(0, jnp.int32))
    q, k, carry = jax.device_put((q, k, carry), dev)

    def impacts(c):
        ln, res, _ = c
        done = np.asarray(res.status) != int(Status.NOT_RUN)
        busy = (np.asarray(ln.mode) != K.MODE_IDLE) | (np.asarray(ln.ic) >= 0)
        return int(np.asarray(res.n)[done].sum()) + int(np.asarray(ln.n)[busy].sum())

    block = 32
    carry, _ = K.run_blocks(carry, q, k, obs, block=block, max_blocks=blocks)  # compile + reach steady state
    i0, c0 = impacts(carry), time.process_time()
    carry, nb = jax.block_until_ready(K.run_blocks(carry, q, k, obs, block=block, max_blocks=blocks))
    c_run, imp = time.process_time() - c0, impacts(carry) - i0
    out = {
        "lanes": lanes,
        "clock": "process CPU time",
        "arrive_every": K.ARRIVE_EVERY,
        "blocks_ns_per_impact": c_run / imp * 1e9,
        "search_steps_per_impact": int(nb) * (block // K.ARRIVE_EVERY) * K.ARRIVE_EVERY * lanes / imp,
    }
    lanes0 = carry[0]
    steps = 2000

    def per_lane(step_fn):
        run = jax.jit(lambda c, kk: jax.lax.fori_loop(0, steps, lambda _, x: step_fn(x, kk), c))
        jax.block_until_ready(run(lanes0, k))
        t0 = time.process_time()
        jax.block_until_ready(run(lanes0, k))
        return (time.process_time() - t0) / (steps * lanes) * 1e9

    out["ns_per_lane_search_step"] = per_lane(lambda x, kk: K._lanewise(lambda s: K.search_step(s, kk), kk)(x))
    out["ns_per_lane_arrival_pass"] = per_lane(lambda x, kk: K._lanewise(lambda s: K.arrival(s, kk, obs), kk)(x))

    def flight_only(x, _k):
        def one(s):
            f, t = s.flight, s.search.t
            r = K.flight_sc(t, f.sin0, f.cos0, f.v0, P.alpha, P.beta, P.gamma)
            return s._replace(search=s.search._replace(t=t + 1e-300 * sum(r)))

        return jax.vmap(one)(x)

    def sincos_only(x, _k):
        t = x.search.t
        return x._replace(search=x.search._replace(t=t + 1e-300 * sum(sincos(t))))

    out["ns_per_lane_flight_eval"] = per_lane(flight_only)
    out["ns_per_lane_sincos"] = per_lane(sincos_only)
    return out


def _save(out: dict, path: str | None) -> str:
    text = json.dumps(out, indent=1, default=float)
    if path:
        with open(path, "w") as fh:
            fh.write(text + "\n")
    return text


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=200, help="grid points per axis of the Fig. 11 box")
    ap.add_argument("--cap", type=int, default=20000)
    ap.add_argument("--delta", type=float, default=1e-3)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--stride", type=int, default=4, help="per-core runs on every stride-th IC (0: skip)")
    ap.add_argument("--no-split", action="store_true", help="skip the engine's cost split")
    ap.add_argument(
        "--warmup-cap",
        type=int,
        default=None,
        help="cap of the engine's warm-up run on the same grid (default: --cap; any compilation left "
        "for the timed runs is reported as jax_compile_s_during_run)",
    )
    ap.add_argument("--out", default=None, help="also write the JSON here (rewritten after every stage)")
    a = ap.parse_args(argv)
    for name, v in (("n", a.n), ("cap", a.cap), ("repeats", a.repeats)):
        if v < 1:
            print(f"bench_engine_vs_numba: --{name}={v} is out of range: allowed >= 1", file=sys.stderr)
            return 2
    deltas = (a.delta,)
    target = periodic_target(P)
    T, S = grid(PAPER_BOX, a.n, a.n)
    tau, sd = T.ravel(), S.ravel()
    out = {
        "setting": {
            "params": vars(P) if hasattr(P, "__dict__") else str(P),
            "grid": [a.n, a.n],
            "box": list(PAPER_BOX),
            "cap": a.cap,
            "delta": a.delta,
            "ic": "pre-impact",
        },
        "machine": {
            "cores": NCORES,
            "cpu_devices": len(jax.devices()),
            "numba_threads": numba.get_num_threads(),
            "numba": numba.__version__,
            "jax": jax.__version__,
            "threading_layer": None,
        },
    }
    # ---- compilation (excluded from every timing below) ----
    t0 = time.perf_counter()
    numba_transients(tau[:8], sd[:8], P, target.theta, target.sdot, target.wall, deltas, 50)
    out["numba_compile_s"] = time.perf_counter() - t0
    out["machine"]["threading_layer"] = numba.threading_layer()
    _, warm = run_engine(tau, sd, deltas, a.delta, a.cap if a.warmup_cap is None else a.warmup_cap)  # compiles
    print(f"compiled: numba {out['numba_compile_s']:.1f} s, engine warm-up run {warm['wall_s']:.1f} s", file=sys.stderr)
    out["engine_warmup_run_s"] = warm["wall_s"]
    out["engine_warmup_cap"] = a.cap if a.warmup_cap is None else a.warmup_cap
    # ---- both cores, alternating ----
    reps_n, reps_e, ratios = [], [], []
    for _ in range(a.repeats):
        rn, mn = run_numba(tau, sd, target, deltas, a.cap, NCORES)
        re, me = run_engine(tau, sd, deltas, a.delta, a.cap)
        reps_n.append(mn)
        reps_e.append(me)
        ratios.append(me["impacts_per_s"] / mn["impacts_per_s"])
        _save({**out, "partial_repeats": {"numba": reps_n, "engine": reps_e}}, a.out)
        print(
            f"repeat: numba {mn['impacts_per_s']:.3e}/s, engine {me['impacts_per_s']:.3e}/s, "
            f"ratio {ratios[-1]:.3f} (load {mn['load_avg_before']:.1f}/{me['load_avg_before']:.1f})",
            file=sys.stderr,
        )
    out["numba_all_cores"] = reps_n
    out["engine_all_cores"] = reps_e
    out["ratio_engine_over_numba"] = {"per_repeat": ratios, **_spread(ratios)}
    out["numba_impacts_per_s"] = _spread([m["impacts_per_s"] for m in reps_n])
    out["engine_impacts_per_s"] = _spread([m["impacts_per_s"] for m in reps_e])
    out["target_ratio"] = 2.0
    # ---- where the time goes ----
    ev = reps_n[-1]["evaluations"]
    imp_n = reps_n[-1]["impacts"]
    out["work"] = {
        "flight_evaluations_per_impact_numba": ev / imp_n,
        "numba_ns_per_impact_per_core": np.median([m["wall_s"] * m["threads"] / m["impacts"] for m in reps_n]) * 1e9,
        "engine_ns_per_impact_per_core": np.median([m["wall_s"] * m["devices"] / m["impacts"] for m in reps_e]) * 1e9,
        "numba_ns_per_evaluation_per_core": np.median([m["wall_s"] * m["threads"] / m["evaluations"] for m in reps_n])
        * 1e9,
        "numba_cpu_ns_per_evaluation": np.median([m["cpu_s"] / m["evaluations"] for m in reps_n]) * 1e9,
    }
    # ---- agreement ----
    out["agreement_fig11_grid"] = agreement(rn, re, a.cap, list(re.deltas).index(a.delta))
    out["agreement_short_transients_fig9_window"] = short_check(target, deltas, a.delta)
    _save(out, a.out)
    # ---- one core each ----
    if a.stride > 0:
        sub = slice(None, None, a.stride)
        ts, ss = tau[sub], sd[sub]
        run_engine(ts, ss, deltas, a.delta, a.cap, devices=1)  # compile the one-device shapes
        _, m1 = run_numba(ts, ss, target, deltas, a.cap, 1)
        _, e1 = run_engine(ts, ss, deltas, a.delta, a.cap, devices=1)
        numba.set_num_threads(NCORES)
        out["one_core"] = {
            "stride": a.stride,
            "numba": m1,
            "engine": e1,
            "ratio_engine_over_numba": e1["impacts_per_s"] / m1["impacts_per_s"],
        }
        _save(out, a.out)
    # ---- the engine's cost split (internals; best effort) ----
    if not a.no_split:
        try:
            sp = engine_split(tau, sd, target, deltas, a.cap)
            sp["numba_cpu_ns_per_evaluation"] = (
                out["one_core"]["numba"]["cpu_s"] / out["one_core"]["numba"]["evaluations"] * 1e9
                if "one_core" in out
                else None
            )
            out["engine_cost_split_one_core"] = sp
        except Exception as exc:  # noqa: BLE001 - the engine's internals changed: report, do not fail the benchmark
            out["engine_cost_split_one_core"] = f"unavailable: {type(exc).__name__}: {exc}"
    print(_save(out, a.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
