"""Run every reproduction and write the validation report: a self-contained HTML page, a Markdown
twin, figures and a JSON summary.  The quick profile runs in a few minutes (it runs in CI); the
paper profile uses the paper's resolution.  Exit status 1 if any section failed."""

from __future__ import annotations

import argparse

NAME = "report"
HELP = "generate the validation report (HTML + Markdown)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--profile", choices=("quick", "paper"), default="quick", help="quick (default) or paper scale")
    p.add_argument("--out", default="report", help="output directory (default: report)")
    p.add_argument("--seed", type=int, default=20040101, help="random seed of every sampled quantity")
    p.add_argument("--sections", nargs="*", default=None, help="run only these section keys")
    p.add_argument("--quiet", action="store_true", help="no progress output")


def run(args: argparse.Namespace) -> int:
    import sys

    from ..report.builder import build_report

    path, ok = build_report(args.profile, args.out, args.sections, seed=args.seed, progress=not args.quiet,
                            argv=["gear-rattle", *sys.argv[1:]])
    print(f"report written: {path}")
    if not ok:
        print("gear-rattle report: some sections FAILED (see the report)", file=sys.stderr)
    return 0 if ok else 1
