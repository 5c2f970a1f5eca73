"""Batches of orbits: the map (Eqs. 12-13) vmapped over initial conditions (and, optionally,
parameters), jit-compiled, float64.  A batch gives the single-orbit numbers to rounding: the
same scalar kernel is vmapped, but XLA compiles the vectorised program separately, so results can
differ by a few ulps per step (and chaotic orbits then diverge at their Lyapunov rate).
"""

from __future__ import annotations

from functools import partial

import numpy as np

from ..core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from .impact_map import iterate, step
from ..core.state import MapState, Trajectory, make_state
from ..core.params import PARAM_NAMES, ParamArrays, Params


def states(tau, sdot, wall=None) -> MapState:
    """Batch of pre-impact states from arrays (wall from the sign of ``sdot`` unless given)."""
    return make_state(jnp.asarray(tau, jnp.float64), jnp.asarray(sdot, jnp.float64), wall)


def _param_axes(p: ParamArrays):
    return ParamArrays._make(0 if jnp.ndim(x) else None for x in p)  # vmap's in_axes for each parameter


@partial(jax.jit, static_argnums=(2,))
def batch_iterate(s: MapState, p: ParamArrays, n: int) -> Trajectory:
    """``n`` map steps for every orbit of the batch, recording all states (shape ``(batch, n)``).

    Parameters may be scalars or arrays of the batch length.
    """
    return jax.vmap(iterate, in_axes=(0, _param_axes(p), None))(s, p, n)


@partial(jax.jit, static_argnums=(2,))
def batch_advance(s: MapState, p: ParamArrays, n: int) -> MapState:
    """``n`` map steps for every orbit of the batch, returning only the final states (no history)."""

    def one(st, pp):
        return jax.lax.fori_loop(0, n, lambda _, x: step(x, pp)[0], st)

    return jax.vmap(one, in_axes=(0, _param_axes(p)))(s, p)


def params_batch(params: list[Params] | None = None, **arrays) -> ParamArrays:
    """ParamArrays for a batch, from a list of Params or validated arrays (alpha=..., ...)."""
    from ..core.params import validate_arrays

    if params is not None:
        arrays = {k: np.array([getattr(q, k) for q in params]) for k in PARAM_NAMES}
    return validate_arrays(*(arrays[k] for k in PARAM_NAMES))


__all__ = [
    "states",
    "batch_iterate",
    "batch_advance",
    "params_batch",
]
