"""Cost of the atlas store's integrity (issue 29): the same atlas with the store code before checksums and
lock (loaded from git, default commit 1252113) and with the current one, in the same run, alternating.

Measured, in this process, serial scheduler (no Dask), the real compute seam (compiled once by a warm-up):

* ``full``: a whole atlas into a new store (lock, create, compute, write with checksums);
* ``resume``: the same command again on the finished store (lock, verify every tile, nothing computed);
* ``digest``: the SHA-256 of one tile's arrays (what :meth:`AtlasStore.write_tile` adds per tile);
* ``big_resume``: the resume of a store of ``--big`` x ``--big`` points in tiles of ``--tile`` (numbers
  from a cheap stand-in of the compute seam: only the store is timed), where verifying every tile is the
  cost that grows with the atlas.

    python benchmarks/bench_atlas_store.py [--n 32] [--tile 8] [--reps 3] [--big 256] [--old-rev 1252113]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gear_rattle import use_cpu_devices

use_cpu_devices()

from gear_rattle.validation.atlas import FIELDS, AtlasSpec, compute_tile
from gear_rattle.validation.atlas.integrity import tile_digest
from gear_rattle.validation.atlas.run import run_atlas
from gear_rattle.validation.atlas.store import CHECKED

PKG = "gear_rattle.validation.atlas"
ROOT = Path(__file__).resolve().parent.parent


def old_run_atlas(rev: str):
    """``run_atlas`` of commit ``rev`` with that commit's store module (the compute seam is today's)."""

    def load(name, source):
        spec = importlib.util.spec_from_loader(f"{PKG}.{name}", loader=None)
        mod = importlib.util.module_from_spec(spec)
        mod.__package__ = PKG
        sys.modules[spec.name] = mod
        exec(compile(source, f"{rev}:{name}.py", "exec"), mod.__dict__)
        return mod

    show = lambda path: (  # noqa: E731
        subprocess.run(
            ["git", "show", f"{rev}:{path}"],
            cwd=ROOT,
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    )
    load("_old_store", show("validation/atlas/store.py"))
    run = load("_old_run", show("validation/atlas/run.py").replace("from .store import", "from ._old_store import"))
    return run.run_atlas


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=32, help="grid points per axis (default 32)")
    ap.add_argument("--tile", type=int, default=8, help="tile side (default 8)")
    ap.add_argument("--reps", type=int, default=3, help="alternating repetitions (default 3)")
    ap.add_argument("--big", type=int, default=256, help="grid side of the resume-only store (default 256)")
    ap.add_argument("--old-rev", default="1252113", help="commit of the store before checksums (default 1252113)")
    a = ap.parse_args()
    spec = AtlasSpec(
        alpha_lo=2.0, alpha_hi=3.0, n_alpha=a.n, r_lo=0.8, r_hi=0.9, n_r=a.n, transient=300, impacts=500, period_max=16
    )
    tile = (a.tile, a.tile)
    versions = {"old": old_run_atlas(a.old_rev), "new": run_atlas}
    work = Path(tempfile.mkdtemp(prefix="bench_atlas_store_"))
    try:
        run_atlas(spec, str(work / "warm.zarr"), tile, "serial")  # compile the kernel for this tile shape
        times = {(v, k): [] for v in versions for k in ("full", "resume")}
        for rep in range(a.reps):
            for v, fn in versions.items():
                path = str(work / f"{v}{rep}.zarr")
                t0 = time.perf_counter()
                fn(spec, path, tile, "serial")
                times[(v, "full")].append(time.perf_counter() - t0)
                t0 = time.perf_counter()
                again = fn(spec, path, tile, "serial")
                times[(v, "resume")].append(time.perf_counter() - t0)
                assert again.computed == []
        # the two stores hold the same atlas
        import zarr

        old, new = (
            zarr.open_group(str(work / "old0.zarr"), mode="r"),
            zarr.open_group(str(work / "new0.zarr"), mode="r"),
        )
        identical = all(np.array_equal(old[k][...], new[k][...], equal_nan=True) for k in FIELDS)
        out = compute_tile(*np.meshgrid(spec.alphas[: a.tile], spec.rs[: a.tile]), spec)
        vals = {**out, "tile_seconds": np.ones((1, 1)), "tile_cpu_seconds": np.ones((1, 1))}
        t0 = time.perf_counter()
        for _ in range(200):
            for k in CHECKED:
                tile_digest(k, 0, 0, vals[k])
        digest = (time.perf_counter() - t0) / 200
        big = AtlasSpec(**{**spec.to_dict(), "n_alpha": a.big, "n_r": a.big})
        stand_in = lambda al, r, sp: {k: np.zeros(al.shape, dt) for k, (dt, _) in FIELDS.items()}  # noqa: E731
        for v, fn in versions.items():
            fn(big, str(work / f"big_{v}.zarr"), tile, "serial", compute=stand_in)
            times[(v, "big_resume")] = []
        for _ in range(a.reps):
            for v, fn in versions.items():
                t0 = time.perf_counter()
                assert fn(big, str(work / f"big_{v}.zarr"), tile, "serial", compute=stand_in).computed == []
                times[(v, "big_resume")].append(time.perf_counter() - t0)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    med = {f"{v}_{k}_s": statistics.median(t) for (v, k), t in times.items()}
    n_tiles = (-(-a.n // a.tile)) ** 2
    n_big = (-(-a.big // a.tile)) ** 2
    res = {
        "grid": [a.n, a.n],
        "tile": list(tile),
        "tiles": n_tiles,
        "reps": a.reps,
        "old_rev": a.old_rev,
        "same_atlas": identical,
        **{k: round(v, 4) for k, v in med.items()},
        "ratio_full_new_over_old": round(med["new_full_s"] / med["old_full_s"], 3),
        "ratio_resume_new_over_old": round(med["new_resume_s"] / med["old_resume_s"], 3),
        "resume_extra_ms_per_tile": round(1e3 * (med["new_resume_s"] - med["old_resume_s"]) / n_tiles, 3),
        "digest_ms_per_tile": round(1e3 * digest, 4),
        "big_tiles": n_big,
        "ratio_big_resume_new_over_old": round(med["new_big_resume_s"] / med["old_big_resume_s"], 3),
        "big_resume_extra_ms_per_tile": round(1e3 * (med["new_big_resume_s"] - med["old_big_resume_s"]) / n_big, 3),
        "compute_ms_per_tile": round(1e3 * med["old_full_s"] / n_tiles, 1),
        "all_times_s": {f"{v}_{k}": [round(x, 4) for x in t] for (v, k), t in times.items()},
    }
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
