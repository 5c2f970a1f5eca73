"""Regenerate the golden conformance suite: ``python -m gear_rattle.validation.golden.generate [--cases ID ...]``.

Every case of the catalogue (:mod:`.catalog.specs`) is certified from scratch with ball arithmetic
(:mod:`mapimpl.certified`) and written to ``validation/golden/cases/<id>/`` (``settings.json``,
``expected.csv``, ``provenance.json``: :mod:`.catalog.build`), then the suite's index
(:func:`.formats.index.write_index`).  Deterministic: the same software writes byte-identical files.  The
map and scipy tracks are run on every case and their deviations recorded in the provenance ("agreed by two
tracks"); they never feed the expected numbers.

Case settings that are *found* rather than chosen (the grazing initial velocities, the chaotic
horizon) are computed by the catalogue, by documented rules, every time.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from .paths import DEFAULT_SUITE
from .catalog.build import build_case
from .catalog.specs import specs
from .formats.case_writer import write_case
from .formats.cases import case_ids
from .formats.index import write_index
from .formats.spec import spec_from_settings


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m gear_rattle.validation.golden.generate", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--out", default=str(DEFAULT_SUITE), help="suite directory (default: the committed one)")
    ap.add_argument("--cases", nargs="*", default=None, help="only these case ids")
    ap.add_argument("--no-tracks", action="store_true", help="skip the map/scipy agreement in the provenance")
    ap.add_argument(
        "--recertify",
        action="store_true",
        help="re-certify the committed cases with their committed settings (no searches)",
    )
    args = ap.parse_args(argv)
    from ...core.jax_config import use_cpu_devices

    use_cpu_devices()  # as the command line does: the engine's float64 samples in the notes are the CLI's
    t0 = time.time()
    if args.recertify:
        all_specs = [
            spec_from_settings(json.loads((DEFAULT_SUITE / c / "settings.json").read_text())) for c in case_ids()
        ]
    else:
        all_specs = specs()
    known = [s.id for s in all_specs]
    if args.cases:
        bad = [c for c in args.cases if c not in known]
        if bad:
            print(f"unknown case id(s): {', '.join(bad)} (known: {', '.join(known)})", file=sys.stderr)
            return 2
    for spec in all_specs:
        if args.cases and spec.id not in args.cases:
            continue
        t = time.time()
        if spec.finish is not None:
            spec = spec.finish(spec)
        settings, text, prov = build_case(spec, tracks=not args.no_tracks)
        write_case(Path(args.out) / spec.id, settings, text, prov)
        agree = prov["tracks_agreement"] or {}
        ok = ", ".join(f"{k}: {'agrees' if v.get('agrees') else 'DISAGREES'}" for k, v in agree.items())
        print(
            f"{spec.id}: {settings['expected_rows']} rows, status {settings['expected_status']}, "
            f"max tau radius {prov['radius']['tau_radius'].get('max')}, {ok} ({time.time() - t:.1f} s)"
        )
    print(f"{write_index(Path(args.out))}: index of the cases in {args.out}")
    print(f"done in {time.time() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
