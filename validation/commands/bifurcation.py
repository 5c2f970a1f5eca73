"""Bifurcation diagram of the impact map: sdot_n against r (Fig. 4a, alpha = 3) or alpha (Fig. 8a,
r = 0.9), transients discarded.  --mode fixed starts every value from the same initial condition;
--mode sweep carries the state over from the previous value.  Writes NPZ or CSV data, optionally the
figure with the Lyapunov exponents below it (--lyapunov)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..cliutil import (
    MAX_AVERAGED,
    MAX_IMPACTS,
    MAX_VALUES,
    CliError,
    add_output_options,
    add_param_args,
    add_renamed,
    check_outputs,
    check_scan,
    nonneg_int,
    params_from,
    positive_int,
    progress_arg,
    real,
    add_start_args,
    check_start_args,
    write_result,
    write_plot,
)
from ..paper import SCAN_OF

if TYPE_CHECKING:
    from ..dynamics.bifurcation import Diagram, DiagramLyapunov

NAME = "bifurcation"
#: Most recorded points of a diagram (values x keep), ~1.6 GB of float64 with the phases.
MAX_RECORDED = 100_000_000
#: Most impacts recorded per value.
MAX_KEEP = 100_000


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("--param", choices=("r", "alpha"), default="r", help="parameter varied (default r)")
    p.add_argument(
        "--lo",
        type=real("--lo"),
        default=None,
        help="lowest value, in the parameter's range: 0 < r <= 1, 0 <= alpha <= 1e10 (default: Fig. 4's "
        f"{SCAN_OF['r'].lo} for r, Fig. 8's {SCAN_OF['alpha'].lo} for alpha)",
    )
    p.add_argument(
        "--hi",
        type=real("--hi"),
        default=None,
        help=f"highest value, in the parameter's range, >= --lo (default {SCAN_OF['r'].hi} for r, "
        f"{SCAN_OF['alpha'].hi} for alpha)",
    )
    p.add_argument(
        "--values",
        type=positive_int("--values", MAX_VALUES),
        default=200,
        help=f"number of parameter values, 1 to {MAX_VALUES} (default 200)",
    )
    p.add_argument(
        "--transient",
        type=nonneg_int("--transient", MAX_IMPACTS),
        default=1000,
        help=f"impacts discarded first, 0 to {MAX_IMPACTS} (default 1000)",
    )
    p.add_argument(
        "--impacts",
        type=positive_int("--impacts", MAX_KEEP),
        default=200,
        help=f"impacts recorded per value after --transient, 1 to {MAX_KEEP} (default 200)",
    )
    add_renamed(p, "--keep", "--impacts", type=positive_int("--keep", MAX_KEEP))
    p.add_argument(
        "--mode", choices=("fixed", "sweep"), default="fixed", help="fixed initial condition or sweep (default fixed)"
    )
    p.add_argument("--reverse", action="store_true", help="sweep from hi down to lo")
    add_start_args(p)
    p.add_argument(
        "--lyapunov",
        type=nonneg_int("--lyapunov", MAX_AVERAGED),
        default=0,
        metavar="N",
        help=f"also compute Lyapunov exponents over N impacts, 0 to {MAX_AVERAGED}, figure panel b (default 0: "
        "not computed)",
    )
    add_output_options(
        p,
        output="the diagram's points (with --lyapunov, the exponents of each value too)",
        plot="write the figure (default: no figure)",
    )


def run(args: argparse.Namespace) -> int:
    from ..dynamics.bifurcation import bifurcation_diagram

    base = params_from(args)
    check_outputs(args)
    if args.values * args.impacts > MAX_RECORDED:
        raise CliError(
            f"--values x --impacts = {args.values * args.impacts} is out of range: allowed <= {MAX_RECORDED}"
        )
    check_start_args(args)
    lo, hi = check_scan(args, SCAN_OF[args.param].lo, SCAN_OF[args.param].hi)
    d = bifurcation_diagram(
        base,
        args.param,
        lo,
        hi,
        args.values,
        args.transient,
        args.impacts,
        args.mode,
        args.tau0,
        args.sdot0,
        args.reverse,
        progress=progress_arg(args),
    )
    lyap: tuple | None = None
    result: Diagram | DiagramLyapunov = d
    if args.lyapunov:
        from ...mapimpl.lyapunov import lyapunov
        from ..dynamics.bifurcation import DiagramLyapunov

        res = lyapunov(
            base,
            args.param,
            d.values,
            n_impacts=args.lyapunov,
            transient=args.transient,
            tau0=args.tau0,
            sdot0=args.sdot0,
            progress=progress_arg(args),
        )
        lyap, result = (res.values, res.lam_free), DiagramLyapunov(d, res)  # --output carries the exponents
    write_result(args, result)
    if args.plot:
        from ..plots import diagram_figure

        write_plot(args, diagram_figure(d, lyap))
    return 0


__all__ = [
    "NAME",
    "MAX_RECORDED",
    "MAX_KEEP",
    "add_arguments",
    "run",
]
