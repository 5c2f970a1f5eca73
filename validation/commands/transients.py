"""Fig. 11 of the paper: statistics of transient durations after the crisis (alpha = 1.245).

A mesh of initial conditions (pre-impact states at s = 0, or free-flight states with --s0) over the
box 3.0 < tau0 < 3.5, 0 < sdot0 < 0.5 is iterated until each orbit comes within --delta of the
stable 4-impact period-1 orbit (found by Newton) or --cap iterations.  Writes transients.npz,
survival.csv, transients.json and fig11_survival.png; fits N(n) = N0 exp(-kappa n/<n>) (Eq. 14).
"""

from __future__ import annotations

import argparse

from ..cliutil import positive_int
from ._transient_common import add_common, print_summary

NAME = "transients"
HELP = "Fig. 11: survival N(n) of transients and the Eq. (14) fit"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_common(p)
    p.add_argument("--n", type=positive_int("--n"), default=None, help="mesh size n x n (quick 60, paper 400)")
    p.add_argument("--cap", type=positive_int("--cap"), default=None, help="most iterations per orbit (default 20000)")
    p.add_argument("--s0", type=float, default=None,
                   help="read (tau0, sdot0) as a free-flight state at s = s0 (-1 <= s0 <= 0) instead of pre-impact")
    p.add_argument("--n-lo", type=int, default=None, help="start of the fit range (default: median duration)")
    p.add_argument("--seed", type=int, default=0, help="bootstrap seed (default 0)")


def run(args: argparse.Namespace) -> int:
    from ..cliutil import params_from
    from ..transient.experiments import transients

    params = params_from(args)
    s = transients(outdir=args.outdir, profile=args.profile, nx=args.n, cap=args.cap, delta=args.delta,
                   deltas=(1e-2, args.delta, 1e-4, 1e-6), params=params,
                   ic_mode="pre-impact" if args.s0 is None else "free", s0=args.s0, n_lo=args.n_lo, seed=args.seed,
                   progress=False if args.no_progress else None, lanes=args.lanes)
    print_summary(s)
    return 0
