"""Validation harness: cross-track agreement, reproduction of the paper's figures and numbers,
the CLI (``gear-rattle``) and the generated validation report."""

from ..core import _jax  # noqa: F401
