"""Closed-form track: the flight solution (Eqs. 7-8) and the impact map (Eqs. 12-13).

Importing this package switches JAX to float64 (``jax_enable_x64``).
"""

from ..core import jax_config  # noqa: F401
from ..core.params import ParamArrays, Params, validate_arrays
from ..core.paper import PAPER_FIG3

__all__ = ["Params", "ParamArrays", "PAPER_FIG3", "validate_arrays"]
