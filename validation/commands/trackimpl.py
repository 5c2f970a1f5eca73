"""Our tracks as an implementation under the suite's protocol: ``python -m gear_rattle.validation.commands.trackimpl
[--track map|scipy|diffrax] CASES_DIR OUT_DIR`` runs every case folder of CASES_DIR (its settings.json;
expected.csv is not read) and writes OUT_DIR/<case-id>.csv, as any implementation that runs the golden
suite does.  ``gear-rattle fuzz --impl "python -m gear_rattle.validation.commands.trackimpl --track scipy"``
fuzzes our own tracks (docs/golden.md, "Fuzzing an implementation"): it must find nothing.

Exit status 0, or 2 with one line on stderr (a case our tracks cannot run: a sticking threshold other than
STICK_TIME, which the tracks do not take).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path


def run_folder(cases: Path, out: Path, track: str) -> int:
    """Run every case folder of ``cases`` on ``track``; returns the number of cases."""
    from ...mapimpl.sticking import STICK_TIME
    from ..golden.suite import run_settings
    from ..io import write_csv

    out.mkdir(parents=True, exist_ok=True)
    folders = sorted(p for p in cases.iterdir() if (p / "settings.json").is_file())
    for folder in folders:
        s = json.loads((folder / "settings.json").read_text())
        if s.get("stick_time", STICK_TIME) != STICK_TIME:
            raise ValueError(f"{folder.name}: stick_time={s['stick_time']!r}: the tracks take only {STICK_TIME:g}")
        seq = run_settings(s, track)
        write_csv(out / f"{s['id']}.csv", *seq.table())
    return len(folders)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m gear_rattle.validation.commands.trackimpl", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--track", choices=("map", "scipy", "diffrax"), default="map")
    ap.add_argument("cases", type=Path)
    ap.add_argument("out", type=Path)
    args = ap.parse_args(argv)
    from ...core._jax import use_cpu_devices

    use_cpu_devices()
    try:
        run_folder(args.cases, args.out, args.track)
    except (ValueError, OSError, KeyError) as e:
        print(f"trackimpl: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
