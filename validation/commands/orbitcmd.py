"""Periodic orbits: find a p-impact, m-turn periodic orbit by Newton (with its Floquet multipliers),
continue it in r or alpha by pseudo-arclength continuation, and print the fold (multiplier +1) and
flip (multiplier -1) points located by Newton on the extended system.

Without --tau0/--sdot0 the guess is the end of a long run (--settle impacts) from (0, 0.5)."""

from __future__ import annotations

import argparse

import numpy as np

from ..cliutil import (MAX_IMPACTS, MAX_VALUES, CliError, add_output_options, add_param_args, check_outputs,
                       int_range, params_from, positive_int, real, tau0_type, write_output, write_plot, write_text)

NAME = "orbit"
#: Most impacts (and turns) per periodic orbit.
MAX_PERIOD = 1000
HELP = "periodic orbits: find, continue in r or alpha, fold and flip points"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_param_args(p)
    p.add_argument("action", choices=("find", "continue"), help="find one orbit, or continue it")
    p.add_argument("--impacts", type=positive_int("--impacts", MAX_PERIOD), default=6,
                   help=f"impacts per orbit, at most {MAX_PERIOD} (default 6)")
    p.add_argument("--turns", type=positive_int("--turns", MAX_PERIOD), default=1,
                   help=f"driving periods per orbit, at most {MAX_PERIOD} (default 1)")
    p.add_argument("--tau0", type=tau0_type(), default=None,
                   help="guess: time of a point of the orbit, |tau0| <= 1e6 (default: from a --settle run)")
    p.add_argument("--sdot0", type=real("--sdot0"), default=None,
                   help="guess: its pre-impact velocity, nonzero (default: from a --settle run)")
    p.add_argument("--settle", type=positive_int("--settle", MAX_IMPACTS), default=5000,
                   help="impacts of the guess run from (0, 0.5) (default 5000)")
    p.add_argument("--param", choices=("r", "alpha"), default="r", help="continuation parameter (default r)")
    p.add_argument("--lo", type=real("--lo"), default=None,
                   help="lower bound of the continuation parameter (default: its value - 0.1)")
    p.add_argument("--hi", type=real("--hi"), default=None,
                   help="upper bound of the continuation parameter (default: its value + 0.1, at most 1 for r)")
    p.add_argument("--direction", type=int, choices=(1, -1), default=1, help="initial sense, +1 or -1 (default 1)")
    p.add_argument("--ds", type=real("--ds", lo=0.0, lo_open=True, hi=1.0), default=2e-3,
                   help="initial arclength step, 0 < ds <= 1 (default 0.002)")
    p.add_argument("--max-points", type=int_range("--max-points", 2, MAX_VALUES), default=200,
                   help=f"most points of the branch, 2 to {MAX_VALUES} (default 200)")
    add_output_options(p, output="orbit or branch data: .npz or .csv (default: CSV on stdout)",
                       plot="branch figure, sdot and |multipliers| (default: no figure)", quiet="no progress bar")


def run(args: argparse.Namespace) -> int:
    import sys

    from ...mapimpl.periodic import find_periodic
    from ..dynamics.continuation import closed_form_det, continue_orbit
    from ..dynamics.crises import attractor_point
    from ...mapimpl.progress import Progress

    base = params_from(args)
    check_outputs(args)
    if args.plot and args.action == "find":
        raise CliError("--plot draws a continued branch: allowed with 'continue' only")
    if (args.tau0 is None) != (args.sdot0 is None):
        raise CliError("--tau0 and --sdot0 must be given together")
    if args.sdot0 == 0:
        raise CliError("--sdot0=0 is out of range: allowed nonzero (a pre-impact velocity; > 0 hits s = 0)")
    if args.lo is not None and args.hi is not None and not args.lo < args.hi:
        raise CliError(f"--lo={args.lo!r}, --hi={args.hi!r} are out of range: allowed lo < hi")
    if args.tau0 is None:
        tau0, sdot0 = attractor_point(base, args.settle)
    else:
        tau0, sdot0 = args.tau0, args.sdot0
    if args.action == "find":
        o = find_periodic(base, tau0, sdot0, args.impacts, args.turns)
        lines = [f"converged: {o.converged} (residual {o.residual:.2e}, {o.iterations} iterations)",
                 "k,tau_mod_2pi,sdot,wall"]
        lines += [f"{k},{float(t)!r},{float(s)!r},{int(w)}" for k, (t, s, w) in enumerate(zip(o.tau, o.sdot, o.walls))]
        lines.append("multipliers: " + ", ".join(f"{complex(m):.12g}" for m in o.multipliers))
        lines.append(f"product of multipliers: {np.prod(o.multipliers).real:.12g}; closed form r^(2p) exp(-2 pi m beta): "
                     f"{closed_form_det(base, args.impacts, args.turns):.12g}; stable: {o.stable}")
        write_text("\n".join(lines) + "\n", args.output)
        return 0 if o.converged else 1
    lo = args.lo if args.lo is not None else getattr(base, args.param) - 0.1
    hi = args.hi if args.hi is not None else min(getattr(base, args.param) + 0.1, 1.0) if args.param == "r" else getattr(base, args.param) + 0.1
    prog = Progress("continuation", not args.quiet)
    br = continue_orbit(base, args.param, tau0, sdot0, args.impacts, args.turns, mu_range=(lo, hi),
                        direction=args.direction, ds=args.ds, ds_max=max(2e-2, args.ds), max_points=args.max_points,
                        progress=prog)
    write_output(args, table=br.table, arrays=lambda: {
        **br.arrays(), "param": args.param, "folds": np.array([f.mu for f in br.folds]),
        "flips": np.array([f.mu for f in br.flips])})
    out = sys.stderr if args.output in (None, "-") else sys.stdout
    print(f"branch: {len(br.points)} points, stop: {br.stop_reason}", file=out)
    for f in br.folds + br.flips:
        print(f.describe(), file=out)
    if args.plot:
        from ..plots import branch_figure

        write_plot(args, branch_figure(br, args.param))
    return 0
