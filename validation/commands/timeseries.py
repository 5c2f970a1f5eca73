"""Time series of Figs. 5-7: the discrete velocity sdot_n before each impact and the stroboscopic
velocity sdot(2 pi k) once per driving period (closed-form flight from the last impact).
--figure fig5|fig6|fig7 sets r to the paper's value (alpha = 3, beta = gamma = 0.1)."""

from __future__ import annotations

import argparse

from ...core.paper import PAPER_FIG3
from ..cliutil import (
    MAX_IMPACTS,
    CliError,
    add_output_options,
    add_param_args,
    check_outputs,
    given_params,
    int_range,
    nonneg_int,
    params_from,
    progress_arg,
    add_start_args,
    check_start_args,
    write_result,
    write_plot,
)

NAME = "timeseries"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument(
        "--figure",
        choices=("fig5", "fig6", "fig7"),
        default=None,
        help="the paper's parameters of this figure: alpha = 3, beta = gamma = 0.1 and its r; not with "
        "--alpha/--beta/--gamma/--r (default: none, use --alpha ... --r)",
    )
    p.add_argument(
        "--impacts",
        type=int_range("--impacts", 2, MAX_IMPACTS),
        default=3000,
        help=f"impacts recorded after --transient, 2 to {MAX_IMPACTS} (default 3000)",
    )
    p.add_argument(
        "--transient",
        type=nonneg_int("--transient", MAX_IMPACTS),
        default=2000,
        help=f"impacts discarded first, 0 to {MAX_IMPACTS} (default 2000)",
    )
    add_start_args(p)
    add_output_options(p, output="the two series", plot="write the figure (default: no figure)")


def run(args: argparse.Namespace) -> int:
    from ..dynamics.timeseries import FIGURE_R, time_series

    base = params_from(args)
    if args.figure:
        given = given_params(args)
        if given:
            raise CliError(
                f"{', '.join(given)}: not allowed with --figure {args.figure} (it sets alpha = 3, "
                f"beta = gamma = 0.1, r = {FIGURE_R[args.figure]}): give one or the other"
            )
        base = PAPER_FIG3.replace(r=FIGURE_R[args.figure])
    check_outputs(args)
    check_start_args(args)
    ts = time_series(base, args.impacts, args.transient, args.tau0, args.sdot0, progress=progress_arg(args))
    if ts.k.size == 0:
        raise CliError(
            f"--impacts={args.impacts} is too small: the impacts kept after --transient={args.transient} "
            "span less than one forcing period (2 pi), so there is no stroboscopic sample; "
            "allowed: enough impacts to span a period (the orbit may chatter or stick)"
        )
    write_result(args, ts)
    if args.plot:
        from ..plots import velocity_series_figure

        from ..plots.base import params_text

        title = f"{args.figure}: {params_text(base)}" if args.figure else None  # default: the parameters
        write_plot(args, velocity_series_figure(ts, title=title))
    return 0


__all__ = [
    "NAME",
    "add_arguments",
    "run",
]
