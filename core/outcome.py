"""Whether a result worked, said one way by every result type (as scipy's ``OdeResult`` and diffrax's
``RESULTS`` do): ``ok``, ``status`` and ``message``, all built on :class:`~gear_rattle.core.status.Status`.

* ``status`` -- the result's :class:`Status`: the label (``"active"``, ``"converged"``, ...; the files'
  spelling) for a result of one computation (:class:`~gear_rattle.core.results.ImpactSequence`,
  :class:`~gear_rattle.mapimpl.periodic.PeriodicOrbit`), an integer array of codes, one per orbit, for a
  result of many (:class:`~gear_rattle.mapimpl.lyapunov.LyapunovResult`, the transient results);
* ``ok`` -- True when every code is one of the result's :attr:`Outcome.OK_CODES` (default: the codes whose
  :attr:`Status.ok` is True);
* ``message`` -- one line: the status' message, or for many orbits the count of each code with its message.

A result type mixes in :class:`Outcome`; it has a ``status`` attribute (a field or a property) and may
narrow :attr:`Outcome.OK_CODES`.  A result type whose ``status`` is a field refuses, when it is built, a
status that is not one of its own (:func:`check_status`: ``ValueError`` naming ``status``) and arrays of
inconsistent shapes (:func:`check_lengths`), so a result never says ``ok`` about data that make no sense.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .status import NOT_OK, Status

#: The codes a result counts as worked, by default: every :class:`Status` that is an answer.
ANSWERS = frozenset(s for s in Status if s not in NOT_OK)


def status_codes(status) -> np.ndarray:
    """``status`` (a :class:`Status`, its label, its integer code, or an array of codes) as a flat int array."""
    if isinstance(status, str):
        return np.array([int(Status.from_label(status))])
    return np.atleast_1d(np.asarray(status, dtype=np.int64)).ravel()


def describe(codes: np.ndarray) -> str:
    """One line for ``codes``: the message of the one code, or ``"N orbits: k label (message); ..."``."""
    values, counts = np.unique(codes, return_counts=True)
    if codes.size == 1:
        s = Status(int(codes[0]))
        return f"{s.label}: {s.message}"
    parts = [f"{int(c)} {Status(int(v)).label} ({Status(int(v)).message})" for v, c in zip(values, counts)]
    return f"{codes.size} orbits: " + "; ".join(parts) if parts else "no orbits"


def is_ok(status, ok_codes: frozenset = ANSWERS) -> bool:
    """Whether every code of ``status`` (as :func:`status_codes` reads it) is one of ``ok_codes``."""
    return bool(np.all(np.isin(status_codes(status), [int(s) for s in ok_codes])))


def check_status(status, allowed) -> None:
    """``ValueError`` naming ``status`` unless it is the label of one of the :class:`Status` ``allowed``
    (a result of one computation) or an integer array whose every code is one of them (a result of many)."""
    labels = ", ".join(s.label for s in allowed)
    if isinstance(status, str):
        if status not in {s.label for s in allowed}:
            raise ValueError(f"status={status!r} is out of range: allowed one of {labels}")
        return
    codes = np.asarray(status)
    if codes.dtype.kind not in "iu" or not np.isin(codes, [int(s) for s in allowed]).all():
        raise ValueError(
            f"status={short_repr(status)} is out of range: allowed codes of {labels} "
            f"({', '.join(str(int(s)) for s in allowed)}), as an integer array"
        )


def check_lengths(what: str, length: int | None = None, /, **arrays) -> int:
    """The common length of the 1-D ``arrays`` (``length`` where given, else the first one's);
    ``ValueError`` naming the first that differs (``what``: whose arrays they are) otherwise."""
    first = next(iter(arrays))
    for k, v in arrays.items():
        shape = np.shape(v)
        if length is None and len(shape) == 1:
            length = shape[0]
        if shape != (length,):
            want = "a 1-D array" + (f" of length {length}" if length is not None else "")
            raise ValueError(f"{k} has shape {shape}: allowed {want} (the length of {first}; {what})")
    assert length is not None
    return length


def short_repr(value) -> str:
    """``repr(value)`` cut to 60 characters (a message naming a bad value)."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


class Outcome:
    """The ``ok`` / ``message`` of a result with a ``status`` (see the module docstring)."""

    #: The codes that count as worked for this result type.
    OK_CODES: ClassVar[frozenset] = ANSWERS

    @property
    def ok(self) -> bool:
        """Whether the computation worked: every code of ``status`` is one of :attr:`OK_CODES`."""
        return is_ok(self.status, self.OK_CODES)  # type: ignore[attr-defined]

    @property
    def message(self) -> str:
        """What ``status`` means, in one line."""
        return describe(status_codes(self.status))  # type: ignore[attr-defined]


__all__ = ["ANSWERS", "Outcome", "check_lengths", "check_status", "describe", "is_ok", "short_repr", "status_codes"]
