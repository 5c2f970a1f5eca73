"""Options shared by the ``basins``, ``uncertainty`` and ``transients`` commands (Section 4)."""

from __future__ import annotations

import argparse

from ..cliutil import add_output_options, add_param_args, check_outputs, positive_int, real
from ...core.paper import PAPER_PARAMS

#: Most orbits advanced together per device.
MAX_LANES = 65536


def add_common(p: argparse.ArgumentParser) -> None:
    add_param_args(p, **{k: getattr(PAPER_PARAMS, k) for k in ("alpha", "beta", "gamma", "r")})
    p.add_argument("--profile", choices=("quick", "paper"), default="quick",
                   help="quick: small (< 1 min); paper: the paper's scale (default quick)")
    p.add_argument("--delta", type=real("--delta", lo=0.0, lo_open=True, hi=1.0), default=1e-3,
                   help="capture distance to the periodic orbit, sup norm of (tau mod 2pi, sdot), 0 < delta <= 1 "
                        "(default 0.001)")
    p.add_argument("--lanes", type=positive_int("--lanes", MAX_LANES), default=None,
                   help=f"orbits advanced together per device, at most {MAX_LANES} "
                        "(default: the orbits per device, at most 256 on a CPU with the engine's XLA options, 512 "
                        "without them, 65536 on an accelerator)")
    add_output_options(p, out=("out/transients", "output directory (default out/transients)"), quiet="no progress bar")


def check_common(args: argparse.Namespace) -> None:
    """Validate the shared options that need more than their own value, before computing."""
    check_outputs(args)


def progress_arg(args: argparse.Namespace):
    """The engine's ``progress=``: off with --quiet, else a bar when stderr is a terminal."""
    return False if args.quiet else None


def print_summary(summary: dict, notes=()) -> None:
    """The result's summary (without the engine's run record) as strict JSON on stdout; the notes (fits
    that failed) and the engine's run record on stderr."""
    import sys

    from ..io import json_text

    print(json_text({k: v for k, v in summary.items() if k != "engine"}))
    for note in notes:
        print(note, file=sys.stderr)
    e = summary.get("engine", {})
    print(f"engine: {e.get('impacts')} impacts in {e.get('elapsed_s', 0):.1f} s "
          f"({e.get('impacts_per_s', 0):.3g} impacts/s), orbits with sticking: {e.get('orbits_with_sticking')}",
          file=sys.stderr)
