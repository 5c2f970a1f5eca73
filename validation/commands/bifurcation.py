"""Bifurcation diagram of the impact map: sdot_n against r (Fig. 4a, alpha = 3) or alpha (Fig. 8a,
r = 0.9), transients discarded.  --mode fixed starts every value from the same initial condition;
--mode sweep carries the state over from the previous value.  Writes NPZ or CSV data, optionally the
figure with the Lyapunov exponents below it (--lyapunov)."""

from __future__ import annotations

import argparse

from ..cliutil import add_param_args, check_writable, nonneg_int, params_from, positive_int, write_text

NAME = "bifurcation"
HELP = "bifurcation diagram in r (Fig. 4a) or alpha (Fig. 8a), NPZ/CSV and figure"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("--param", choices=("r", "alpha"), default="r", help="parameter varied (default r)")
    p.add_argument("--lo", type=float, default=None, help="lowest value (default 0.7 for r, 1.1 for alpha)")
    p.add_argument("--hi", type=float, default=None, help="highest value (default 0.95 for r, 1.4 for alpha)")
    p.add_argument("--values", type=positive_int("--values"), default=200, help="number of parameter values")
    p.add_argument("--transient", type=nonneg_int("--transient"), default=1000, help="impacts discarded")
    p.add_argument("--keep", type=positive_int("--keep"), default=200, help="impacts recorded per value")
    p.add_argument("--mode", choices=("fixed", "sweep"), default="fixed", help="fixed initial condition or sweep")
    p.add_argument("--reverse", action="store_true", help="sweep from hi down to lo")
    p.add_argument("--tau0", type=float, default=0.0)
    p.add_argument("--sdot0", type=float, default=0.5)
    p.add_argument("--lyapunov", type=nonneg_int("--lyapunov"), default=0, metavar="N",
                   help="also compute Lyapunov exponents over N impacts (figure panel b)")
    p.add_argument("--output", default=None, help="data file: .npz or .csv (default: CSV on stdout)")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="write the figure")
    p.add_argument("--quiet", action="store_true", help="no progress indicator")


def run(args: argparse.Namespace) -> int:
    from ..dynamics.bifurcation import bifurcation_diagram, plot_diagram
    from ...mapimpl.progress import Progress

    base = params_from(args)
    check_writable(args.output, "--output")
    check_writable(args.plot, "--plot")
    lo = args.lo if args.lo is not None else (0.7 if args.param == "r" else 1.1)
    hi = args.hi if args.hi is not None else (0.95 if args.param == "r" else 1.4)
    d = bifurcation_diagram(base, args.param, lo, hi, args.values, args.transient, args.keep, args.mode,
                            args.tau0, args.sdot0, args.reverse, progress=Progress("bifurcation", not args.quiet))
    if args.output and args.output.endswith(".npz"):
        d.save_npz(args.output)
    else:
        write_text(d.to_csv(), args.output)
    lyap = None
    if args.lyapunov:
        from ..dynamics.lyapunov import lyapunov

        res = lyapunov(base, args.param, d.values, n=args.lyapunov, transient=args.transient, tau0=args.tau0,
                       sdot0=args.sdot0, progress=Progress("lyapunov", not args.quiet))
        lyap = (res.values, res.lam_free)
    if args.plot:
        plot_diagram(d, args.plot, lyap)
    return 0
