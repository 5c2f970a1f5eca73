"""Shared helpers of the CLI subcommands: parameter options, validated inputs, output files."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..mapimpl.params import Params


class CliError(Exception):
    """A user error on the command line: printed as one line, exit status 2."""


def add_param_args(p: argparse.ArgumentParser, alpha=3.0, beta=0.1, gamma=0.1, r=0.9) -> None:
    """Add --alpha --beta --gamma --r (Eqs. 4-6 and 11) with the given defaults."""
    g = p.add_argument_group("model parameters (Eqs. 4-6, 11)")
    g.add_argument("--alpha", type=float, default=alpha, help=f"driving amplitude, >= 0 (default {alpha})")
    g.add_argument("--beta", type=float, default=beta, help=f"damping, > 0 (default {beta})")
    g.add_argument("--gamma", type=float, default=gamma, help=f"constant torque term, finite (default {gamma})")
    g.add_argument("--r", type=float, default=r, help=f"restitution coefficient, 0 < r <= 1 (default {r})")


def params_from(args: argparse.Namespace) -> Params:
    """Validated Params from parsed arguments (ValueError names the parameter and its range)."""
    return Params(args.alpha, args.beta, args.gamma, args.r)


def int_at_least(name: str, lo: int):
    """argparse type: an integer >= ``lo``, with a message naming the option and the range."""

    def conv(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}={text!r} is not an integer") from None
        if v < lo:
            raise argparse.ArgumentTypeError(f"{name}={v} is out of range: allowed {name} >= {lo}")
        return v

    return conv


def positive_int(name: str):
    """argparse type: an integer >= 1."""
    return int_at_least(name, 1)


def nonneg_int(name: str):
    """argparse type: an integer >= 0."""
    return int_at_least(name, 0)


def write_text(text: str, output: str | None) -> None:
    """Write to a file (parents created) or to stdout when ``output`` is None or '-'."""
    if output in (None, "-"):
        sys.stdout.write(text)
        return
    path = Path(output)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    except OSError as e:
        raise CliError(f"cannot write output file {output!r}: {e.strerror}") from None


def check_writable(path: str | None, option: str) -> None:
    """Fail early (before a long run) if the output file cannot be created."""
    if path in (None, "-"):
        return
    parent = Path(path).resolve().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise CliError(f"{option}: cannot create directory {str(parent)!r}: {e.strerror}") from None
