"""Periodic orbits: find a p-impact, m-turn periodic orbit by Newton (with its Floquet multipliers),
continue it in r or alpha by pseudo-arclength continuation, and print the fold (multiplier +1) and
flip (multiplier -1) points located by Newton on the extended system.

Without --tau0/--sdot0 the guess is the end of a long run (--settle impacts) from (0, 0.5).
'find' writes the orbit's points (CSV), or all of it (JSON, NPZ); 'continue' the branch.  What is
said about them (convergence, multipliers, folds and flips) goes to stderr."""

from __future__ import annotations

import argparse

import numpy as np

from ..cliutil import (
    MAX_IMPACTS,
    MAX_VALUES,
    CliError,
    CommandFailed,
    add_output_options,
    add_param_args,
    add_renamed,
    check_outputs,
    check_scan,
    int_range,
    note,
    params_from,
    positive_int,
    real,
    add_start_args,
    check_start_args,
    write_result,
    write_plot,
)

NAME = "orbit"
#: Most impacts (and turns) per periodic orbit.
MAX_PERIOD = 1000
#: The options of 'continue' only, with their defaults (None: from the orbit's parameter value).
CONTINUATION = {"param": "r", "lo": None, "hi": None, "direction": 1, "ds": 2e-3, "max_points": 200}


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument(
        "action",
        choices=("find", "continue"),
        metavar="{find,continue}",
        help="find: one orbit by Newton; continue: its branch in --param",
    )
    p.add_argument(
        "--period",
        type=positive_int("--period", MAX_PERIOD),
        default=6,
        help=f"p: impacts per orbit, 1 to {MAX_PERIOD} (default 6)",
    )
    add_renamed(p, "--impacts", "--period", type=positive_int("--impacts", MAX_PERIOD))
    p.add_argument(
        "--turns",
        type=positive_int("--turns", MAX_PERIOD),
        default=1,
        help=f"m: driving periods per orbit, 1 to {MAX_PERIOD} (default 1)",
    )
    add_start_args(p, None, what="guess: a point of the orbit's", none="from a --settle run")
    p.add_argument(
        "--settle",
        type=positive_int("--settle", MAX_IMPACTS),
        default=5000,
        help=f"impacts of the guess run from (0, 0.5), 1 to {MAX_IMPACTS} (default 5000)",
    )
    c = p.add_argument_group("continue only")
    c.add_argument("--param", choices=("r", "alpha"), default=None, help="continuation parameter (default r)")
    c.add_argument(
        "--lo",
        type=real("--lo"),
        default=None,
        help="lower bound of the continuation parameter, in its range (0 < r <= 1, 0 <= alpha <= 1e10), <= "
        "its value (default: its value - 0.1, at least 0 for alpha and half the value for r)",
    )
    c.add_argument(
        "--hi",
        type=real("--hi"),
        default=None,
        help="upper bound of the continuation parameter, in its range, >= its value (default: its value + "
        "0.1, at most 1 for r)",
    )
    c.add_argument("--direction", type=int, choices=(1, -1), default=None, help="initial sense, 1 or -1 (default 1)")
    c.add_argument(
        "--ds",
        type=real("--ds", lo=0.0, lo_open=True, hi=1.0),
        default=None,
        help="initial arclength step, 0 < ds <= 1 (default 0.002)",
    )
    c.add_argument(
        "--max-points",
        type=int_range("--max-points", 2, MAX_VALUES),
        default=None,
        help=f"most points of the branch, 2 to {MAX_VALUES} (default 200)",
    )
    add_output_options(
        p, output="the orbit's points or the branch", plot="branch figure, sdot and |multipliers| (default: no figure)"
    )


