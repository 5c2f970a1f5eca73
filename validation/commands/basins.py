"""Fig. 9 of the paper: transient basins for n = 90, 500, 1000, 2000 (alpha = 1.245).

Durations are computed once on a mesh over --window (default 0 < tau0 < 2 pi, 0 < sdot0 < 0.5,
which contains the box of Figs. 10-11) and thresholded four times: black = duration < n.
Writes basins.npz, basins.json and fig9_basins.png.
"""

from __future__ import annotations

import argparse
import math

from ..cliutil import positive_int
from ._transient_common import add_common, print_summary

NAME = "basins"
HELP = "Fig. 9: transient basins for n = 90, 500, 1000, 2000"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_common(p)
    p.add_argument("--nx", type=positive_int("--nx"), default=None, help="mesh points in tau0 (quick 120, paper 400)")
    p.add_argument("--ny", type=positive_int("--ny"), default=None, help="mesh points in sdot0 (quick 60, paper 400)")
    p.add_argument("--window", type=float, nargs=4, default=[0.0, 2 * math.pi, 0.0, 0.5],
                   metavar=("TAU_LO", "TAU_HI", "SDOT_LO", "SDOT_HI"), help="mesh window (default 0 2pi 0 0.5)")
    p.add_argument("--ns", type=int, nargs="+", default=[90, 500, 1000, 2000], help="thresholds n (default 90 500 1000 2000)")


def run(args: argparse.Namespace) -> int:
    from ..cliutil import params_from
    from ..transient.experiments import basins

    s = basins(outdir=args.outdir, profile=args.profile, nx=args.nx, ny=args.ny, window=tuple(args.window),
               ns=tuple(args.ns), delta=args.delta, params=params_from(args),
               progress=False if args.no_progress else None, lanes=args.lanes)
    print_summary(s)
    return 0
