"""The margin of every row of the shipped golden suite: tolerance / actual error of our tracks and of the correct
variants of the mutation test (tests/golden_mutants.py: every contact displaced by the modelled per-contact
error, all late or with pseudo-random signs), per row and column (docs/golden_tolerances.md, "Tolerances from the
conditioning"; issue 36).

Per case and implementation: the median and the smallest of ``tolerance / |error|`` over the rows (the
smallest over the columns of a row; a row without error counts as infinite), and the largest share
``|error| / tolerance``.  Usage: ``python benchmarks/bench_tolerance_margins.py [--suite DIR] [--out FILE]
[--impls map,scipy,diffrax,gap-error-late,gap-error-random]``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.formats.cases import TOLERANCE_COLUMNS, load_suite, sequence_from_impacts
from gear_rattle.validation.golden.scoring.cases import circular_distance
from gear_rattle.validation.golden.self_check import run_case

VARIANTS = ("gap-error-late", "gap-error-random")


def outputs(case, impl: str):
    """The rows ``(tau, tau_mod_2pi, sdot)`` of an implementation on a case (None: other events)."""
    if impl in VARIANTS:
        from golden_mutants import Mutant, run

        rows = run(case.settings, Mutant(impl, gap_error=impl.rsplit("-", 1)[1]))
        seq = (
            np.array([r[1] for r in rows]),
            np.array([r[1] % (2 * math.pi) for r in rows]),
            np.array([r[3] for r in rows]),
        )
    else:
        s = sequence_from_impacts(run_case(case, impl))
        seq = (s.tau, s.tau_mod_2pi, s.sdot)
    return seq if len(seq[0]) == len(case.expected) else None


def margins(case, got) -> dict:
    e = case.expected
    ratio = np.full(len(e), math.inf)  # tolerance / |error|, the smallest over the columns
    share = 0.0
    for c, x in zip(TOLERANCE_COLUMNS, got):
        g = getattr(e, c)
        err = circular_distance(x, g) if c == "tau_mod_2pi" else np.abs(x - g)
        tol = case.row_tolerances(c)[0]
        m = ~np.isnan(g)
        with np.errstate(divide="ignore"):
            r = np.where(m & (err > 0), tol / np.where(err > 0, err, 1.0), math.inf)
        ratio = np.minimum(ratio, r)
        share = max(share, float(np.max(np.where(m, err / tol, 0.0))))
    return {"median": float(np.median(ratio)), "min": float(np.min(ratio)), "largest_share": share}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--suite", default=str(DEFAULT_SUITE))
    ap.add_argument("--impls", default="map,scipy,diffrax," + ",".join(VARIANTS))
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    t = time.time()
    res: dict = {}
    for case in load_suite(a.suite):
        entry: dict = {
            "rows": len(case.expected),
            "tolerance": {
                c: {
                    "min": float(np.nanmin(case.row_tolerances(c)[0][~np.isnan(getattr(case.expected, c))])),
                    "median": float(np.nanmedian(case.row_tolerances(c)[0][~np.isnan(getattr(case.expected, c))])),
                    "max": float(np.nanmax(case.row_tolerances(c)[0])),
                }
                for c in TOLERANCE_COLUMNS
            },
        }
        for impl in a.impls.split(","):
            got = outputs(case, impl)
            entry[impl] = "other events" if got is None else margins(case, got)
        res[case.id] = entry
        print(case.id, {k: v for k, v in entry.items() if k not in ("rows", "tolerance")}, flush=True)
    res["_seconds"] = round(time.time() - t, 1)
    if a.out:
        Path(a.out).write_text(json.dumps(res, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
