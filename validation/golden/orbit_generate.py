"""Regenerate the golden periodic orbits and bifurcation points:
``python -m gear_rattle.validation.golden.orbit_generate [--cases ID ...] [--out DIR] [--from-records]``.

Each record of the catalogue (:mod:`.catalog.orbits`) is found in float64 first (the *seed*), proven in
ball arithmetic and written to ``validation/golden/orbits/<id>.json`` (:mod:`.catalog.orbit_records`),
after the written record has been proven again from its own decimal intervals
(:func:`.catalog.orbit_records.verify_record`).  Deterministic: the same software writes byte-identical
files.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .catalog.orbits import CASE_IDS, CASES, build, float64_seeds, seeds_from_records
from .paths import DEFAULT_ORBITS


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--cases", nargs="+", default=None, metavar="ID", choices=CASE_IDS, help="only these case ids (default: all)"
    )
    ap.add_argument("--out", default=str(DEFAULT_ORBITS), help="output directory (default: validation/golden/orbits)")
    ap.add_argument(
        "--from-records",
        action="store_true",
        help="seed from the committed records' midpoints instead of the float64 runs (fast)",
    )
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    seeds = seeds_from_records() if args.from_records else float64_seeds()
    t1 = time.perf_counter()
    for case in CASES:
        if args.cases and case.id not in args.cases:
            continue
        (out / f"{case.id}.json").write_text(build(case, seeds[case.id]))
        print(f"wrote {out / (case.id + '.json')}", file=sys.stderr)
    t2 = time.perf_counter()
    print(f"float64 seeds {t1 - t0:.1f} s, certification and re-verification {t2 - t1:.2f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
