"""Sample implementations' output for the golden suite: what a perfect implementation writes, and what
a faulty one does (a wrong value, a malformed or missing file, a crash).

    python .ci/golden_sample.py GOLDEN OUT [--levels 1,2] [--no-orbits] [--break ID] [--malformed ID]
                                           [--drop ID] [--crash-after N]

``GOLDEN`` is the suite's folder holding ``cases/`` and ``orbits/`` (``validation/golden``, or a copy
written by ``gear-rattle check --export-suite``); writes ``OUT/<case-id>.csv`` (each case's certified
``expected.csv``: extra trailing columns are ignored by ``gear-rattle check``) for the cases of the
levels given (``--levels``, as read from each ``settings.json``; default all) and ``OUT-orbits/<id>.json``
(each record's interval midpoints; not with ``--no-orbits``).  Faults: ``--break ID`` moves one value of
case or record ID far outside its tolerance (its first ``tau``, or its ``value`` / first multiplier);
``--malformed ID`` writes that file with a second ``tau`` column; ``--drop ID`` writes no file for it;
``--crash-after N`` stops after N case files with exit status 101, as a panicking program does (after
the orbit files; N = 0: before writing anything, no folder made; N at least the number of cases: every
file written, then the crash).  Standard library
only: it runs in the light install's CI stage (.ci/run) and in tests/test_check_ci.py.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

#: The exit status of ``--crash-after`` (a Rust panic's).
CRASH_STATUS = 101


class Crash(Exception):
    """``--crash-after``: the sample stops as a crashing implementation does."""


def _case_rows(case: Path, broken: bool, malformed: bool) -> list[list[str]]:
    rows = list(csv.reader((case / "expected.csv").read_text(encoding="utf-8").splitlines()))
    j = rows[0].index("tau")
    if broken:
        rows[1][j] = repr(float(rows[1][j]) + 0.5)
    if malformed:  # a second column named tau: the format refuses it
        rows = [rows[0] + ["tau"]] + [r + [r[j]] for r in rows[1:]]
    return rows


def record_values(path: Path, broken: bool) -> dict:
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
    if broken:
        if "value" in d:
            d["value"] += 0.5
        else:
            d["multipliers"][0]["re"] += 0.5
    return d


def write_sample(
    golden: Path,
    out: Path,
    broken: str | None = None,
    *,
    levels: list[int] | None = None,
    orbits: bool = True,
    malformed: str | None = None,
    drop: str | None = None,
    crash_after: int | None = None,
) -> tuple[Path, Path]:
    """Write the sample outputs (module docstring); returns the two folders (the second is not written
    without ``orbits``).  :class:`Crash` after ``crash_after`` case files."""
    orbits_out = out.with_name(out.name + "-orbits")
    if crash_after == 0:
        raise Crash("before writing anything")
    out.mkdir(parents=True, exist_ok=True)
    if orbits:
        orbits_out.mkdir(parents=True, exist_ok=True)
        for path in sorted((golden / "orbits").glob("*.json")):
            if path.stem != drop:
                text = json.dumps(record_values(path, path.stem == broken))
                (orbits_out / path.name).write_text(text + ("}" if path.stem == malformed else ""), encoding="utf-8")
    written = 0
    for case in sorted(p for p in (golden / "cases").iterdir() if (p / "expected.csv").is_file()):
        level = json.loads((case / "settings.json").read_text(encoding="utf-8")).get("level")
        if (levels and level not in levels) or case.name == drop:
            continue
        if crash_after is not None and written >= crash_after:
            raise Crash(case.name)
        with open(out / f"{case.name}.csv", "w", newline="", encoding="utf-8") as fh:
            csv.writer(fh, lineterminator="\n").writerows(_case_rows(case, case.name == broken, case.name == malformed))
        written += 1
    if crash_after is not None:
        raise Crash("after the last case")
    return out, orbits_out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("golden", type=Path)
    p.add_argument("out", type=Path)
    p.add_argument("--break", dest="broken", default=None, metavar="ID")
    p.add_argument("--levels", type=lambda t: [int(x) for x in t.split(",")], default=None)
    p.add_argument("--no-orbits", dest="orbits", action="store_false")
    p.add_argument("--malformed", default=None, metavar="ID")
    p.add_argument("--drop", default=None, metavar="ID")
    p.add_argument("--crash-after", type=int, default=None, metavar="N")
    a = p.parse_args(argv)
    try:
        write_sample(
            a.golden, a.out, a.broken, levels=a.levels, orbits=a.orbits, malformed=a.malformed, drop=a.drop,
            crash_after=a.crash_after,
        )  # fmt: skip
    except Crash as e:
        print(f"thread 'main' panicked at src/main.rs: simulated crash ({e})")
        return CRASH_STATUS
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
