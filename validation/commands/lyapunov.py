"""Lyapunov exponents of the 2-D impact map (Figs. 4b, 8b) by QR re-orthonormalisation of the Jacobian
products, with the check lambda1 + lambda2 = mean ln|det J| (closed form, telescoped).  Sticking
steps (J = 0) make the exponents -inf; they are counted and the exponents of the free steps are given
too.  Writes CSV (or NPZ) and optionally a figure."""

from __future__ import annotations

import argparse

import numpy as np

from ..cliutil import (
    MAX_AVERAGED,
    MAX_VALUES,
    add_output_options,
    add_param_args,
    check_outputs,
    check_scan,
    nonneg_int,
    note,
    params_from,
    positive_int,
    progress_arg,
    real,
    add_start_args,
    check_start_args,
    write_result,
    write_plot,
)

NAME = "lyapunov"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("--param", choices=("r", "alpha"), default="r", help="parameter varied (default r)")
    p.add_argument(
        "--lo",
        type=real("--lo"),
        default=None,
        help="lowest value, in the parameter's range: 0 < r <= 1, 0 <= alpha <= 1e10 (default: the --r or "
        "--alpha value)",
    )
    p.add_argument("--hi", type=real("--hi"), default=None, help="highest value, in the range, >= --lo (default: --lo)")
    p.add_argument(
        "--values",
        type=positive_int("--values", MAX_VALUES),
        default=1,
        help=f"number of parameter values, 1 to {MAX_VALUES} (default 1)",
    )
    p.add_argument(
        "--impacts",
        type=positive_int("--impacts", MAX_AVERAGED),
        default=20000,
        help=f"impacts averaged after --transient, 1 to {MAX_AVERAGED} (default 20000)",
    )
    p.add_argument(
        "--transient",
        type=nonneg_int("--transient", MAX_AVERAGED),
        default=1000,
        help=f"impacts discarded first, 0 to {MAX_AVERAGED} (default 1000)",
    )
    add_start_args(p)
    add_output_options(p, output="the exponents", plot="write the figure (default: no figure)")


def run(args: argparse.Namespace) -> int:
    from ...mapimpl.lyapunov import lyapunov

    base = params_from(args)
    check_outputs(args)
    check_start_args(args)
    lo = args.lo if args.lo is not None else getattr(base, args.param)
    lo, hi = check_scan(args, lo, lo if args.hi is None else args.hi)
    values = np.linspace(lo, hi, args.values)
    res = lyapunov(
        base,
        args.param,
        values,
        n_impacts=args.impacts,
        transient=args.transient,
        tau0=args.tau0,
        sdot0=args.sdot0,
        progress=progress_arg(args),
    )
    fig = None
    if args.plot:  # drawn before anything is written
        from ..plots import lyapunov_figure
        from ..plots.base import params_text

        fig = lyapunov_figure(
            values,
            res.lam_free,
            args.param,
            title=f"Lyapunov exponents (free steps): {params_text(base, args.param, values)}",
        )
    write_result(args, res)
    ended = ~np.asarray(res.active)
    if ended.any():
        at = ", ".join(f"{v:g}" for v in values[ended][:5]) + (", ..." if ended.sum() > 5 else "")
        note(
            f"{int(ended.sum())} of {values.size} orbits ended before --transient + --impacts impacts (stuck forever, "
            f"no impact or the step cap) at {args.param} = {at}: their exponents are NaN (nan in CSV, null in JSON)"
        )
    write_plot(args, fig)
    return 0


__all__ = [
    "NAME",
    "add_arguments",
    "run",
]
