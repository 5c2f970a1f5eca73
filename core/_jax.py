"""The old, private name of :mod:`gear_rattle.core.jax_config` (the project's JAX set-up), kept importable
for the modules that still import it by that name; new code imports ``core.jax_config``.  Importing it
switches JAX to float64, as importing ``jax_config`` does."""

from .jax_config import *  # noqa: F403
from .jax_config import __all__  # noqa: F401
