"""The deprecation path of the library's old spellings: an old keyword argument or attribute keeps working
with a ``DeprecationWarning`` that names the new spelling (the names of today: docs/architecture.md,
"One public vocabulary")."""

from __future__ import annotations

import warnings

from .checks import InputTypeError


class _Unset:
    """The type of :data:`UNSET`."""

    def __repr__(self) -> str:
        return "UNSET"


#: The value a keyword argument has when the caller did not give it (distinct from None).
UNSET: object = _Unset()


def warn_renamed(old: str, new: str, stacklevel: int = 3) -> None:
    """A DeprecationWarning: ``old`` is now spelled ``new`` (same meaning)."""
    warnings.warn(f"{old} is deprecated: use {new} (same meaning)", DeprecationWarning, stacklevel=stacklevel)


def renamed_argument(old: str, new: str, value, old_value, default):
    """The value of the keyword argument ``new`` whose old name was ``old``: ``old_value`` (with a
    DeprecationWarning) when only the old name was given, ``default`` when neither was; ``TypeError`` when
    both were.  :data:`UNSET` marks an argument not given."""
    if old_value is UNSET:
        return default if value is UNSET else value
    if value is not UNSET:
        raise InputTypeError(f"give {new}= or its old name {old}=, not both")
    warn_renamed(f"{old}=", f"{new}=", stacklevel=4)
    return old_value


def renamed_attribute(old: str, new: str):
    """A read-only property ``old`` that returns the attribute ``new`` with a DeprecationWarning."""

    def get(self):
        warn_renamed(f"{type(self).__name__}.{old}", f".{new}")
        return getattr(self, new)

    return property(get, doc=f"Deprecated: the old name of :attr:`{new}`.")


def renamed_names(module: str, names: dict[str, str], namespace: dict):
    """A module's ``__getattr__`` (PEP 562) for the old names of its objects: ``names`` maps an old name to
    the object's name today in ``namespace`` (the module's ``globals()``); the old name returns that object
    with a DeprecationWarning naming the new one, any other name raises ``AttributeError``."""

    def __getattr__(name: str):
        if name in names:
            warn_renamed(f"{module}.{name}", f"{module}.{names[name]}")
            return namespace[names[name]]
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__


__all__ = ["UNSET", "renamed_argument", "renamed_attribute", "renamed_names", "warn_renamed"]
