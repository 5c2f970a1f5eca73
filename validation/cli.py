"""The ``gear-rattle`` command line.

Every subcommand lives in its own module (see :mod:`validation.commands`); :data:`SUBCOMMANDS` lists
their names and one-line help, so that the parser imports the module of the command that runs and no
other (``gear-rattle --version`` and ``--help`` import none).  Errors in the input are reported as one
line on stderr with exit status 2, never as a traceback.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import sys
import threading
import warnings
from types import ModuleType

from ..core import jax_config
from . import interrupt, progress
from ..core.jax_config import use_compilation_cache, use_cpu_devices
from .clierror import COMMAND, CliError, CommandFailed
from .extras import FULL_INSTALL, MissingExtra, require_full_install

#: The subcommands, in the order ``gear-rattle --help`` shows them, with their one-line help: the parser
#: lists them from here and imports the module of the one that runs (:func:`command_module`).
SUBCOMMANDS = {
    "simulate": "simulate one orbit (impact sequence, CSV/JSON, optional Figs. 2-3 plot)",
    "report": "generate the validation report (HTML + Markdown)",
    "bifurcation": "bifurcation diagram in r (Fig. 4a) or alpha (Fig. 8a), NPZ/CSV and figure",
    "lyapunov": "Lyapunov exponents against r or alpha (Figs. 4b, 8b), QR method",
    "orbit": "periodic orbits: find, continue in r or alpha, fold and flip points",
    "timeseries": "discrete and stroboscopic velocity time series (Figs. 5-7)",
    "basins": "Fig. 9: transient basins for n = 90, 500, 1000, 2000",
    "uncertainty": "Fig. 10: uncertain fraction f(eps) and uncertainty exponents",
    "transients": "Fig. 11: survival N(n) of transients and the Eq. (14) fit",
    "atlas": "Lyapunov/period atlas over (alpha, r) in tiles on Dask, stored in Zarr, resumable",
    "check": "score another implementation's output against the golden conformance suite",
    "case": "build a certified golden-format case (or a whole suite, --from) for your own input",
    "fuzz": "differential fuzzing of another implementation against certified cases (finds and shrinks failures)",
}


def command_module(name: str) -> ModuleType:
    """The module of the subcommand ``name`` (a key of :data:`SUBCOMMANDS`), imported by an import
    statement, which the import contract and tests/test_import_cycles.py see (a module named in a string
    is an edge neither sees).  Each is light to import (numpy at most; its ``add_arguments`` and ``run``
    import what the command computes with)."""
    match name:
        case "simulate":
            from .commands import simulate

            return simulate
        case "report":
            from .commands import report

            return report
        case "bifurcation":
            from .commands import bifurcation

            return bifurcation
        case "lyapunov":
            from .commands import lyapunov

            return lyapunov
        case "orbit":
            from .commands import orbitcmd

            return orbitcmd
        case "timeseries":
            from .commands import timeseries

            return timeseries
        case "basins":
            from .commands import basins

            return basins
        case "uncertainty":
            from .commands import uncertainty

            return uncertainty
        case "transients":
            from .commands import transients

            return transients
        case "atlas":
            from .commands import atlas

            return atlas
        case "check":
            from .commands import check

            return check
        case "case":
            from .commands import case

            return case
        case "fuzz":
            from .commands import fuzz

            return fuzz
    raise ValueError(f"name={name!r} is out of range: allowed one of {list(SUBCOMMANDS)}")


def command_modules() -> list[ModuleType]:
    """Every subcommand's module, in the order of :data:`SUBCOMMANDS` (imports all of them)."""
    return [command_module(name) for name in SUBCOMMANDS]


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

    def parse_args(self, args=None, namespace=None):
        """As argparse's, but an unknown option is reported by the subcommand that was given it
        (``gear-rattle simulate: error: unrecognized arguments: --bogus``)."""
        ns, extra = self.parse_known_args(args, namespace)
        if extra:
            sub = self._subparsers_by_name().get(getattr(ns, "command", None), self)
            sub.error(f"unrecognized arguments: {' '.join(extra)}")
        return ns

    def _subparsers_by_name(self) -> dict:
        for a in self._actions:
            if isinstance(a, argparse._SubParsersAction):
                return dict(a.choices)
        return {}


