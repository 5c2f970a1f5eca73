"""Validation harness: cross-track agreement, reproduction of the paper's figures and numbers,
the CLI (``gear-rattle``) and the generated validation report."""

from . import interrupt  # noqa: F401  (first: the command line's Ctrl-C and SIGTERM)
from . import progress  # noqa: F401  (the display of every progress bar: core.progress)
from ..core import jax_config  # noqa: F401
