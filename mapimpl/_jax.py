"""Import side effect: JAX runs in float64 everywhere in this project (``jax_enable_x64``)."""

import jax

jax.config.update("jax_enable_x64", True)
