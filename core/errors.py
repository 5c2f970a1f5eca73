"""The library's exception for a value of the wrong type (standard library only: :mod:`core.progress` and
the facade import it without numpy)."""

from __future__ import annotations

__all__ = ["InputTypeError"]


class InputTypeError(TypeError, ValueError):
    """A value of the wrong type (a str, None or a bool where a number is meant; a nested list where a
    scalar is meant).  A ``TypeError``, and also a ``ValueError`` so that a caller which reports bad
    input by catching ``ValueError`` (the command line) reports it too."""
