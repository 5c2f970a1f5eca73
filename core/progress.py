"""What a ``progress=`` argument means, and how a library function reports a stage's progress.

Every library function that runs long takes ``progress=``:

* ``None`` (default): a bar on stderr when stderr is a terminal (a log file or a pipe gets nothing),
  drawn by the function itself;
* ``True``: the same on a terminal; without one (a CI log, ``| tee``) a line per stage, at most one
  every few seconds, the phase it is in (compiling) announced -- what the command line asks for;
* ``False``: nothing;
* a callable ``progress(done, total)``: called as the work advances, and no bar is drawn (the caller
  draws: one bar per stage, never two).  A :class:`Bar` is such a callable.

A function reports a stage through a :class:`Bar` (``Bar(label, total, enabled=wanted(progress))``).
Drawing it is not the library's business: the display -- the bar on a terminal, the lines in a log --
is :mod:`gear_rattle.validation.progress`, which registers itself here (:func:`set_display`) when the
package is imported; without a display a :class:`Bar` counts nothing and draws nothing.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from .errors import InputTypeError

#: :func:`wanted`'s answer for ``progress=None``: a bar on a terminal only.
TERMINAL = "terminal"
#: :func:`wanted`'s answer for ``progress=True``: a bar on a terminal, else lines (a log).
ANYWHERE = "anywhere"


class View(Protocol):
    """What a display draws for one :class:`Bar` (see :mod:`gear_rattle.validation.progress`)."""

    def phase(self, text: str | None) -> None: ...

    def postfix(self, text: str) -> None: ...

    def update(self, done: float, total: float | None = None) -> None: ...

    def close(self) -> None: ...

    def abort(self) -> None: ...


#: The registered display: ``display(label, total=, unit=, phase=, delay=, where=)`` returns a
#: :class:`View`, or None where it draws nothing (``where``: :data:`TERMINAL` or :data:`ANYWHERE`).
_DISPLAY: list[Callable[..., View | None]] = []


def set_display(display: Callable[..., View | None] | None) -> None:
    """Register the display that draws every :class:`Bar` (None: none, bars draw nothing)."""
    if display is not None and not callable(display):
        raise TypeError(f"display={display!r} is not callable: allowed a function returning a view, or None")
    _DISPLAY[:] = [] if display is None else [display]


def check_progress(progress, name: str = "progress"):
    """``progress`` if it is one of the values of the module docstring (None, True, False or a callable),
    else ``InputTypeError`` (a ``TypeError`` and a ``ValueError``) naming ``name`` and what is allowed: a
    ``progress=5`` or ``progress="yes"`` is refused, not taken for False."""
    if progress is None or isinstance(progress, bool) or callable(progress):
        return progress
    raise InputTypeError(
        f"{name}={progress!r} is a {type(progress).__name__}: allowed None (a bar on a terminal), True, False "
        "or a callable progress(done, total)"
    )


def wanted(progress) -> str | bool:
    """Whether a function given ``progress`` draws its own bar, and where: :data:`TERMINAL` for None,
    :data:`ANYWHERE` for True, False for False or a callable (see the module docstring); anything else is
    refused (:func:`check_progress`)."""
    check_progress(progress)
    if progress is None:
        return TERMINAL
    if progress is True:
        return ANYWHERE
    return False


def sink(progress):
    """The caller's ``progress(done, total)`` callable, or None (:func:`check_progress` first)."""
    check_progress(progress)
    return progress if callable(progress) and not isinstance(progress, bool) else None


class Bar:
    """One stage's progress: ``label``, the work done of ``total`` (None: unknown; it may change, an
    estimate that improves) counted in ``unit``, the ``phase`` it is in until the first count
    (compiling, certifying), and ``delay``: seconds before anything is shown (short runs show nothing).

    ``enabled``: :func:`wanted`'s answer (``True``, as a command passes it, is :data:`ANYWHERE`).
    Drawn by the registered display (:func:`set_display`); :attr:`drawn` says whether it is.  Callable
    as ``bar(done, total)``; a context manager that closes it (aborts it on an exception)."""

    def __init__(
        self,
        label: str,
        total: float | None = None,
        unit: str = "impacts",
        enabled: bool | str = True,
        phase: str | None = None,
        delay: float = 0.0,
    ):
        if not isinstance(label, str) or not label.strip():
            raise ValueError(f"label={label!r} is out of range: allowed a non-empty string (every bar is labelled)")
        self.label = label
        self._view: Any = None
        if enabled and _DISPLAY:
            where = TERMINAL if enabled == TERMINAL else ANYWHERE
            self._view = _DISPLAY[0](label, total=total, unit=unit, phase=phase, delay=delay, where=where)

    @property
    def drawn(self) -> bool:
        """Whether this bar is drawn (enabled, a display that draws here, not closed)."""
        return self._view is not None

    def phase(self, text: str | None) -> None:
        """Show ``text`` (a phase such as compiling, which has no count) until the first count; None: back
        to the count."""
        if self._view is not None:
            self._view.phase(text)

    def postfix(self, text: str) -> None:
        """Show ``text`` after the counts (e.g. the precision of a certified run)."""
        if self._view is not None:
            self._view.postfix(text)

    def update(self, done: float, total: float | None = None) -> None:
        """``done`` units of ``total`` (None: keep the total).  The first count ends the phase shown."""
        if self._view is not None:
            self._view.update(done, total)

    def __call__(self, done: float, total: float | None = None) -> None:
        self.update(done, total)

    def close(self) -> None:
        """Finish the stage (a bar's line stays on the screen); later calls do nothing."""
        if self._view is not None:
            self._view.close()
            self._view = None

    def abort(self) -> None:
        """End the stage on an error (no half-finished bar is left on the screen)."""
        if self._view is not None:
            self._view.abort()
            self._view = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.abort() if exc[0] is not None else self.close()
        return False


__all__ = [
    "TERMINAL",
    "ANYWHERE",
    "View",
    "set_display",
    "wanted",
    "sink",
    "Bar",
]
