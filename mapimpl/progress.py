"""The one progress indicator of the project: a labelled bar on stderr for long runs (no dependency).

Use it as a callable ``progress(done, total)`` (the library functions' ``progress=`` argument) or
with a fixed total through ``update(done)`` and ``close()``.  It draws only when ``enabled`` is True
*and* its stream is a terminal (a log file or a pipe gets no carriage-return noise), always starts
with its label, and shows an ETA only once one is known (after the first completed unit).
"""

from __future__ import annotations

import sys
import time


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):  # no isatty, or a closed stream
        return False


class Progress:
    """``label [#####     ] done/total  elapsed  eta`` on stderr, redrawn at most twice a second."""

    def __init__(self, label: str, enabled: bool = True, total: int | None = None, stream=None, width: int = 30):
        if not isinstance(label, str) or not label.strip():
            raise ValueError(f"label={label!r} is out of range: allowed a non-empty string (every bar is labelled)")
        self.label, self.width = label, width
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = bool(enabled) and _is_terminal(self.stream)
        self.total = max(int(total), 1) if total is not None else None
        self.t0 = time.monotonic()
        self._last = -1.0
        self._drawn = False

    def __call__(self, done: int, total: int) -> None:
        self.total = max(int(total), 1)
        self.update(done)
        if done >= self.total:
            self.close()

    def line(self, done: int, now: float | None = None, extra: str = "") -> str:
        """The text of the bar at ``done`` units (no ETA before the first unit is done)."""
        now = time.monotonic() if now is None else now
        total = self.total if self.total is not None else max(int(done), 1)
        f = min(max(done / total, 0.0), 1.0)
        el = now - self.t0
        text = f"{self.label} [{'#' * int(f * self.width):<{self.width}}] {done}/{total} {el:6.1f}s"
        if 0 < f < 1:
            text += f" eta {el * (1 - f) / f:6.1f}s"
        return text + (f" {extra}" if extra else "")

    def update(self, done: int, extra: str = "") -> None:
        if not self.enabled or self.total is None:
            return
        now = time.monotonic()
        if done < self.total and now - self._last < 0.5:
            return
        self._last = now
        self.stream.write("\r" + self.line(done, now, extra) + "\033[K")  # clear the rest of the line
        self.stream.flush()
        self._drawn = True

    def close(self) -> None:
        """End the bar's line (only if a bar was drawn); later calls do nothing."""
        if self.enabled and self._drawn:
            self.stream.write("\n")
            self.stream.flush()
        self._drawn = False
