"""A minimal progress indicator on stderr for long runs (CLI only)."""

from __future__ import annotations

import sys
import time


class Progress:
    """Callable ``progress(done, total)`` printing ``label: 42% (done/total) 3.1 s`` on stderr."""

    def __init__(self, label: str, enabled: bool = True, stream=None):
        self.label, self.enabled = label, enabled
        self.stream = stream or sys.stderr
        self.t0 = time.monotonic()
        self._last = -1.0

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        if done < total and now - self._last < 0.5:
            return
        self._last = now
        pct = 100.0 * done / max(total, 1)
        end = "\n" if done >= total else ""
        self.stream.write(f"\r{self.label}: {pct:5.1f}% ({done}/{total}) {now - self.t0:.1f} s{end}")
        self.stream.flush()
