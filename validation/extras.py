"""Optional dependencies (the ``extras`` of ``pyproject.toml``), imported only where they are used.

A default code path imports core dependencies only.  A command that needs an extra calls
:func:`require` before it computes or writes anything; a missing extra raises :class:`MissingExtra`,
which the command line prints as one line naming the extra to install, with exit status 2.
"""

from __future__ import annotations

import importlib
from types import ModuleType

#: The extras and the modules each provides (pyproject.toml's ``[project.optional-dependencies]``).
EXTRAS = {"atlas": ("zarr", "dask", "distributed"), "bench": ("numba",), "test": ("hypothesis",)}


class MissingExtra(ImportError):
    """An optional dependency is not installed; the message names the extra that installs it."""


def require(module: str, extra: str, purpose: str) -> ModuleType:
    """Import ``module`` from the optional ``extra``; :class:`MissingExtra` if it is not installed.

    ``purpose`` completes the message: ``f"{purpose} needs the optional dependency {module}"``.
    """
    if module not in EXTRAS.get(extra, ()):
        raise ValueError(f"module {module!r} is not in the extra {extra!r}: {EXTRAS}")
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingExtra(f"{purpose} needs the optional dependency {module}: "
                           f"pip install \"gear-rattle[{extra}]\"") from None
