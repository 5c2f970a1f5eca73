"""Simulate one orbit and print its events: one row per impact (n, tau, tau mod 2 pi, wall, sdot just
before the impact, kind) plus stick/release rows under the sticking policy.

The initial state (--tau0, --sdot0) is the state just before an impact (sdot0 > 0 hits s = 0,
sdot0 < 0 hits s = -1), as in the paper; with --s0 it is a free-flight state instead.

``--track certified`` proves every row in ball arithmetic (:mod:`mapimpl.certified.track`): the values are
the float64 nearest to the exact ones, followed by the float64 bounds ``tau_lo ... sdot_hi`` that contain
them.  Its precision rises by itself up to ``--max-precision``; where that does not certify every impact,
the certified rows alone are written (a prefix: the JSON says so in ``certified``) and the command ends with
one line naming the first impact not certified and why, exit status 1.
"""

from __future__ import annotations

import argparse

from ..cliutil import (
    MAX_IMPACTS,
    CliError,
    CommandFailed,
    add_output_options,
    add_stick_time_arg,
    int_range,
    add_param_args,
    check_outputs,
    nonneg_int,
    note,
    params_from,
    progress_arg,
    real,
    add_start_args,
    check_start_args,
    write_result,
    write_plot,
)

NAME = "simulate"


def add_arguments(p: argparse.ArgumentParser) -> None:
    # the certified track's limits come from its module (python-flint: a light install lacks it, and the
    # command line imports every command's module to list it)
    from ...mapimpl.certified.balls import MAX_PREC
    from ...mapimpl.certified.track import MAX_TRACK_PREC
    from ...mapimpl.sticking import STICK_TIME

    add_param_args(p)
    add_start_args(p, s0="start in free flight at -1 <= s0 <= 0 (default: none, start at an impact)")
    p.add_argument(
        "--impacts",
        type=nonneg_int("--impacts", MAX_IMPACTS),
        default=1000,
        help=f"impacts after impact 0, 0 to {MAX_IMPACTS} (default 1000)",
    )
    p.add_argument(
        "--track",
        choices=("map", "scipy", "diffrax", "certified"),
        default="map",
        help="which track computes the orbit (default map; certified: every row proven, with float64 bounds)",
    )
    add_stick_time_arg(p, STICK_TIME)
    p.add_argument(
        "--max-precision",
        type=int_range("--max-precision", 64, MAX_PREC),
        default=None,
        help=f"--track certified: the precision limit in bits, 64 to {MAX_PREC} (default {MAX_TRACK_PREC}); "
        "the precision starts at 320 bits (or the limit) and rises until every impact is certified",
    )
    add_output_options(p, output="the events", plot="draw the paper's Figs. 2-3 for this orbit (default: no figure)")
    p.add_argument(
        "--plot-span",
        type=real("--plot-span", lo=0.0, lo_open=True, hi=1e4),
        default=50.0,
        help="time span of the plot in tau units, 0 < span <= 1e4 (default 50.0)",
    )


def run(args: argparse.Namespace) -> int:
    from ...mapimpl.tracks import orbit

    params = params_from(args)
    if args.max_precision is not None and args.track != "certified":
        raise CliError("--max-precision: allowed with --track certified only")
    check_outputs(args)
    check_start_args(args)
    if args.track == "certified":
        return _run_certified(args, params)
    seq = orbit(params, args.tau0, args.sdot0, args.impacts, track=args.track, **_start(args))
    _finish(args, seq)
    return 0


def _start(args: argparse.Namespace) -> dict:
    """The options every track's orbit takes from the command line: ``s0``, ``stick_time``, ``progress``."""
    return {"s0": args.s0, "stick_time": args.stick_time, "progress": progress_arg(args)}


def _finish(args: argparse.Namespace, seq) -> None:
    """The plot, the output and the note of an orbit that ended early."""
    fig = None
    if args.plot:  # drawn before anything is written
        from ..plots import time_series_figure

        fig = time_series_figure(seq, span=args.plot_span)
    write_result(args, seq)
    if seq.status != "active":
        why = {
            "no_impact": "no wall is reached within the flight horizon T_MAX",
            "stuck_forever": "the tooth sticks to a wall and the forcing never releases it",
            "step_cap": "the impact search hit its iteration cap",
        }.get(seq.status, seq.status)
        made = int(seq.impacts.sum())  # impact 0 and those after it
        when = "before its first impact" if made == 0 else f"after {made - 1} impacts"
        note(f"the orbit ended {when} (status {seq.status}: {why})")
    write_plot(args, fig)


def _run_certified(args: argparse.Namespace, params) -> int:
    """``--track certified``: the certified orbit, or its certified prefix and one line, exit status 1."""
    from ...mapimpl.certified.track import MAX_TRACK_PREC, certified_orbit
    from ..io.atomic import commit_pending

    limit = MAX_TRACK_PREC if args.max_precision is None else args.max_precision
    run = certified_orbit(params, args.tau0, args.sdot0, args.impacts, max_prec=limit, **_start(args))
    seq = run.sequence()
    if run.complete:
        _finish(args, seq)
        return 0
    write_result(args, seq)  # the certified prefix only (no plot of a partial orbit)
    commit_pending()  # a whole file, kept although the command fails (io.atomic discards on failure)
    k = run.impacts_certified
    raise CommandFailed(
        f"impact {run.first_uncertified} not certified: {run.reason}; the output holds the "
        f"{k} certified impact{'' if k == 1 else 's'} before it"
    )


__all__ = [
    "NAME",
    "add_arguments",
    "run",
]
