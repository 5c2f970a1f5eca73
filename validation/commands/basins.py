"""Fig. 9 of the paper: transient basins for n = 90, 500, 1000, 2000 (alpha = 1.245).

Durations are computed once on a mesh over --window (default 0 < tau0 < 2 pi, 0 < sdot0 < 0.5,
which contains the box of Figs. 10-11) and thresholded four times: black = duration < n.
Writes basins.npz, basins.json and fig9_basins.png.  The paper prints no number for Fig. 9; away from
the paper's parameters basins.json, the terminal and the title say that no comparison is made.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..cliutil import MAX_IMPACTS, MAX_MESH, CliError, positive_int, progress_arg, real
from .transient_common import add_common, check_common, execution_of, print_summary

NAME = "basins"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..profiles import get_profile

    add_common(p)
    q, pp = (get_profile(k, "basins") for k in ("quick", "paper"))
    p.add_argument(
        "--nx",
        type=positive_int("--nx", MAX_MESH),
        default=None,
        help=f"mesh points in tau0, 1 to {MAX_MESH} (default: quick {q['nx']}, paper {pp['nx']})",
    )
    p.add_argument(
        "--ny",
        type=positive_int("--ny", MAX_MESH),
        default=None,
        help=f"mesh points in sdot0, 1 to {MAX_MESH} (default: quick {q['ny']}, paper {pp['ny']}; with --nx "
        "the profile's ratio ny/nx times --nx)",
    )
    p.add_argument(
        "--window",
        type=real("--window"),
        nargs=4,
        default=[0.0, 2 * math.pi, 0.0, 0.5],
        metavar=("TAU_LO", "TAU_HI", "SDOT_LO", "SDOT_HI"),
        help="mesh window, TAU_LO < TAU_HI within |tau| <= 1e6 and SDOT_LO < SDOT_HI (default 0 2pi 0 0.5)",
    )
    p.add_argument(
        "--ns",
        type=positive_int("--ns", MAX_IMPACTS),
        nargs="+",
        default=[90, 500, 1000, 2000],
        help=f"thresholds n, each 1 to {MAX_IMPACTS} (default 90 500 1000 2000)",
    )


def run(args: argparse.Namespace) -> int:
    from ...core.checks import TAU0_MAX, TAU0_RANGE
    from ..cliutil import params_from
    from ..io import save_figure
    from ..io.transients import write_basins
    from ..plots.transients import basins_figure
    from ..transient.experiments import basins
    from ..transient.settings import BasinsSettings

    params = params_from(args)
    t_lo, t_hi, s_lo, s_hi = args.window
    if not (t_lo < t_hi and s_lo < s_hi and max(abs(t_lo), abs(t_hi)) <= TAU0_MAX):
        raise CliError(
            f"--window={' '.join(map(repr, args.window))} is out of range: allowed TAU_LO < TAU_HI "
            f"({TAU0_RANGE.replace('tau0', 'tau')}) and SDOT_LO < SDOT_HI"
        )
    check_common(args)
    settings = BasinsSettings.of_profile(
        args.profile, nx=args.nx, ny=args.ny, window=tuple(args.window), ns=tuple(args.ns), delta=args.delta
    )
    res = basins(params=params, settings=settings, execution=execution_of(args), progress=progress_arg(args))
    files = write_basins(args.out, res)
    fig = Path(args.out) / "fig9_basins.png"
    save_figure(basins_figure(res), fig)
    print_summary(res.summary(), getattr(res, "notes", ()), [*files, fig])
    return 0


__all__ = [
    "NAME",
    "add_arguments",
    "run",
]
