"""Run every reproduction and write the validation report: a self-contained HTML page, a Markdown
twin, figures and a JSON summary.  The quick profile runs in a few minutes (it runs in CI); the
paper profile uses the paper's resolution.  Exit status 1 if any section failed."""

from __future__ import annotations

import argparse

from ..cliutil import CliError, add_output_options, check_outputs, seed_int

NAME = "report"
HELP = "generate the validation report (HTML + Markdown)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--profile", choices=("quick", "paper"), default="quick",
                   help="quick or paper scale (default quick)")
    p.add_argument("--seed", type=seed_int(), default=20040101,
                   help="random seed of every sampled quantity, 0 to 2**32-1 (default 20040101)")
    p.add_argument("--sections", nargs="*", default=None, metavar="KEY",
                   help="run only these section keys (default: all sections)")
    add_output_options(p, out=("report", "output directory (default report)"), quiet="no progress output")


def section_keys() -> list[str]:
    """The report's section keys, in order."""
    import importlib

    from ..report.builder import SECTIONS

    return [importlib.import_module(m).KEY for m in SECTIONS]


def run(args: argparse.Namespace) -> int:
    import sys

    from ..report.builder import build_report

    if args.sections:
        keys = section_keys()
        unknown = [s for s in args.sections if s not in keys]
        if unknown:
            raise CliError(f"--sections: unknown key(s) {', '.join(unknown)}: allowed {', '.join(keys)}")
    check_outputs(args)
    path, ok = build_report(args.profile, args.out, args.sections, seed=args.seed, progress=not args.quiet,
                            argv=["gear-rattle", *sys.argv[1:]])
    print(f"report written: {path}")
    if not ok:
        print("gear-rattle report: some sections FAILED (see the report)", file=sys.stderr)
    return 0 if ok else 1
