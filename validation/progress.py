"""The display of progress (the command line's UI): what draws every :class:`gear_rattle.core.progress.Bar`.

* On a terminal, a labelled bar per stage on stderr (tqdm, :class:`TerminalBar`), counting the work in
  its own unit -- impacts for orbits, so that the rate and the time left mean something -- and showing
  the phase a stage is in (compiling, certifying) while it has no count yet.
* Without a terminal (a CI log, ``| tee``), for ``progress=True`` (the command line) and the command
  line's own stages: lines (:class:`LogLines`) -- a stage that lasts longer than :data:`LOG_FIRST_S`
  writes a line that names it and the phase it is in (``engine: compiling, 3 s``), then at most one
  line every :data:`LOG_INTERVAL_S` seconds (count, rate, time left) and a last line when it ends; a
  shorter stage writes nothing.  ``GEAR_RATTLE_PROGRESS_LINES=0`` turns the lines off (:data:`LINES_ENV`).

What ``progress=`` means is :mod:`gear_rattle.core.progress` (the library's side: it reports, this
module draws); importing this module registers :func:`display` there (``gear_rattle.validation``
imports it; the package's facade registers a stand-in that imports this module when the first bar is
drawn, so that ``import gear_rattle`` does not load it).  :func:`status` shows a line that the next bar,
note or result replaces (the command line's start-up).  A Ctrl-C in the command line clears the bar's
line before its one line (:func:`gear_rattle.validation.interrupt.exit_interrupted`).
"""

from __future__ import annotations

import os
import sys
import threading
import time
from typing import Any

from ..core import progress as _core
from . import interrupt

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


class TerminalBar:
    """One stage's bar on a terminal: ``label (phase): 42%|####      | 1.2M/2.9M impacts [00:03<00:04,
    3.4M impacts/s]`` (tqdm).  ``total`` may be None (no ETA: count and rate only) and may change
    (:meth:`update`); ``phase`` is shown after the label until the first count (or until :meth:`phase`
    changes it); ``delay``: seconds before the bar appears at all (short runs show nothing)."""

    def __init__(
        self,
        label: str,
        total: float | None = None,
        unit: str = "impacts",
        phase: str | None = None,
        delay: float = 0.0,
    ):
        from tqdm import tqdm

        self.label, self._counting = label, False
        clear_status()
        tqdm.monitor_interval = 0  # no tqdm monitor thread
        self._bar: Any = tqdm(
            total=total,
            desc=label if phase is None else f"{label} ({phase})",
            unit=" " + unit,
            unit_scale=unit == "impacts",
            file=sys.stderr,
            ncols=_width(),
            mininterval=MIN_INTERVAL,
            smoothing=0.3,
            delay=delay,
            leave=True,
            bar_format=None if phase is None else PHASE_FORMAT,
        )
        if _clear_for_interrupt not in interrupt.CLEAR_LINE:
            interrupt.CLEAR_LINE.append(_clear_for_interrupt)
        self._ticker: tuple[Any, Any] | None = None  # (threading.Event, threading.Thread)
        self._start_ticker()

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


#: Environment variable: ``0`` turns the lines off (stderr that is not a terminal then gets no progress).
LINES_ENV = "GEAR_RATTLE_PROGRESS_LINES"
#: Without a terminal: seconds a stage runs before its first line (a shorter stage writes none).
LOG_FIRST_S = 5.0
#: Without a terminal: the least number of seconds between two lines of one stage.
LOG_INTERVAL_S = 10.0


def _count(x: float, unit: str) -> str:
    """``1.2M`` for impacts (SI prefixes, as the bar), a plain integer otherwise."""
    if unit == "impacts":
        for div, p in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
            if abs(x) >= div:
                return f"{x / div:.3g}{p}"
    return f"{x:.0f}"


