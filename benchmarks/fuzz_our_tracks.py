"""False positives of the oracle on our own tracks (issue 36 item 2): ``gear-rattle check --self`` and
``gear-rattle fuzz --keep-going`` on the map, scipy and diffrax tracks, whose answers are correct: a failure is a
false positive of the oracle (or a defect of the track), to be triaged.

Runs ``check --self --track T`` for each track, then the fuzz runs (a track, a seed, a budget, the scenarios:
all, or a group of them), each with ``--keep-going --quiet --json``, and writes one JSON table: per run the
cases, batches, inputs drawn and skipped, the elapsed seconds, the load average before and after, and every
group of failures (signature, scenario, message, shrunk input).  The failing cases stay in ``--keep DIR``.

Usage: ``python benchmarks/fuzz_our_tracks.py --out FILE [--budget 240] [--group-budget 120] [--seed 61]
[--tracks map,scipy,diffrax] [--groups wide,long,sticking] [--no-check] [--keep DIR]``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from gear_rattle.validation.io.atomic import write_text_atomic

ROOT = Path(__file__).resolve().parents[1]
TRACKS = ("map", "scipy", "diffrax")
#: The scenario groups of the whole box (validation/golden/scenarios.py): the wide parameter box, long orbits
#: and flights, and the sticking decisions at any ``stick_time``.
GROUPS = {
    "wide": ("wide-generic", "wide-graze", "wide-chatter"),
    "long": ("long-orbit", "long-flight"),
    "sticking": ("stick-threshold", "release-delay", "stuck-forever", "chatter-lower", "chatter-upper"),
}


def gear_rattle() -> list[str]:
    """The command line of this checkout's ``gear-rattle`` (the interpreter running this script)."""
    return [str(Path(sys.executable).parent / "gear-rattle")]


def load() -> float:
    return round(os.getloadavg()[0], 2)


def commit() -> str:
    out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True)
    return out.stdout.strip()


def check_self(track: str, work: Path) -> dict:
    """``check --self --track track``: the counts and the smallest tolerance / |error| over the cases."""
    js = work / f"check-{track}.json"
    t, l0 = time.time(), load()
    rc = subprocess.run(
        [*gear_rattle(), "check", "--self", "--track", track, "--json", str(js), "--quiet"],
        capture_output=True,
        text=True,
    ).returncode
    res = json.loads(js.read_text()) if js.is_file() else {}
    worst = [c["worst_over_tolerance"] for c in res.get("results", []) if c.get("worst_over_tolerance") is not None]
    return {
        "track": track,
        "exit": rc,
        "counts": {k: res.get(k) for k in ("tests", "passed", "failed", "errors", "skipped")},
        "largest_error_over_tolerance": max(worst) if worst else None,
        "seconds": round(time.time() - t, 1),
        "load_avg": f"{l0}-{load()}",
    }


def fuzz(track: str, seed: int, budget: float, scenarios: tuple[str, ...] | None, keep: Path) -> dict:
    """One ``fuzz --keep-going`` run of our ``track``: its summary, condensed."""
    impl = f"{sys.executable} -m gear_rattle.validation.commands.trackimpl --track {track}"
    name = f"{track}-{seed}" + ("" if scenarios is None else "-" + scenarios[0].split("-")[0])
    js = keep / f"{name}.json"
    cmd = [*gear_rattle(), "fuzz", "--impl", impl, "--seed", str(seed), "--budget", str(budget), "--keep-going"]
    cmd += ["--quiet", "--json", str(js), "--out", str(keep / name)]
    if scenarios:
        cmd += ["--scenarios", *scenarios]
    l0 = load()
    rc = subprocess.run(cmd, capture_output=True, text=True).returncode
    s = json.loads(js.read_text()) if js.is_file() else {}
    return {
        "track": track,
        "seed": seed,
        "budget_s": budget,
        "scenarios": "all" if scenarios is None else list(scenarios),
        "exit": rc,
        "elapsed_s": s.get("elapsed_s"),
        "cases": s.get("cases"),
        "batches": s.get("batches"),
        "inputs_drawn": s.get("inputs_drawn"),
        "inputs_skipped": s.get("inputs_skipped"),
        "status": "clean" if rc == 0 else "failures" if rc == 1 else "error",
        "failures": [
            {k: g.get(k) for k in ("signature", "scenario", "count", "message", "input", "original_input", "folder")}
            for g in s.get("groups", [])
        ],
        "error": s.get("error"),
        "load_avg": f"{l0}-{load()}",
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="the JSON table to write")
    ap.add_argument("--tracks", default=",".join(TRACKS))
    ap.add_argument("--groups", default=",".join(GROUPS), help="scenario groups, one run per track each ('' none)")
    ap.add_argument("--budget", type=float, default=240.0, help="seconds of each run on all scenarios")
    ap.add_argument("--group-budget", type=float, default=120.0, help="seconds of each run on a group")
    ap.add_argument("--seed", type=int, default=61, help="the first seed (one more per run)")
    ap.add_argument("--no-check", action="store_true", help="skip check --self")
    ap.add_argument("--keep", default=None, help="where the failing cases are kept (default: a temporary folder)")
    a = ap.parse_args(argv)
    tracks = [t for t in a.tracks.split(",") if t]
    groups = [g for g in a.groups.split(",") if g]
    keep = Path(a.keep) if a.keep else Path(tempfile.mkdtemp(prefix="fuzz-our-tracks-"))
    keep.mkdir(parents=True, exist_ok=True)
    out: dict = {
        "what": "our three tracks through check --self and fuzz --keep-going (issue 36 item 2): every failure is a "
        "false positive of the oracle or a defect of the track",
        "date": time.strftime("%Y-%m-%d"),
        "commit": commit(),
        "machine": f"{os.cpu_count()} cores shared with other sessions (load averages per run)",
        "check_self": [],
        "runs": [],
    }

    def save() -> None:
        write_text_atomic(a.out, json.dumps(out, indent=1) + "\n")

    if not a.no_check:
        for track in tracks:
            out["check_self"].append(check_self(track, keep))
            print("check --self", out["check_self"][-1], flush=True)
            save()
    plan = [(t, None, a.budget) for t in tracks] + [(t, GROUPS[g], a.group_budget) for g in groups for t in tracks]
    for k, (track, scenarios, budget) in enumerate(plan):
        run = fuzz(track, a.seed + k, budget, scenarios, keep)
        out["runs"].append(run)
        print("fuzz", {x: run[x] for x in ("track", "seed", "scenarios", "cases", "status", "load_avg")}, flush=True)
        save()
    failed = [r for r in out["runs"] if r["status"] != "clean"]
    failed += [c for c in out["check_self"] if c["exit"] != 0]
    out["outcome"] = "no failure" if not failed else f"{len(failed)} runs with failures: triage them"
    save()
    if not a.keep and not failed:
        shutil.rmtree(keep, ignore_errors=True)
    print(out["outcome"], "kept in", keep if failed or a.keep else "(removed)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
