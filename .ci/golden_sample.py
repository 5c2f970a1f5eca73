"""A sample implementation's output for the golden suite: what a perfect implementation writes.

    python .ci/golden_sample.py GOLDEN OUT [--break ID]

``GOLDEN`` is the suite's folder (``validation/golden``, holding ``cases/`` and ``orbits/``); writes
``OUT/<case-id>.csv`` (each case's certified ``expected.csv``: extra trailing columns are ignored by
``gear-rattle check``) and ``OUT-orbits/<id>.json`` (each record's interval midpoints).  ``--break
ID`` moves one value of case or record ID far outside its tolerance (its first ``tau``, or its
``value`` / first multiplier), so that exactly that one fails.  Standard library only: it runs in the
light install's CI stage (.ci/run) and in tests/test_check_ci.py.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path


def write_sample(golden: Path, out: Path, broken: str | None = None) -> tuple[Path, Path]:
    """Write the sample outputs (module docstring); returns the two folders."""
    orbits_out = out.with_name(out.name + "-orbits")
    out.mkdir(parents=True, exist_ok=True)
    orbits_out.mkdir(parents=True, exist_ok=True)
    for case in sorted(p for p in (golden / "cases").iterdir() if (p / "expected.csv").is_file()):
        rows = list(csv.reader((case / "expected.csv").read_text(encoding="utf-8").splitlines()))
        if case.name == broken:
            j = rows[0].index("tau")
            rows[1][j] = repr(float(rows[1][j]) + 0.5)
        with open(out / f"{case.name}.csv", "w", newline="", encoding="utf-8") as fh:
            csv.writer(fh, lineterminator="\n").writerows(rows)
    for path in sorted((golden / "orbits").glob("*.json")):
        rec = json.loads(path.read_text(encoding="utf-8"))
        d = {
            "points": [
                {"tau_mod_2pi": sum(p["tau_mod_2pi"]) / 2, "sdot": sum(p["sdot"]) / 2, "wall": p["wall"]}
                for p in rec["points"]
            ],
            "multipliers": [{"re": sum(m["re"]) / 2, "im": sum(m["im"]) / 2} for m in rec["multipliers"]],
        }
        if "value" in rec:
            d["value"] = sum(rec["value"]) / 2
        if path.stem == broken:
            if "value" in d:
                d["value"] += 0.5
            else:
                d["multipliers"][0]["re"] += 0.5
        (orbits_out / path.name).write_text(json.dumps(d), encoding="utf-8")
    return out, orbits_out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("golden", type=Path)
    p.add_argument("out", type=Path)
    p.add_argument("--break", dest="broken", default=None, metavar="ID")
    a = p.parse_args(argv)
    write_sample(a.golden, a.out, a.broken)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
