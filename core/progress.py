"""The one progress mechanism of the project: a labelled bar per stage on stderr (tqdm), counting the
work in its own unit -- impacts for orbits, so that the rate and the time left mean something -- and
showing the phase a stage is in (compiling, certifying) while it has no count yet.

Every library function that runs long takes ``progress=``:

* ``None`` (default) or ``True``: a bar on stderr when stderr is a terminal (a log file or a pipe gets
  none), drawn by the function itself;
* ``False``: nothing;
* a callable ``progress(done, total)``: called as the work advances, and no bar is drawn (the caller
  draws: one bar per stage, never two).  A :class:`Bar` is such a callable.

:func:`status` shows a line that the next bar, note or result replaces (the command line's start-up).
A Ctrl-C in the command line clears the bar's line before its one line (:func:`core._jax.exit_interrupted`).
"""

from __future__ import annotations

import os
import sys
from typing import Any

#: Seconds between redraws of a bar.
MIN_INTERVAL = 0.25
#: A bar in a phase (no count yet): its label, the phase and the time so far.
PHASE_FORMAT = "{desc} {elapsed}"


def stderr_is_terminal() -> bool:
    """Whether stderr is a terminal (bars are drawn only there)."""
    try:
        return bool(sys.stderr.isatty())
    except (AttributeError, ValueError, OSError):  # no isatty, or a closed stream
        return False


def wanted(progress) -> bool:
    """Whether a function given ``progress`` draws its own bar (see the module docstring)."""
    if progress is None or progress is True:
        return stderr_is_terminal()
    return False


def sink(progress):
    """The caller's ``progress(done, total)`` callable, or None."""
    return progress if callable(progress) and not isinstance(progress, bool) else None


_STATUS: list[str] = []


def status(text: str) -> None:
    """A transient line on stderr (a terminal only), replaced by the next bar, note or result."""
    if stderr_is_terminal():
        sys.stderr.write("\r" + text + "\033[K")
        sys.stderr.flush()
        _STATUS[:] = [text]


def clear_status() -> None:
    """Remove the :func:`status` line, if one is shown."""
    if _STATUS:
        _STATUS.clear()
        try:
            sys.stderr.write("\r\033[K")
            sys.stderr.flush()
        except (OSError, ValueError):  # pragma: no cover - a closed stderr
            pass


def _width() -> int:
    """A bar's width: the terminal's less two columns, so that the terminal's echo of Ctrl-C (``^C``)
    stays on the bar's line (on a full-width line it wraps, and clearing the line would clear the
    echo's line instead of the bar's)."""
    try:
        cols = os.get_terminal_size(sys.stderr.fileno()).columns
    except (AttributeError, ValueError, OSError):
        cols = 80
    return max(20, cols - 2)


def _clear_for_interrupt() -> None:
    """What the command line's Ctrl-C runs: wait (briefly) for a bar being drawn, then clear its line."""
    from tqdm import tqdm

    lock = tqdm.get_lock()
    got = lock.acquire(timeout=0.2)
    try:
        os.write(2, b"\r\033[K")
    finally:
        if got:
            lock.release()


class Bar:
    """One stage's bar: ``label (phase): 42%|####      | 1.2M/2.9M impacts [00:03<00:04, 3.4M impacts/s]``.

    ``total`` may be None (no ETA: count and rate only) and may change (:meth:`update`, an estimate that
    improves as the work goes on); ``phase`` is shown after the label until the first count arrives
    (or until :meth:`phase` changes it); ``delay``: seconds before the bar appears at all (short runs
    show nothing).  Drawn only when ``enabled`` and stderr is a terminal.  Callable as
    ``bar(done, total)``; a context manager that closes it."""

    def __init__(self, label: str, total: float | None = None, unit: str = "impacts", enabled: bool = True,
                 phase: str | None = None, delay: float = 0.0):
        if not isinstance(label, str) or not label.strip():
            raise ValueError(f"label={label!r} is out of range: allowed a non-empty string (every bar is labelled)")
        self.label, self._bar, self._counting = label, None, False
        if not (enabled and stderr_is_terminal()):
            return
        from tqdm import tqdm

        from . import _jax

        clear_status()
        tqdm.monitor_interval = 0  # no tqdm monitor thread
        self._bar = tqdm(total=total, desc=label if phase is None else f"{label} ({phase})", unit=" " + unit,
                         unit_scale=unit == "impacts", file=sys.stderr, ncols=_width(), mininterval=MIN_INTERVAL,
                         smoothing=0.3, delay=delay, leave=True, bar_format=None if phase is None else PHASE_FORMAT)
        if _clear_for_interrupt not in _jax.CLEAR_LINE:
            _jax.CLEAR_LINE.append(_clear_for_interrupt)
        self._ticker: tuple[Any, Any] | None = None  # (threading.Event, threading.Thread)
        self._start_ticker()

    @property
    def drawn(self) -> bool:
        """Whether this bar draws (enabled on a terminal, not closed)."""
        return self._bar is not None

    def phase(self, text: str | None) -> None:
        """Show ``label (text) elapsed`` until the first count (a phase such as compiling has no count to
        show); ``None``: back to the bar."""
        b = self._bar
        if b is None:
            return
        if text is None:
            b.bar_format = None
            b.set_description_str(self.label)
            return
        b.bar_format = PHASE_FORMAT
        b.set_description_str(f"{self.label} ({text})")

    def _start_ticker(self) -> None:
        """Redraw twice a second while the bar is open, so that its clock moves while the work has nothing
        to count (compiling, a long kernel call, a narrower block compiled for the tail)."""
        import threading

        stop, b = threading.Event(), self._bar
        if b is None:
            return

        def tick():
            while not stop.wait(0.5):
                b.refresh()

        self._ticker = (stop, threading.Thread(target=tick, name="progress-ticker", daemon=True))
        self._ticker[1].start()

    def _stop_ticker(self) -> None:
        if self._ticker is not None:
            self._ticker[0].set()
            self._ticker[1].join()
            self._ticker = None

    def postfix(self, text: str) -> None:
        """Show ``text`` after the counts (e.g. the precision of a certified run)."""
        if self._bar is not None:
            self._bar.set_postfix_str(text, refresh=False)

    def update(self, done: float, total: float | None = None) -> None:
        """``done`` units of ``total`` (None: keep the total).  The first count ends the phase shown and
        restarts the clock, so that the rate and the time left leave the phase (compilation) out."""
        b = self._bar
        if b is None:
            return
        if not self._counting:
            self._counting = True
            b.bar_format = None
            b.set_description_str(self.label, refresh=False)
            b.reset(total=total if total is not None else b.total)
        elif total is not None and total != b.total:
            b.total = total
        b.n = done
        b.refresh() if done >= (b.total or float("inf")) else b.update(0)

    def __call__(self, done: float, total: float | None = None) -> None:
        self.update(done, total)

    def close(self) -> None:
        """Finish the bar's line (it stays on the screen); later calls do nothing."""
        if self._bar is not None:
            self._stop_ticker()
            self._bar.close()
            self._bar = None

    def abort(self) -> None:
        """Remove the bar's line (an error or Ctrl-C: no half-finished bar is left on the screen)."""
        if self._bar is not None:
            self._bar.leave = False
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.abort() if exc[0] is not None else self.close()
        return False
