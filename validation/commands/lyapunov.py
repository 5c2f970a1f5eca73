"""Lyapunov exponents of the 2-D impact map (Figs. 4b, 8b) by QR re-orthonormalisation of the Jacobian
products, with the check lambda1 + lambda2 = mean ln|det J| (closed form, telescoped).  Sticking
steps (J = 0) make the exponents -inf; they are counted and the exponents of the free steps are given
too.  Writes CSV (or NPZ) and optionally a figure."""

from __future__ import annotations

import argparse

import numpy as np

from ..cliutil import add_param_args, check_writable, nonneg_int, params_from, positive_int, write_text

NAME = "lyapunov"
HELP = "Lyapunov exponents against r or alpha (Figs. 4b, 8b), QR method"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("--param", choices=("r", "alpha"), default="r")
    p.add_argument("--lo", type=float, default=None, help="lowest value (default: the --r or --alpha value)")
    p.add_argument("--hi", type=float, default=None, help="highest value (default: --lo)")
    p.add_argument("--values", type=positive_int("--values"), default=1)
    p.add_argument("--impacts", type=positive_int("--impacts"), default=20000, help="impacts averaged")
    p.add_argument("--transient", type=nonneg_int("--transient"), default=1000)
    p.add_argument("--tau0", type=float, default=0.0)
    p.add_argument("--sdot0", type=float, default=0.5)
    p.add_argument("--output", default=None, help=".npz or .csv (default: CSV on stdout)")
    p.add_argument("--plot", default=None, metavar="FILE.png")
    p.add_argument("--quiet", action="store_true")


def run(args: argparse.Namespace) -> int:
    from ..dynamics.lyapunov import lyapunov
    from ...mapimpl.progress import Progress

    base = params_from(args)
    check_writable(args.output, "--output")
    check_writable(args.plot, "--plot")
    lo = args.lo if args.lo is not None else getattr(base, args.param)
    hi = args.hi if args.hi is not None else lo
    if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi):
        raise ValueError(f"--lo={lo!r}, --hi={hi!r} are out of range: allowed finite lo <= hi")
    values = np.linspace(lo, hi, args.values)
    res = lyapunov(base, args.param, values, n=args.impacts, transient=args.transient, tau0=args.tau0,
                   sdot0=args.sdot0, progress=Progress("lyapunov", not args.quiet))
    if args.output and args.output.endswith(".npz"):
        res.save_npz(args.output)
    else:
        write_text(res.to_csv(), args.output)
    if args.plot:
        from ..figures import subplots

        fig, ax = subplots(figsize=(7, 3.5))
        ax.plot(values, res.lam_free[:, 0], "-", label=r"$\lambda_1$")
        ax.plot(values, res.lam_free[:, 1], "-", label=r"$\lambda_2$")
        ax.axhline(0, color="gray", lw=0.5)
        ax.set_xlabel(args.param); ax.set_ylabel("per impact"); ax.legend()
        fig.tight_layout(); fig.savefig(args.plot, dpi=150);    return 0
