"""The ``gear-rattle`` command line.

Every subcommand lives in its own module (see :mod:`validation.commands`).  Errors in the input
are reported as one line on stderr with exit status 2, never as a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys

from ..core._jax import use_cpu_devices
from .cliutil import CliError
from .extras import MissingExtra

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


#: A negative number in any float notation (``-1``, ``-1.5``, ``-.5``, ``-1e-2``, ``-3E+1``, ``-inf``):
#: argparse's own pattern knows only ``-1`` and ``-1.5`` and takes ``-1e-2`` for an option.
NEGATIVE_NUMBER = re.compile(r"^-(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|inf|infinity|nan)$", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """One-line errors with exit status 2; negative numbers in any float notation are values."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message: str):  # one line, exit 2
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered subcommand."""
    parser = _Parser(prog="gear-rattle", description="Gear-rattling impact model (de Souza et al. 2004): "
                     "simulation, cross-validation and reproduction of the paper.")
    from gear_rattle import __version__

    parser.add_argument("--version", action="version", version=f"gear-rattle {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in COMMAND_MODULES:
        mod = importlib.import_module(name)
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.__doc__)
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script; returns the exit status (a usage error found while parsing
    raises SystemExit(2) after its one-line message, as argparse does)."""
    command = None
    try:
        parser = build_parser()
        args = parser.parse_args(argv)
        command = args.command
        # the command line (not the library) spreads the engine over one XLA CPU device per core
        use_cpu_devices()
        return int(args._run(args) or 0)
    except (ValueError, CliError, MissingExtra) as e:
        print(f"gear-rattle {command}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C: one line, the shell's status for SIGINT
        print(f"gear-rattle{' ' + command if command else ''}: interrupted", file=sys.stderr)
        if argv is None:
            # the console script: end the process now.  A Ctrl-C that lands while XLA starts its
            # CPU client or compiles can leave native work behind that crashes the interpreter's
            # teardown (a segfault after the message); outputs are written only after the
            # computation, so there is nothing to finish.
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(130)
        return 130
    except BrokenPipeError:  # e.g. `gear-rattle simulate | head`: stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141


if __name__ == "__main__":
    sys.exit(main())
