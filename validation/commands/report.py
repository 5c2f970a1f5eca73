"""Run every reproduction and write the validation report: a self-contained HTML page, a Markdown
twin, figures and a JSON summary.  The quick profile runs in a few minutes (it runs in CI); the
paper profile uses the paper's resolution.  Exit status 1 if any section failed."""

from __future__ import annotations

import argparse

from ..cliutil import add_output_options, check_outputs, note, print_result, seed_int
from ..report.builder import SECTION_KEYS

NAME = "report"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--profile", choices=("quick", "paper"), default="quick", help="quick or paper scale (default quick)"
    )
    p.add_argument(
        "--seed",
        type=seed_int(),
        default=20040101,
        help="random seed of every sampled quantity, 0 to 2**32-1 (default 20040101)",
    )
    p.add_argument(
        "--sections",
        nargs="+",
        default=None,
        metavar="KEY",
        choices=SECTION_KEYS,
        help=f"run only these sections, of {', '.join(SECTION_KEYS)} (default: all sections)",
    )
    add_output_options(
        p,
        out=(
            "report",
            "output directory (default report); written when the run ends, an interrupted run leaves it as it was",
        ),
    )


def run(args: argparse.Namespace) -> int:
    import sys
    from pathlib import Path

    from ..io import read_json
    from ..report.builder import build_report

    check_outputs(args)
    path, ok = build_report(
        args.profile,
        args.out,
        args.sections,
        seed=args.seed,
        progress=not args.quiet,
        argv=["gear-rattle", *sys.argv[1:]],
    )
    summary = read_json(Path(args.out) / "summary.json")
    c = summary["counts"]
    print_result(
        summary,
        [f"report written: {path}", "verdicts: " + ", ".join(f"{k} {v}" for k, v in c.items())],
        [Path(args.out) / "summary.json"],
    )
    if not ok:
        note("some sections FAILED (see the report)")
    return 0 if ok else 1


__all__ = [
    "NAME",
    "add_arguments",
    "run",
]
