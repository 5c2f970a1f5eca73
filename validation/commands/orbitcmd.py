"""Periodic orbits: find a p-impact, m-turn periodic orbit by Newton (with its Floquet multipliers),
continue it in r or alpha by pseudo-arclength continuation, and print the fold (multiplier +1) and
flip (multiplier -1) points located by Newton on the extended system.

Without --tau0/--sdot0 the guess is the end of a long run (--settle impacts) from (0, 0.5)."""

from __future__ import annotations

import argparse

import numpy as np

from ..cliutil import (MAX_IMPACTS, MAX_VALUES, CliError, add_param_args, check_distinct, check_output_file,
                       int_range, params_from, positive_int, real, save_figure, tau0_type, write_file, write_text)

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
    p.add_argument("--output", default=None, help="orbit or branch data: .npz or .csv (default: CSV on stdout)")
    p.add_argument("--plot", default=None, metavar="FILE.png",
                   help="branch figure, sdot and |multipliers| (default: no figure)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    import sys

    from ...mapimpl.periodic import find_periodic
    from ..dynamics.continuation import closed_form_det, continue_orbit
    from ..dynamics.crises import attractor_point
    from ...mapimpl.progress import Progress

    base = params_from(args)
    check_output_file(args.output, "--output")
    check_output_file(args.plot, "--plot", plot=True)
    check_distinct(**{"--output": args.output, "--plot": args.plot})
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
    a = br.arrays()
    if args.output and args.output.endswith(".npz"):
        write_file("--output", args.output, lambda path: np.savez_compressed(
            path, **a, param=args.param, folds=np.array([f.mu for f in br.folds]),
            flips=np.array([f.mu for f in br.flips])))
    else:
        rows = [f"{args.param},tau,sdot,mult1_re,mult1_im,mult2_re,mult2_im,stable"]
        for i in range(a["mu"].size):
            rows.append(f"{float(a['mu'][i])!r},{float(a['tau'][i])!r},{float(a['sdot'][i])!r},{float(a['mult_re'][i, 0])!r},{float(a['mult_im'][i, 0])!r},"
                        f"{float(a['mult_re'][i, 1])!r},{float(a['mult_im'][i, 1])!r},{bool(a['stable'][i])}")
        write_text("\n".join(rows) + "\n", args.output)
    out = sys.stderr if args.output in (None, "-") else sys.stdout
    print(f"branch: {len(br.points)} points, stop: {br.stop_reason}", file=out)
    for f in br.folds + br.flips:
        print(f.describe(), file=out)
    if args.plot:
        from ..figures import subplots

        fig, ax = subplots(2, 1, figsize=(7, 5), sharex=True)
        st = a["stable"]
        ax[0].plot(a["mu"], a["sdot"], "-", color="gray", lw=0.6)
        ax[0].plot(a["mu"][st], a["sdot"][st], ".b", ms=3, label="stable")
        ax[0].plot(a["mu"][~st], a["sdot"][~st], ".r", ms=3, label="unstable")
        ax[0].set_ylabel(r"$\dot s$ (one point of the orbit)"); ax[0].legend(fontsize=8)
        mods = np.abs(a["mult_re"] + 1j * a["mult_im"])
        ax[1].semilogy(a["mu"], mods, ".", ms=3); ax[1].axhline(1, color="k", lw=0.5)
        for f in br.folds + br.flips:
            for x in ax:
                x.axvline(f.mu, color="g" if f.kind == "fold" else "m", lw=0.6)
        ax[1].set_ylabel("|Floquet multipliers|"); ax[1].set_xlabel(args.param)
        fig.tight_layout()
        save_figure(fig, args.plot, "--plot", dpi=150)
    return 0
