"""Fig. 10 of the paper: fraction f(eps) of eps-uncertain initial conditions and the uncertainty
exponent, for transient durations n = 500 and 1000 (alpha = 1.245).

Random points A in 3.0 < tau0 < 3.5, 0 < sdot0 < 0.5 (--seed); A is eps-uncertain when
B = (tau0 + eps, sdot0) or C = (tau0 - eps, sdot0) lies in the other transient basin
(duration < n vs >= n).  Fits f ~ eps^phi with least-squares and bootstrap errors.
Writes uncertainty.npz, uncertainty.csv, uncertainty.json and fig10_uncertainty.png.  The paper's
exponents are shown beside ours only at the paper's parameters (elsewhere the output says that no
comparison is made).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..cliutil import MAX_IMPACTS, CliError, int_range, positive_int, progress_arg, real, seed_int
from .transient_common import add_common, check_common, execution_of, print_summary

NAME = "uncertainty"
#: Most random points (each costs 1 + 2 x n-eps orbits).
MAX_POINTS = 1_000_000


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_common(p)
    p.add_argument(
        "--points",
        type=int_range("--points", 10, MAX_POINTS),
        default=None,
        help=f"random points, 10 to {MAX_POINTS} (default: quick 300, paper 3000)",
    )
    p.add_argument(
        "--eps-min",
        type=real("--eps-min", lo=0.0, lo_open=True, hi=0.1),
        default=1e-9,
        help="smallest eps, 0 < eps-min < eps-max (default 1e-09)",
    )
    p.add_argument(
        "--eps-max",
        type=real("--eps-max", lo=0.0, lo_open=True, hi=0.1),
        default=1e-3,
        help="largest eps, eps-min < eps-max <= 0.1 (default 0.001)",
    )
    p.add_argument(
        "--n-eps",
        type=int_range("--n-eps", 3, 100),
        default=None,
        help="eps values, log-spaced, 3 to 100 (default: quick 7, paper 13)",
    )
    p.add_argument(
        "--ns",
        type=positive_int("--ns", MAX_IMPACTS),
        nargs="+",
        default=[500, 1000],
        help=f"durations n, each 1 to {MAX_IMPACTS} (default 500 1000)",
    )
    p.add_argument("--seed", type=seed_int(), default=0, help="random seed of the points, 0 to 2**32-1 (default 0)")


def run(args: argparse.Namespace) -> int:
    from ..cliutil import params_from
    from ..io import save_figure
    from ..io.transients import write_uncertainty
    from ..plots.transients import uncertainty_figure
    from ..transient.experiments import uncertainty
    from ..transient.settings import UncertaintySettings, default_eps

    params = params_from(args)
    if not args.eps_min < args.eps_max:
        raise CliError(
            f"--eps-min={args.eps_min!r}, --eps-max={args.eps_max!r} are out of range: "
            "allowed 0 < eps-min < eps-max <= 0.1"
        )
    check_common(args)
    eps = default_eps(args.profile, args.n_eps, args.eps_min, args.eps_max)
    settings = UncertaintySettings.of_profile(
        args.profile, n_points=args.points, eps=eps, ns=tuple(args.ns), seed=args.seed, delta=args.delta
    )
    res = uncertainty(params=params, settings=settings, execution=execution_of(args), progress=progress_arg(args))
    files = write_uncertainty(args.out, res)
    fig = Path(args.out) / "fig10_uncertainty.png"
    save_figure(uncertainty_figure(res), fig)
    print_summary(res.summary(), getattr(res, "notes", ()), [*files, fig])
    return 0


__all__ = [
    "NAME",
    "MAX_POINTS",
    "add_arguments",
    "run",
]