def _check(args: argparse.Namespace, base) -> tuple[float, float] | None:
    """Every option checked before computing; the continuation bounds ``(lo, hi)`` for 'continue'."""
    given = [k for k in CONTINUATION if getattr(args, k) is not None]
    if args.action == "find":
        if given or args.plot:
            opts = ", ".join("--" + k.replace("_", "-") for k in given + (["plot"] if args.plot else []))
            raise CliError(f"{opts}: allowed with 'continue' only ('find' computes one orbit)")
        return None
    for k, v in CONTINUATION.items():
        if getattr(args, k) is None:
            setattr(args, k, v)
    mu = getattr(base, args.param)
    if args.param == "r":  # defaults within the range (r = 0.05 had the default --lo=-0.05 refused)
        default_lo, default_hi = (mu - 0.1 if mu > 0.2 else mu / 2), min(mu + 0.1, 1.0)
    else:
        default_lo, default_hi = max(mu - 0.1, 0.0), mu + 0.1
    lo, hi = check_scan(args, default_lo, default_hi, strict=True)
    if not lo <= mu <= hi:
        raise CliError(f"--lo={lo!r}, --hi={hi!r}: allowed bounds around the starting --{args.param}={mu!r}")
    return lo, hi


def run(args: argparse.Namespace) -> int:
    from ..dynamics.crises import attractor_point

    base = params_from(args)
    check_outputs(args)
    bounds = _check(args, base)
    check_start_args(args)
    if args.tau0 is None:
        tau0, sdot0 = attractor_point(base, args.settle)
    else:
        tau0, sdot0 = args.tau0, args.sdot0
    if args.action == "find":
        return _find(args, base, tau0, sdot0)
    assert bounds is not None, "_check gives the bounds of 'continue'"
    return _continue(args, base, tau0, sdot0, bounds)


def _converged(args, base, tau0: float, sdot0: float):
    """The periodic orbit through the guess, or :class:`CommandFailed` (one line, exit 1)."""
    from ...mapimpl.periodic import find_periodic

    o = find_periodic(base, tau0, sdot0, args.period, args.turns)
    if not o.converged:
        where = "--tau0/--sdot0" if args.tau0 is not None else f"the end of a --settle={args.settle} run"
        raise CommandFailed(
            f"Newton did not converge (residual {o.residual:.2e} after {o.iterations} iterations): no "
            f"{args.period}-impact, {args.turns}-turn orbit near the guess ({tau0!r}, {sdot0!r}) from "
            f"{where}; try another guess, --period or parameters"
        )
    return o


def _find(args, base, tau0: float, sdot0: float) -> int:
    from ...mapimpl.continuation import closed_form_det

    o = _converged(args, base, tau0, sdot0)
    write_result(args, o)
    note(
        f"converged (residual {o.residual:.2e}, {o.iterations} iterations); multipliers "
        + ", ".join(f"{complex(m):.12g}" for m in o.multipliers)
        + f"; stable: {o.stable}"
    )
    note(
        f"product of multipliers {np.prod(o.multipliers).real:.12g}; closed form r^(2p) exp(-2 pi m beta) "
        f"{closed_form_det(base, args.period, args.turns):.12g}"
    )
    return 0


def _continue(args, base, tau0: float, sdot0: float, bounds: tuple[float, float]) -> int:
    from ...mapimpl.continuation import continue_orbit

    _converged(args, base, tau0, sdot0)  # the start, before the branch (a failure is exit 1, not a usage error)
    br = continue_orbit(
        base,
        args.param,
        tau0,
        sdot0,
        args.period,
        args.turns,
        mu_range=bounds,
        direction=args.direction,
        ds=args.ds,
        ds_max=max(2e-2, args.ds),
        max_points=args.max_points,
    )
    write_result(
        args,
        table=br.table,
        arrays=lambda: {
            **br.arrays(),
            "param": args.param,
            "folds": np.array([f.mu for f in br.folds]),
            "flips": np.array([f.mu for f in br.flips]),
        },
    )
    note(f"branch: {len(br.points)} points, stop: {br.stop_reason}")
    for f in br.folds + br.flips:
        note(f.describe())
    if args.plot:
        from ..plots import branch_figure

        write_plot(args, branch_figure(br, args.param))
    return 0


__all__ = [
    "NAME",
    "MAX_PERIOD",
    "CONTINUATION",
    "add_arguments",
    "run",
]
