"""Options shared by the ``basins``, ``uncertainty`` and ``transients`` commands (Section 4)."""

from __future__ import annotations

import argparse

from ..cliutil import add_output_options, add_param_args, check_outputs, positive_int, real
from ...core.paper import DELTA, PAPER_PARAMS

#: Most orbits advanced together per device.
MAX_LANES = 65536


def add_common(p: argparse.ArgumentParser) -> None:
    add_param_args(p, PAPER_PARAMS)
    p.add_argument(
        "--profile",
        choices=("quick", "paper"),
        default="quick",
        help="quick: small (< 1 min); paper: the paper's scale (default quick)",
    )
    p.add_argument(
        "--delta",
        type=real("--delta", lo=0.0, lo_open=True, hi=1.0),
        default=DELTA,
        help="capture distance to the periodic orbit, sup norm of (tau mod 2pi, sdot), 0 < delta <= 1 "
        f"(default {DELTA:g})",
    )
    p.add_argument(
        "--lanes",
        type=positive_int("--lanes", MAX_LANES),
        default=None,
        help=f"orbits advanced together per device, 1 to {MAX_LANES} "
        "(default: the orbits per device, at most 256 on a CPU with the engine's XLA options, 512 "
        "without them, 65536 on an accelerator)",
    )
    add_output_options(p, out=("out/transients", "output directory (default out/transients)"), quiet="no progress bar")


def check_common(args: argparse.Namespace) -> None:
    """Validate the shared options that need more than their own value, before computing."""
    check_outputs(args)


def execution_of(args: argparse.Namespace):
    """The engine's :class:`~gear_rattle.mapimpl.engine.options.Execution` of ``--lanes``."""
    from ...mapimpl.engine.options import Execution

    return Execution(lanes=args.lanes)


def _fmt(x, spec: str = ".4g") -> str:
    return "n/a" if x is None else format(x, spec)


def _no_comparison(summary: dict) -> list[str]:
    """The line saying that no comparison with the paper is made, where the summary's ``paper`` is that line
    (:func:`~gear_rattle.validation.transient.results.paper_comparison`)."""
    p = summary.get("paper")
    return [f"  {p}"] if isinstance(p, str) else []


def human_lines(summary: dict) -> list[str]:
    """A few lines for a person at a terminal: the figure's headline numbers (the JSON has all), the paper's
    values beside them only at the paper's parameters."""
    fig = summary.get("figure")
    if fig == "9":
        fr = ", ".join(f"n = {n}: {f:.3f}" for n, f in summary["short_fraction"].items())
        head = f"Fig. 9 basins, {summary['nx']} x {summary['ny']} mesh: fraction of transients shorter than {fr}"
        return [head, *_no_comparison(summary)]
    if fig == "10":
        lines = [f"Fig. 10 uncertainty, {summary['n_points']} points:"]
        papers = summary.get("paper")
        papers = papers if isinstance(papers, dict) else {}  # else: not the paper's parameters
        for n, f in summary["fits"].items():
            paper = papers.get(n)
            ours = "no fit" if f is None else f"phi = {_fmt(f['phi'])} +- {_fmt(f['phi_se_boot'], '.2g')}"
            lines.append(f"  n = {n}: {ours}" + (f" (paper {paper[0]} +- {paper[1]})" if paper else ""))
        return lines + _no_comparison(summary)
    d = str(summary["delta"])
    f = summary["fits"].get(d) or next(iter(summary["fits"].values()), None)
    head = f"Fig. 11 survival, {summary['nx']} x {summary['ny']} mesh, cap {summary['cap']}:"
    if f is None:
        return [head, "  no Eq. (14) fit (see the notes above)"]
    p = summary.get("paper", {})
    ours = f"  delta = {d}: kappa = {_fmt(f['kappa'])} +- {_fmt(f['kappa_se_boot'], '.2g')}"
    if _no_comparison(summary):  # not the paper's parameters: the line saying so
        return [head, f"{ours}, <n> = {_fmt(f['mean_n'], '.1f')}", *_no_comparison(summary)]
    return [
        head,
        f"{ours} (paper {p.get('kappa', ['?'])[0]}), <n> = {_fmt(f['mean_n'], '.1f')} (paper {p.get('mean_n', '?')})",
    ]


def print_summary(summary: dict, notes=(), files=()) -> None:
    """The result's summary (without the engine's run record) on stdout (strict JSON, or on a terminal
    :func:`human_lines`); the notes (fits that failed) and the engine's run record as notes on stderr."""
    from ..cliutil import note, print_result

    for text in notes:
        note(text)
    e = summary.get("engine", {})
    note(
        f"engine: {e.get('impacts')} impacts in {e.get('elapsed_s', 0):.1f} s ({e.get('impacts_per_s', 0):.3g} "
        f"impacts/s), orbits with sticking: {e.get('orbits_with_sticking')}"
    )
    print_result({k: v for k, v in summary.items() if k != "engine"}, human_lines(summary), files)


__all__ = [
    "MAX_LANES",
    "add_common",
    "check_common",
    "execution_of",
    "human_lines",
    "print_summary",
]
