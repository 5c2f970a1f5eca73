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
        raise MissingExtra(
            f'{purpose} needs the optional dependency {module}: pip install "gear-rattle[{extra}]"'
        ) from None


#: What the full install adds to numpy (pyproject.toml's ``dependencies``, by import name): a light
#: install (``pip install --no-deps gear-rattle numpy``) scores files with ``gear-rattle check`` only.
FULL_INSTALL = ("jax", "jaxlib", "scipy", "diffrax", "optimistix", "equinox", "matplotlib", "flint", "tqdm")


def require_full_install(what: str) -> None:
    """:class:`MissingExtra` (one line: what is missing and ``pip install gear-rattle``) where a module
    of :data:`FULL_INSTALL` cannot be found -- a light install -- before ``what`` computes anything."""
    import importlib.util

    missing = []
    for m in FULL_INSTALL:
        try:
            if importlib.util.find_spec(m) is None:
                missing.append(m)
        except (ImportError, ValueError):  # blocked in sys.modules (None), or a broken install
            missing.append(m)
    if missing:
        raise MissingExtra(
            f"{what} needs {', '.join(missing)} (not installed; this install scores files with "
            "`gear-rattle check` only): pip install gear-rattle"
        )


__all__ = [
    "EXTRAS",
    "MissingExtra",
    "require",
    "FULL_INSTALL",
    "require_full_install",
]
