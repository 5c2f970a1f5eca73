"""Fault injection on `gear-rattle atlas` (issue 29): SIGKILL at random moments of a run (after 1 or 2 more
tiles are stored, plus up to 0.6 s), one damaged chunk of a finished tile after each kill (cycling: a flipped
byte, a truncated chunk, a deleted chunk, a chunk copied from another tile, a truncated done chunk), rerun
until the atlas is complete; then two identical commands started together on a new store, twice.  Prints
counts as JSON: kills, damages, the notes that named them, stale locks taken over, refusals, tracebacks,
and whether the final atlas equals an uninterrupted one bit for bit.

    python benchmarks/atlas_faults.py [--seed 29] [--workdir /tmp/atlas_faults]
"""

from __future__ import annotations

import argparse
import json
import random
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

GR = [sys.executable, "-m", "gear_rattle"]
ARGS = [
    "atlas",
    "--alpha-lo",
    "2",
    "--alpha-hi",
    "3",
    "--n-alpha",
    "16",
    "--r-lo",
    "0.8",
    "--r-hi",
    "0.9",
    "--n-r",
    "6",
    "--transient",
    "300",
    "--impacts",
    "500",
    "--period-max",
    "16",
    "--tile",
    "2",
    "--scheduler",
    "serial",
    "--quiet",
]
TILES = 24
DAMAGES = ("flip", "truncate", "delete", "copy", "truncate_done")


def ndone(out: Path) -> int:
    d = out / "atlas.zarr/done/c"
    return sum(1 for f in d.rglob("*") if f.is_file()) if d.exists() else 0


def run(out: Path, rng, kill_after=None, extra=()):
    p = subprocess.Popen(
        [*GR, *ARGS, "--out", str(out), *extra], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    if kill_after is not None:  # SIGKILL once kill_after more tiles are stored, a random fraction of a second later
        start = ndone(out)
        while p.poll() is None and ndone(out) < start + kill_after:
            time.sleep(0.02)
        time.sleep(rng.uniform(0, 0.6))
        p.kill()
    _, err = p.communicate()
    return p.returncode, err


def damage(store: Path, rng, kind: str) -> bool:
    done = sorted(f for f in (store / "done/c").rglob("*") if f.is_file())
    if not done:
        return False
    d = done[rng.randrange(len(done))]
    f = d if kind == "truncate_done" else store / "lambda1/c" / d.parent.name / d.name
    if not f.exists():
        return False
    b = f.read_bytes()
    if kind == "flip":
        bb = bytearray(b)
        bb[len(bb) // 2] ^= 4
        f.write_bytes(bytes(bb))
    elif kind in ("truncate", "truncate_done"):
        f.write_bytes(b[: len(b) // 2])
    elif kind == "delete":
        f.unlink()
    else:
        others = [g for g in (store / "lambda1/c").rglob("*") if g.is_file() and g != f]
        if not others:
            return False
        f.write_bytes(others[0].read_bytes())
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=29)
    ap.add_argument("--workdir", default="/tmp/atlas_faults")
    a = ap.parse_args()
    import zarr

    rng = random.Random(a.seed)
    w = Path(a.workdir)
    shutil.rmtree(w, ignore_errors=True)
    w.mkdir(parents=True)
    rc, err = run(w / "ref", rng)
    assert rc == 0, err
    out = w / "x"
    c = {
        "runs": 0,
        "kills": 0,
        "damages": 0,
        "damage_notes": 0,
        "stale_lock_notes": 0,
        "tracebacks": 0,
        "other_exit_status": 0,
    }
    for _ in range(40):
        rc, err = run(out, rng, kill_after=rng.randint(1, 2))
        c["runs"] += 1
        c["tracebacks"] += "Traceback" in err
        c["damage_notes"] += err.count("computing it again")
        c["stale_lock_notes"] += err.count("took over the lock")
        if rc == -9:
            c["kills"] += 1
            c["damages"] += damage(out / "atlas.zarr", rng, DAMAGES[c["damages"] % len(DAMAGES)])
        elif rc == 0 and ndone(out) == TILES:
            break
        else:
            c["other_exit_status"] += 1
    rc, err = run(out, rng)
    c["runs"] += 1
    c["damage_notes"] += err.count("computing it again")
    c["stale_lock_notes"] += err.count("took over the lock")
    c["final_exit_status"] = rc
    ref, got = zarr.open_group(str(w / "ref/atlas.zarr"), mode="r"), zarr.open_group(str(out / "atlas.zarr"), mode="r")
    c["identical_to_uninterrupted"] = all(
        np.array_equal(ref[k][...], got[k][...], equal_nan=True)
        for k in ("lambda1", "lambda2", "period_p", "period_m", "status")
    )
    c["two_at_once_exit_statuses"], c["second_writer_refused_in_one_line"] = [], 0
    for n in range(2):
        o = w / f"two{n}"
        ps = [
            subprocess.Popen(
                [*GR, *ARGS, "--store", str(o / "s.zarr"), "--out", str(o / f"o{m}")],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                text=True,
            )
            for m in range(2)
        ]
        res = sorted((p.wait(), p.stderr.read()) for p in ps)
        c["two_at_once_exit_statuses"].append([r for r, _ in res])
        c["second_writer_refused_in_one_line"] += sum(
            r == 1 and e.count("\n") == 1 and "in use by another writer" in e for r, e in res
        )
    print(json.dumps(c))


if __name__ == "__main__":
    main()
