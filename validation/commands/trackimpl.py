"""Our tracks as an implementation under the suite's protocol: ``python -m gear_rattle.validation.commands.trackimpl
[--track map|scipy|diffrax] CASES_DIR OUT_DIR`` runs every case folder of CASES_DIR (its settings.json;
expected.csv is not read) and writes OUT_DIR/<case-id>.csv, as any implementation that runs the golden
suite does.  ``gear-rattle fuzz --impl "python -m gear_rattle.validation.commands.trackimpl --track scipy"``
fuzzes our own tracks (docs/reference/golden_commands.md, "Fuzzing an implementation"): it must find nothing.

Every track takes the case's sticking threshold ``stick_time`` (0 <= stick_time <= 1e-2, the library's range,
:func:`mapimpl.sticking.check_stick_time`), so a case of any threshold that ``gear-rattle case`` builds runs.
Exit status 0, or 2 with one line on stderr (a settings file our tracks cannot run, named).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path


def run_folder(cases: Path, out: Path, track: str) -> int:
    """Run every case folder of ``cases`` on ``track``; returns the number of cases."""
    from ..golden.self_check import run_settings
    from ..io import write_csv

    out.mkdir(parents=True, exist_ok=True)
    folders = sorted(p for p in cases.iterdir() if (p / "settings.json").is_file())
    for folder in folders:
        s = json.loads((folder / "settings.json").read_text())
        try:
            seq = run_settings(s, track)
        except ValueError as e:
            raise ValueError(f"{folder.name}: {e}") from None
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
