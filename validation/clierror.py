"""The command line's two kinds of error and the name it reports under: what the entry point
(:mod:`validation.cli`) needs before it has parsed a command, kept apart from the option toolkit
(:mod:`validation.cliutil`, which imports the library's parameters and numpy) so that ``gear-rattle
--version`` and ``--help`` load no third-party package.  :mod:`validation.cliutil` re-exports them."""

from __future__ import annotations


class CliError(Exception):
    """A user error on the command line: printed as one line, exit status 2."""


class CommandFailed(Exception):
    """The computation did not give the result asked for (e.g. Newton did not converge): printed as
    one line, exit status 1, nothing written."""


#: The name the running command reports under (``gear-rattle COMMAND``), set by the entry point once the
#: command is known; notes and errors begin with it.
COMMAND = ["gear-rattle"]

__all__ = ["CliError", "CommandFailed", "COMMAND"]
