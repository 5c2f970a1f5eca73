"""The command line's process control: Ctrl-C (SIGINT) and SIGTERM end a ``gear-rattle`` command at once,
with one line on stderr and exit status 130 or 143, after killing the processes the command started in
sessions of their own and removing the output writer's temporary files.

* :func:`exit_interrupted`, the handler (installed by the console script's ``main``,
  ``validation/cli.py``, for the command's run, and -- ``_guard_command_line_start`` -- as soon as this
  package is imported in the command line, so that a signal while JAX loads gives the one line too, not
  a traceback);
* :data:`CLEANUP` and :data:`CLEANUP_LOCK`, the files that the handler removes and the lock that the
  output writer (:mod:`gear_rattle.validation.io.atomic`) and the atlas lock
  (:mod:`gear_rattle.validation.writelock`) hold while they register or rename them;
* :data:`CLEAR_LINE`, what clears a progress bar's line first (:mod:`gear_rattle.validation.progress`).

The library (``core``, ``mapimpl``, ``reference``) installs no signal handler and never ends the
process: this module is imported by ``gear_rattle.validation`` (docs/architecture.md).
"""

from __future__ import annotations

import os
import signal
import sys
import threading


def command_line_process() -> bool:
    """Whether this process is the ``gear-rattle`` command line (the console script or ``python -m
    gear_rattle``), as opposed to a program importing the library."""
    orig = list(getattr(sys, "orig_argv", ()))
    # the console script is on the interpreter's own command line (a multiprocessing child of the command
    # line inherits its sys.argv, not its orig_argv)
    if sys.argv and os.path.basename(sys.argv[0]) in ("gear-rattle", "gear-rattle.exe") and sys.argv[0] in orig:
        return True
    return "-m" in orig[:-1] and orig[orig.index("-m") + 1] == "gear_rattle"


#: The line a Ctrl-C prints in the command line (the CLI adds the command's name once it is known);
#: SIGTERM prints it with "terminated" for "interrupted".
INTERRUPTED = ["gear-rattle: interrupted"]
#: Temporary files and staging folders a Ctrl-C or SIGTERM removes before the process ends (those of the
#: output writer, validation/io/atomic.py: nothing half-written stays).
CLEANUP: list[str] = []
#: Process groups the command started in sessions of their own (``fuzz``'s implementation,
#: validation/golden/fuzzing/process.py): the handler kills each whole group (SIGKILL) before it removes the files.
PROCESS_GROUPS: list[int] = []
#: Held while the output writer registers a temporary file or renames outputs into place; the signal
#: handler takes it before it cleans up, so a signal never lands between two renames of one command.
CLEANUP_LOCK = threading.RLock()
#: The longest the signal handler waits for :data:`CLEANUP_LOCK` (renames take milliseconds).
CLEANUP_WAIT_S = 10.0
#: What clears a progress bar from the terminal line before the Ctrl-C line (set by
#: :class:`validation.progress.TerminalBar`); without one, the line is cleared when stderr is a terminal.
CLEAR_LINE: list = []
#: The signals the command line ends on with one line, and their exit statuses (128 + the number).
EXIT_SIGNALS = {signal.SIGINT: 130, signal.SIGTERM: 143}


def exit_interrupted(signum=None, frame=None) -> None:
    """The command line's SIGINT and SIGTERM handler: :data:`INTERRUPTED` on stderr ("terminated" for
    SIGTERM) and exit status 130 (SIGINT) or 143 (SIGTERM) at once, after removing the output writer's
    temporary files (:data:`CLEANUP`).  Outputs are renamed into place only after the computation (or,
    for the atlas, tile by tile, each tile marked done after its data), so there is nothing to finish;
    ending the process from the signal handler, rather than with an exception, is what makes Ctrl-C act
    while the main thread is not running Python (JAX loading its extension, XLA compiling) and what
    keeps an exception from being swallowed by a library (a KeyboardInterrupt inside JAX's
    garbage-collection callback is printed and ignored)."""
    term = signum == signal.SIGTERM
    for group in list(PROCESS_GROUPS):  # what the command started goes first (it may be writing)
        try:
            os.killpg(group, signal.SIGKILL)
        except OSError:
            pass
    try:
        sys.stdout.flush()
    except Exception:  # noqa: BLE001 - a closed or broken stdout: nothing to keep
        pass
    try:
        if os.isatty(2):  # a progress bar or status line: cleared, not left half-drawn (with the ^C echo)
            for clear in CLEAR_LINE or [lambda: os.write(2, b"\r\033[K")]:
                clear()
        import shutil

        CLEANUP_LOCK.acquire(timeout=CLEANUP_WAIT_S)  # outputs being renamed: all of them go in first
        for path in list(CLEANUP):
            if os.path.isdir(path) and not os.path.islink(path):
                shutil.rmtree(path, ignore_errors=True)
            else:
                try:
                    os.unlink(path)
                except OSError:
                    pass
    except Exception:  # noqa: BLE001 - never keep the process from ending
        pass
    line = INTERRUPTED[0].rsplit(": interrupted", 1)[0] + ": terminated" if term else INTERRUPTED[0]
    try:
        os.write(2, (line + "\n").encode())
    finally:
        os._exit(EXIT_SIGNALS.get(signum, 130) if signum is not None else 130)


def _guard_command_line_start() -> None:
    """In the command line only: a Ctrl-C or SIGTERM while the libraries load (JAX takes ~1 s to import)
    exits at once with the one line, instead of a traceback from inside an import.  A signal the
    process was started ignoring stays ignored."""
    if not command_line_process():
        return
    for sig, default in ((signal.SIGINT, signal.default_int_handler), (signal.SIGTERM, signal.SIG_DFL)):
        if signal.getsignal(sig) is default:
            try:
                signal.signal(sig, exit_interrupted)
            except ValueError:  # not the main thread: leave signals alone
                return


_guard_command_line_start()


__all__ = [
    "command_line_process",
    "INTERRUPTED",
    "CLEANUP",
    "CLEANUP_LOCK",
    "CLEANUP_WAIT_S",
    "CLEAR_LINE",
    "EXIT_SIGNALS",
    "exit_interrupted",
]
