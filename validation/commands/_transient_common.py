"""Options shared by the ``basins``, ``uncertainty`` and ``transients`` commands (Section 4)."""

from __future__ import annotations

import argparse
import json

from ..cliutil import add_param_args, positive_int


def add_common(p: argparse.ArgumentParser) -> None:
    add_param_args(p, alpha=1.245, beta=0.1, gamma=0.1, r=0.9)
    p.add_argument("--profile", choices=("quick", "paper"), default="quick",
                   help="quick: small default (< 1 min); paper: the paper's scale")
    p.add_argument("--delta", type=float, default=1e-3,
                   help="capture distance to the periodic orbit (sup norm of (tau mod 2pi, sdot); default 1e-3)")
    p.add_argument("--outdir", default="out/transients", help="output directory (default out/transients)")
    p.add_argument("--lanes", type=positive_int("--lanes"), default=None,
                   help="orbits advanced together per device (default: ~N/16, at most 512 on CPU)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")


def print_summary(summary: dict) -> None:
    print(json.dumps({k: v for k, v in summary.items() if k != "engine"}, indent=1))
    e = summary.get("engine", {})
    print(f"engine: {e.get('impacts')} impacts in {e.get('elapsed_s', 0):.1f} s "
          f"({e.get('impacts_per_s', 0):.3g} impacts/s), orbits with sticking: {e.get('orbits_with_sticking')}")
