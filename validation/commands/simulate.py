"""Simulate one orbit and print its events: one row per impact (n, tau, tau mod 2 pi, wall, sdot just
before the impact, kind) plus stick/release rows under the sticking policy.

The initial state (--tau0, --sdot0) is the state just before an impact (sdot0 > 0 hits s = 0,
sdot0 < 0 hits s = -1), as in the paper; with --s0 it is a free-flight state instead.
"""

from __future__ import annotations

import argparse

from ..cliutil import add_param_args, check_writable, nonneg_int, params_from, write_text

NAME = "simulate"
HELP = "simulate one orbit (impact sequence, CSV/JSON, optional Figs. 2-3 plot)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("--tau0", type=float, default=0.0, help="initial time tau0 (default 0)")
    p.add_argument("--sdot0", type=float, default=0.5, help="initial velocity (default 0.5)")
    p.add_argument("--s0", type=float, default=None, help="start in free flight at -1 <= s0 <= 0 instead of at an impact")
    p.add_argument("--impacts", type=nonneg_int("--impacts"), default=1000, help="impacts after impact 0 (default 1000)")
    p.add_argument("--track", choices=("map", "scipy", "diffrax"), default="map", help="which track computes the orbit")
    p.add_argument("--format", choices=("csv", "json"), default="csv", help="output format (default csv)")
    p.add_argument("--output", default=None, help="output file (default: stdout)")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="draw the paper's Figs. 2-3 for this orbit")
    p.add_argument("--plot-span", type=float, default=50.0, help="time span of the plot in tau units (default 50)")


def run(args: argparse.Namespace) -> int:
    from ..tracks import orbit

    params = params_from(args)
    check_writable(args.output, "--output")
    check_writable(args.plot, "--plot")
    if not args.plot_span > 0:
        raise ValueError(f"--plot-span={args.plot_span!r} is out of range: allowed > 0")
    seq = orbit(args.track, params, args.tau0, args.sdot0, args.impacts, s0=args.s0)
    write_text(seq.to_csv() if args.format == "csv" else seq.to_json() + "\n", args.output)
    if seq.status != "active":
        import sys

        why = {"no_impact": "no wall is reached within the flight horizon T_MAX",
               "stuck_forever": "the tooth sticks to a wall and the forcing never releases it",
               "step_cap": "the impact search hit its iteration cap"}.get(seq.status, seq.status)
        print(f"gear-rattle simulate: note: the orbit ended after {int(seq.impacts.sum())} impacts "
              f"(status {seq.status}: {why})", file=sys.stderr)
    if args.plot:
        from ..plots import plot_time_series

        plot_time_series(seq, args.plot, span=args.plot_span)
    return 0