def build_parser(only: list[str] | None = None) -> argparse.ArgumentParser:
    """The argument parser with every subcommand of :data:`SUBCOMMANDS`; with ``only`` (subcommand
    names), the modules of those subcommands alone are imported and their options added, the others
    listed by name and help (:func:`command_word`: the command line adds the options of the command it
    runs -- some import JAX to state their limits).  A subcommand whose options need a package that a
    light install lacks is one line naming it (:func:`extras.require_full_install`)."""
    parser = _Parser(
        prog="gear-rattle",
        description="Gear-rattling impact model (de Souza et al. 2004): "
        "simulation, cross-validation and reproduction of the paper.",
    )
    from gear_rattle import __version__

    from .golden.formats.version import version_line

    parser.add_argument("--version", action="version", version=f"gear-rattle {__version__} ({version_line()})")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name, text in SUBCOMMANDS.items():
        if only is not None and name not in only:
            sub.add_parser(name, help=text)
            continue
        mod = command_module(name)
        p = sub.add_parser(name, help=text, description=mod.__doc__)
        try:
            mod.add_arguments(p)
        except ModuleNotFoundError as e:
            if (e.name or "").split(".")[0] in FULL_INSTALL:
                require_full_install("this command")
            raise
        p.set_defaults(_run=mod.run, _needs_jax=getattr(mod, "needs_jax", None))
    return parser


def command_word(argv: list[str]) -> list[str]:
    """The subcommand named in ``argv`` (the first word that is not an option: ``gear-rattle`` itself
    has no option that takes a value), as a list for :func:`build_parser`'s ``only``; ``[]`` if none."""
    return next(([a] for a in argv if not a.startswith("-")), [])


