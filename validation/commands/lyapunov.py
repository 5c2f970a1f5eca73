"""Lyapunov exponents of the 2-D impact map (Figs. 4b, 8b) by QR re-orthonormalisation of the Jacobian
products, with the check lambda1 + lambda2 = mean ln|det J| (closed form, telescoped).  Sticking
steps (J = 0) make the exponents -inf; they are counted and the exponents of the free steps are given
too.  Writes CSV (or NPZ) and optionally a figure."""

from __future__ import annotations

import argparse

import numpy as np

from ..cliutil import (MAX_AVERAGED, MAX_VALUES, CliError, add_output_options, add_param_args, check_outputs,
                       nonneg_int, params_from, positive_int, real, tau0_type, write_output, write_plot)

NAME = "lyapunov"
HELP = "Lyapunov exponents against r or alpha (Figs. 4b, 8b), QR method"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("--param", choices=("r", "alpha"), default="r", help="parameter varied (default r)")
    p.add_argument("--lo", type=real("--lo"), default=None, help="lowest value (default: the --r or --alpha value)")
    p.add_argument("--hi", type=real("--hi"), default=None, help="highest value (default: --lo)")
    p.add_argument("--values", type=positive_int("--values", MAX_VALUES), default=1,
                   help=f"number of parameter values, at most {MAX_VALUES} (default 1)")
    p.add_argument("--impacts", type=positive_int("--impacts", MAX_AVERAGED), default=20000,
                   help=f"impacts averaged, at most {MAX_AVERAGED} (default 20000)")
    p.add_argument("--transient", type=nonneg_int("--transient", MAX_AVERAGED), default=1000,
                   help="impacts discarded first (default 1000)")
    p.add_argument("--tau0", type=tau0_type(), default=0.0, help="initial time, |tau0| <= 1e6 (default 0.0)")
    p.add_argument("--sdot0", type=real("--sdot0"), default=0.5, help="initial velocity, nonzero (default 0.5)")
    add_output_options(p, output=".npz or .csv (default: CSV on stdout)", plot="write the figure (default: no figure)",
                       quiet="no progress bar")


def run(args: argparse.Namespace) -> int:
    from ...mapimpl.lyapunov import lyapunov
    from ...mapimpl.progress import Progress

    base = params_from(args)
    check_outputs(args)
    if args.sdot0 == 0:
        raise CliError("--sdot0=0 is out of range: allowed nonzero (a pre-impact velocity; > 0 hits s = 0)")
    lo = args.lo if args.lo is not None else getattr(base, args.param)
    hi = args.hi if args.hi is not None else lo
    if not lo <= hi:
        raise CliError(f"--lo={lo!r}, --hi={hi!r} are out of range: allowed lo <= hi")
    values = np.linspace(lo, hi, args.values)
    res = lyapunov(base, args.param, values, n=args.impacts, transient=args.transient, tau0=args.tau0,
                   sdot0=args.sdot0, progress=Progress("lyapunov", not args.quiet))
    fig = None
    if args.plot:  # drawn before anything is written
        from ..plots import lyapunov_figure

        fig = lyapunov_figure(values, res.lam_free, args.param)
    write_output(args, res)
    write_plot(args, fig)
    return 0
