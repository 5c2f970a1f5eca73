"""The ``gear-rattle`` command line.

Every subcommand lives in its own module (see :mod:`validation.commands`).  Errors in the input
are reported as one line on stderr with exit status 2, never as a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from ..mapimpl._jax import use_cpu_devices
from .cliutil import CliError

#: Subcommand modules, in the order shown by ``gear-rattle --help``.
COMMAND_MODULES = [
    "gear_rattle.validation.commands.simulate",
    "gear_rattle.validation.commands.report",
    "gear_rattle.validation.commands.bifurcation",
    "gear_rattle.validation.commands.lyapunov",
    "gear_rattle.validation.commands.orbitcmd",
    "gear_rattle.validation.commands.timeseries",
    "gear_rattle.validation.commands.basins",
    "gear_rattle.validation.commands.uncertainty",
    "gear_rattle.validation.commands.transients",
    "gear_rattle.validation.commands.atlas",
    "gear_rattle.validation.commands.check",
]


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, exit 2
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered subcommand."""
    parser = _Parser(prog="gear-rattle", description="Gear-rattling impact model (de Souza et al. 2004): "
                     "simulation, cross-validation and reproduction of the paper.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in COMMAND_MODULES:
        mod = importlib.import_module(name)
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.__doc__)
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        # the command line (not the library) spreads the engine over one XLA CPU device per core
        use_cpu_devices()
        return int(args._run(args) or 0)
    except (ValueError, CliError) as e:
        print(f"gear-rattle {args.command}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"gear-rattle {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