def _start_jax(args: argparse.Namespace, console: bool) -> None:
    """Before a command that computes with JAX (a module's ``needs_jax(args)``, default: every command):
    one line naming the packages a light install lacks (:func:`extras.require_full_install`), then
    the engine's XLA CPU devices and, in the console script, the compilation cache.  ``gear-rattle
    check`` scoring files needs none of it: it runs with numpy alone."""
    if args._needs_jax is not None and not args._needs_jax(args):
        return
    require_full_install("this command")
    # the command line (not the library) spreads the engine over one XLA CPU device per core and, as a
    # process of its own, keeps compiled kernels in a per-user cache ($GEAR_RATTLE_JAX_CACHE=0: off)
    use_cpu_devices()
    if console:
        use_compilation_cache()


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script; returns the exit status (a usage error found while parsing
    raises SystemExit(2) after its one-line message, as argparse does).

    The console script (``argv`` None) runs the command in a worker thread with SIGINT blocked and
    keeps the main thread waiting, so that Ctrl-C is taken by the main thread at once, whatever the
    command is doing -- loading JAX, compiling (XLA holds the thread for seconds), computing -- and ends
    the process with one line and status 130 (:func:`.interrupt.exit_interrupted`).  Threads and
    processes the command starts inherit the blocked signal: the atlas's Dask workers do not see the
    terminal's Ctrl-C (they exit with this process).  SIGTERM ends it the same way with status 143; it is
    not blocked in the worker (sent to one process, it must still reach the atlas's Dask worker
    processes from their nanny), so the main thread takes it at its next 0.1 s wake-up at the latest.
    The command's files are renamed into place together when it returns (:func:`.io.atomic.outputs`;
    the signal handler waits for those renames).  The console script also turns on the persistent
    compilation cache (:func:`core.jax_config.use_compilation_cache`).  Called with ``argv`` (tests, other
    programs), the command runs in the calling thread, a KeyboardInterrupt returns 130, and JAX's
    configuration is left as the caller has it (no cache).  Python warnings become one-line notes on
    stderr in both (:class:`_WarningNotes`)."""
    if argv is None and threading.current_thread() is threading.main_thread():
        return _main_in_worker()
    return _run(argv)


def _main_in_worker() -> int:
    outcome: dict = {}

    def work():
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            outcome["rc"] = _run(None, console=True)
        except BaseException as e:  # noqa: BLE001 - re-raised in the main thread (SystemExit included)
            outcome["exc"] = e

    for sig in interrupt.EXIT_SIGNALS:  # SIGINT and SIGTERM: one line, 130 or 143
        if signal.getsignal(sig) is not signal.SIG_IGN:  # started ignoring it (`cmd &` in a script):
            signal.signal(sig, interrupt.exit_interrupted)  # keep ignoring it, as Python itself does
    worker = threading.Thread(target=work, name="gear-rattle-command", daemon=True)
    worker.start()
    while worker.is_alive():
        worker.join(0.1)  # the main thread wakes for signals
    if "exc" in outcome:
        raise outcome["exc"]
    return outcome["rc"]


def _run(argv: list[str] | None, console: bool = False) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = _WarningNotes()
        return _run_command(argv, console)


class _WarningNotes:
    """The command line's one boundary for Python warnings: a warning that reaches it (a numpy
    RuntimeWarning, JAX reporting an unreadable compilation-cache entry, ...) becomes one line on
    stderr, ``gear-rattle COMMAND: note: Category: message``, once per place in the code that warns,
    instead of a two-line warning with a source line; stdout is never touched."""

    def __init__(self):
        self.seen: set = set()

    def __call__(self, message, category, filename, lineno, file=None, line=None):
        key = (category, filename, lineno)
        if key in self.seen:
            return
        self.seen.add(key)
        label = interrupt.INTERRUPTED[0].rsplit(":", 1)[0]  # "gear-rattle COMMAND"
        text = " ".join(str(message).split())
        if "persistent compilation cache" in text:  # JAX recompiled: say where the cache is
            text += (
                f" (recompiled; the cache is {jax_config.compilation_cache_dir()!r}: delete it to rebuild it, or "
                f"set {jax_config.JAX_CACHE_ENV}=0)"
            )
        print(f"{label}: note: {category.__name__}: {text}", file=sys.stderr)


def _run_command(argv: list[str] | None, console: bool) -> int:
    command = None
    try:
        only = command_word(sys.argv[1:] if argv is None else list(argv))
        command = only[0] if only else None
        parser = build_parser(only)
        args = parser.parse_args(argv)
        command = args.command
        interrupt.INTERRUPTED[0] = f"gear-rattle {command}: interrupted"
        COMMAND[0] = f"gear-rattle {command}"
        if not getattr(args, "quiet", False):  # until the first bar, note or result (a terminal only)
            progress.status(f"gear-rattle {command}: starting (loading libraries)")
        _start_jax(args, console)
        from .io.atomic import outputs

        # every file the command writes is renamed into place at the end, together (io.atomic)
        with outputs(command, _out_folder(args), None if argv is None else ["gear-rattle", *argv]):
            rc = int(args._run(args) or 0)
        progress.clear_status()
        return rc
    except (ValueError, CliError, MissingExtra) as e:
        progress.clear_status()
        print(f"gear-rattle {command}: error: {e}", file=sys.stderr)
        return 2
    except CommandFailed as e:
        progress.clear_status()
        print(f"gear-rattle {command}: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:  # Ctrl-C in a command run from Python (the console script exits at once)
        progress.clear_status()
        print(f"gear-rattle{' ' + command if command else ''}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `gear-rattle simulate | head`: stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141
    except OSError as e:  # a file system fault outside the writers' own messages: one line as well
        from .cliutil import output_fault

        progress.clear_status()
        fault = output_fault(e)
        print(f"gear-rattle {command}: error: {fault}", file=sys.stderr)
        return 1 if isinstance(fault, CommandFailed) else 2


def _out_folder(args: argparse.Namespace) -> str | None:
    """The ``--out`` folder whose manifest names the run (validation/io/atomic.py); the atlas keeps its own
    store records instead."""
    out = getattr(args, "out", None)
    return out if isinstance(out, str) and args.command != "atlas" else None


if __name__ == "__main__":
    sys.exit(main())


__all__ = [
    "SUBCOMMANDS",
    "command_module",
    "command_modules",
    "NEGATIVE_NUMBER",
    "build_parser",
    "command_word",
    "main",
]
