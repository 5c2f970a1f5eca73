"""Time series of Figs. 5-7: the discrete velocity sdot_n before each impact and the stroboscopic
velocity sdot(2 pi k) once per driving period (closed-form flight from the last impact).
--figure fig5|fig6|fig7 sets r to the paper's value (alpha = 3, beta = gamma = 0.1)."""

from __future__ import annotations

import argparse

from ..cliutil import add_param_args, check_writable, nonneg_int, params_from, positive_int, write_text

NAME = "timeseries"
HELP = "discrete and stroboscopic velocity time series (Figs. 5-7)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("--figure", choices=("fig5", "fig6", "fig7"), default=None, help="use the paper's r of this figure")
    p.add_argument("--impacts", type=positive_int("--impacts"), default=3000)
    p.add_argument("--transient", type=nonneg_int("--transient"), default=2000)
    p.add_argument("--tau0", type=float, default=0.0)
    p.add_argument("--sdot0", type=float, default=0.5)
    p.add_argument("--output", default=None, help=".npz or .csv (default: CSV on stdout)")
    p.add_argument("--plot", default=None, metavar="FILE.png")


def run(args: argparse.Namespace) -> int:
    from ..dynamics.timeseries import FIGURE_R, plot_time_series, time_series

    base = params_from(args)
    if args.figure:
        base = base.replace(alpha=3.0, beta=0.1, gamma=0.1, r=FIGURE_R[args.figure])
    check_writable(args.output, "--output")
    check_writable(args.plot, "--plot")
    if args.impacts < 2:
        raise ValueError("--impacts is out of range: allowed >= 2")
    ts = time_series(base, args.impacts, args.transient, args.tau0, args.sdot0)
    if args.output and args.output.endswith(".npz"):
        ts.save_npz(args.output)
    else:
        write_text(ts.to_csv(), args.output)
    if args.plot:
        plot_time_series(ts, args.plot, title=f"{args.figure or ''} alpha={base.alpha}, r={base.r}")
    return 0