class LogLines:
    """One stage's progress as lines on stderr, for a log (see the module docstring): ``label: phase,
    12 s``; ``label: 1.2M/2.9M impacts (41%), 3.4M impacts/s, 5 s left``; ``label: done, 2.9M impacts
    in 9.1 s``.  A ticker thread writes the lines of a stage that has nothing to count (a compilation)."""

    def __init__(
        self,
        label: str,
        total: float | None = None,
        unit: str = "impacts",
        phase: str | None = None,
        delay: float = 0.0,
    ):
        self.label, self.total, self.unit, self._phase = label, total, unit, phase
        self.done: float = 0.0
        self._post = ""
        self._t0 = self._tc = time.monotonic()  # start; start of the count (the phase left out of the rate)
        self._first = max(float(delay), LOG_FIRST_S)
        self._last: float | None = None  # when the last line was written
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._ticker = threading.Thread(target=self._tick, name="progress-log", daemon=True)
        self._ticker.start()

    def _tick(self) -> None:
        while not self._stop.wait(0.5):
            self._maybe_line()

    def _text(self, now: float) -> str:
        if self._phase is not None:
            return f"{self._phase}, {now - self._t0:.0f} s"
        n, total, unit = self.done, self.total, self.unit
        text = f"{_count(n, unit)}/{_count(total, unit)} {unit}" if total else f"{_count(n, unit)} {unit}"
        if total:
            text += f" ({100 * n / total:.0f}%)"
        dt = now - self._tc
        if dt > 0 and n > 0:
            rate = n / dt
            text += f", {_count(rate, unit)} {unit}/s"
            if total and total > n:
                text += f", {(total - n) / rate:.0f} s left"
        return text + (f", {self._post}" if self._post else "")

    def _write(self, text: str) -> None:
        try:
            sys.stderr.write(f"{self.label}: {text}\n")
            sys.stderr.flush()
        except (OSError, ValueError):  # pragma: no cover - a closed stderr
            pass

    def _maybe_line(self) -> None:
        with self._lock:
            now = time.monotonic()
            if now - self._t0 < self._first:
                return
            if self._last is not None and now - self._last < LOG_INTERVAL_S:
                return
            self._last = now
            self._write(self._text(now))

    def phase(self, text: str | None) -> None:
        """A new phase (None: back to the count), written at once if the stage has written lines."""
        with self._lock:
            changed, self._phase = text != self._phase, text
        if changed and text is not None and self._last is not None:
            with self._lock:
                self._last = time.monotonic()
                self._write(self._text(self._last))

    def postfix(self, text: str) -> None:
        """``text`` after the counts of the next line."""
        self._post = text

    def update(self, done: float, total: float | None = None) -> None:
        """``done`` units of ``total`` (None: keep it); the first count ends the phase (and restarts the
        clock of the rate)."""
        with self._lock:
            if self._phase is not None:
                self._phase, self._tc = None, time.monotonic()
            self.done = done
            if total is not None:
                self.total = total
        self._maybe_line()

    def _end(self, word: str) -> None:
        self._stop.set()
        self._ticker.join()
        with self._lock:
            if self._last is not None:  # a stage that wrote lines says that it ended
                dt = time.monotonic() - self._t0
                count = f"{_count(self.done, self.unit)} {self.unit} " if self.done else ""
                self._write(f"{word}, {count}in {dt:.1f} s")
                self._last = None

    def close(self) -> None:
        """The stage's last line (if it wrote any)."""
        self._end("done")

    def abort(self) -> None:
        """The stage stopped on an error: its last line says so (if it wrote any)."""
        self._end("stopped")


def display(
    label: str,
    *,
    total: float | None = None,
    unit: str = "impacts",
    phase: str | None = None,
    delay: float = 0.0,
    where: str = _core.TERMINAL,
):
    """The view of one :class:`gear_rattle.core.progress.Bar` (registered there by this module): a
    :class:`TerminalBar` when stderr is a terminal, :class:`LogLines` when it is not, ``where`` is
    :data:`gear_rattle.core.progress.ANYWHERE` and ``$GEAR_RATTLE_PROGRESS_LINES`` is not ``0``, else
    None (nothing drawn)."""
    if stderr_is_terminal():
        return TerminalBar(label, total, unit, phase, delay)
    if where == _core.ANYWHERE and os.environ.get(LINES_ENV, "1").strip() != "0":
        return LogLines(label, total, unit, phase, delay)
    return None


_core.set_display(display)


__all__ = [
    "MIN_INTERVAL",
    "PHASE_FORMAT",
    "stderr_is_terminal",
    "status",
    "clear_status",
    "TerminalBar",
    "LINES_ENV",
    "LOG_FIRST_S",
    "LOG_INTERVAL_S",
    "LogLines",
    "display",
]
