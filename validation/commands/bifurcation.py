"""Bifurcation diagram of the impact map: sdot_n against r (Fig. 4a, alpha = 3) or alpha (Fig. 8a,
r = 0.9), transients discarded.  --mode fixed starts every value from the same initial condition;
--mode sweep carries the state over from the previous value.  Writes NPZ or CSV data, optionally the
figure with the Lyapunov exponents below it (--lyapunov)."""

from __future__ import annotations

import argparse

from ..cliutil import (MAX_AVERAGED, MAX_IMPACTS, MAX_VALUES, CliError, add_output_options, add_param_args,
                       check_outputs, nonneg_int, params_from, positive_int, real, tau0_type, write_output, write_plot)

NAME = "bifurcation"
HELP = "bifurcation diagram in r (Fig. 4a) or alpha (Fig. 8a), NPZ/CSV and figure"
#: Most recorded points of a diagram (values x keep), ~1.6 GB of float64 with the phases.
MAX_RECORDED = 100_000_000


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("--param", choices=("r", "alpha"), default="r", help="parameter varied (default r)")
    p.add_argument("--lo", type=real("--lo"), default=None, help="lowest value (default 0.7 for r, 1.1 for alpha)")
    p.add_argument("--hi", type=real("--hi"), default=None, help="highest value (default 0.95 for r, 1.4 for alpha)")
    p.add_argument("--values", type=positive_int("--values", MAX_VALUES), default=200,
                   help=f"number of parameter values, at most {MAX_VALUES} (default 200)")
    p.add_argument("--transient", type=nonneg_int("--transient", MAX_IMPACTS), default=1000,
                   help="impacts discarded (default 1000)")
    p.add_argument("--keep", type=positive_int("--keep", 100_000), default=200,
                   help="impacts recorded per value, at most 100000 (default 200)")
    p.add_argument("--mode", choices=("fixed", "sweep"), default="fixed",
                   help="fixed initial condition or sweep (default fixed)")
    p.add_argument("--reverse", action="store_true", help="sweep from hi down to lo")
    p.add_argument("--tau0", type=tau0_type(), default=0.0, help="initial time, |tau0| <= 1e6 (default 0.0)")
    p.add_argument("--sdot0", type=real("--sdot0"), default=0.5, help="initial velocity, nonzero (default 0.5)")
    p.add_argument("--lyapunov", type=nonneg_int("--lyapunov", MAX_AVERAGED), default=0, metavar="N",
                   help="also compute Lyapunov exponents over N impacts, figure panel b (default 0: not computed)")
    add_output_options(p, output="data file: .npz or .csv (default: CSV on stdout)",
                       plot="write the figure (default: no figure)", quiet="no progress bar")


def run(args: argparse.Namespace) -> int:
    from ..dynamics.bifurcation import bifurcation_diagram
    from ...mapimpl.progress import Progress

    base = params_from(args)
    check_outputs(args)
    if args.values * args.keep > MAX_RECORDED:
        raise CliError(f"--values x --keep = {args.values * args.keep} is out of range: allowed <= {MAX_RECORDED}")
    if args.sdot0 == 0:
        raise CliError("--sdot0=0 is out of range: allowed nonzero (a pre-impact velocity; > 0 hits s = 0)")
    lo = args.lo if args.lo is not None else (0.7 if args.param == "r" else 1.1)
    hi = args.hi if args.hi is not None else (0.95 if args.param == "r" else 1.4)
    if not lo <= hi:
        raise CliError(f"--lo={lo!r}, --hi={hi!r} are out of range: allowed lo <= hi")
    d = bifurcation_diagram(base, args.param, lo, hi, args.values, args.transient, args.keep, args.mode,
                            args.tau0, args.sdot0, args.reverse, progress=Progress("bifurcation", not args.quiet))
    lyap = None
    if args.lyapunov:
        from ...mapimpl.lyapunov import lyapunov

        res = lyapunov(base, args.param, d.values, n=args.lyapunov, transient=args.transient, tau0=args.tau0,
                       sdot0=args.sdot0, progress=Progress("lyapunov", not args.quiet))
        lyap = (res.values, res.lam_free)
    write_output(args, d)
    if args.plot:
        from ..plots import diagram_figure

        write_plot(args, diagram_figure(d, lyap))
    return 0
