"""Fig. 11 of the paper: statistics of transient durations after the crisis (alpha = 1.245).

A mesh of initial conditions (pre-impact states at s = 0, or free-flight states with --s0) over the
box 3.0 < tau0 < 3.5, 0 < sdot0 < 0.5 is iterated until each orbit comes within --delta of the
stable 4-impact period-1 orbit (found by Newton) or --cap iterations.  Writes transients.npz,
survival.csv, transients.json and fig11_survival.png; fits N(n) = N0 exp(-kappa n/<n>) (Eq. 14).  The
paper's <n> and kappa are shown beside ours only at the paper's parameters (elsewhere the output says
that no comparison is made).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ...core.paper import recorded_deltas
from ..cliutil import MAX_IMPACTS, MAX_MESH, add_renamed, add_s0_arg, nonneg_int, positive_int, progress_arg, seed_int
from .transient_common import add_common, check_common, execution_of, print_summary

NAME = "transients"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_common(p)
    p.add_argument(
        "--nx",
        type=positive_int("--nx", MAX_MESH),
        default=None,
        help=f"mesh points in tau0, 1 to {MAX_MESH} (default: quick 60, paper 400)",
    )
    p.add_argument(
        "--ny",
        type=positive_int("--ny", MAX_MESH),
        default=None,
        help=f"mesh points in sdot0, 1 to {MAX_MESH} (default: --nx)",
    )
    add_renamed(p, "--n", "--nx", type=positive_int("--n", MAX_MESH))
    p.add_argument(
        "--cap",
        type=positive_int("--cap", MAX_IMPACTS),
        default=None,
        help=f"most impacts per orbit, 1 to {MAX_IMPACTS} (default 20000)",
    )
    add_s0_arg(
        p, help="read (tau0, sdot0) as a free-flight state at s = s0, -1 <= s0 <= 0 (default: none, pre-impact states)"
    )
    p.add_argument(
        "--n-lo",
        type=nonneg_int("--n-lo", MAX_IMPACTS),
        default=None,
        help=f"start of the fit range in impacts, 0 to {MAX_IMPACTS} (default: the median duration)",
    )
    p.add_argument("--seed", type=seed_int(), default=0, help="bootstrap seed, 0 to 2**32-1 (default 0)")
    p.add_argument(
        "--float64-rounding",
        action="store_true",
        help="also certify T_post for the float64 roundings of the parameters and report it in "
        "transients.json beside the value used (not used for the durations; ~20 s or more)",
    )


def run(args: argparse.Namespace) -> int:
    from ..cliutil import params_from
    from ..io import save_figure
    from ..io.transients import write_survival
    from ..plots.transients import survival_figure
    from ..transient.experiments import transients
    from ..transient.settings import SurvivalSettings

    params = params_from(args)
    check_common(args)
    settings = SurvivalSettings.of_profile(
        args.profile,
        nx=args.nx,
        ny=args.ny,
        cap=args.cap,
        delta=args.delta,
        deltas=recorded_deltas(args.delta),
        ic_mode="pre-impact" if args.s0 is None else "free",
        s0=args.s0,
        n_lo=args.n_lo,
        seed=args.seed,
        float64_rounding=args.float64_rounding,
    )
    res = transients(params=params, settings=settings, execution=execution_of(args), progress=progress_arg(args))
    files = write_survival(args.out, res)
    fig = Path(args.out) / "fig11_survival.png"
    save_figure(survival_figure(res), fig)
    print_summary(res.summary(), getattr(res, "notes", ()), [*files, fig])
    return 0


__all__ = [
    "NAME",
    "add_arguments",
    "run",
]
