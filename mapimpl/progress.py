"""The one progress indicator of the project: a bar on stderr for long runs (no dependency).

Use it as a callable ``progress(done, total)`` (the library functions' ``progress=`` argument) or
with a fixed total through ``update(done)`` and ``close()``.  Silent when ``enabled`` is False.
"""

from __future__ import annotations

import sys
import time


class Progress:
    """``label [#####     ] done/total  elapsed  eta`` on stderr, redrawn at most twice a second."""

    def __init__(self, label: str, enabled: bool = True, total: int | None = None, stream=None, width: int = 30):
        self.label, self.enabled, self.width = label, bool(enabled), width
        self.total = max(int(total), 1) if total is not None else None
        self.stream = stream or sys.stderr
        self.t0 = time.monotonic()
        self._last = -1.0

    def __call__(self, done: int, total: int) -> None:
        self.total = max(int(total), 1)
        self.update(done)
        if done >= self.total:
            self.close()

    def update(self, done: int, extra: str = "") -> None:
        if not self.enabled or self.total is None:
            return
        now = time.monotonic()
        if done < self.total and now - self._last < 0.5:
            return
        self._last = now
        f = min(done / self.total, 1.0)
        el = now - self.t0
        eta = el * (1 - f) / f if f > 0 else float("nan")
        self.stream.write(f"\r{self.label} [{'#' * int(f * self.width):<{self.width}}] {done}/{self.total} "
                          f"{el:6.1f}s eta {eta:6.1f}s {extra}")
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()
