"""Model parameters of Eq. (3) and their validation.

The nondimensional parameters are defined in Eqs. (4)-(6) of the paper:
``alpha`` (driving amplitude), ``beta`` (damping), ``gamma`` (constant torque term) and the
restitution coefficient ``r`` of Eq. (11).  The allowed ranges are

=========  ==========================
alpha      finite, ``alpha >= 0``
beta       finite, ``beta > 0``
gamma      finite (any sign)
r          finite, ``0 < r <= 1``
=========  ==========================

``Params`` is the immutable, validated object used by the library and the CLI.  Kernels that are
vectorised over parameter values take :class:`ParamArrays` (a JAX pytree of float64 arrays);
:func:`validate_arrays` checks such arrays with the same rules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from . import _jax  # noqa: F401  (enables float64)
import jax.numpy as jnp

#: Human-readable allowed range of each parameter, used in error messages.
RANGES: dict[str, str] = {
    "alpha": "alpha >= 0",
    "beta": "beta > 0",
    "gamma": "any finite real",
    "r": "0 < r <= 1",
}


def _check(name: str, ok: bool, value: object) -> None:
    if not ok:
        raise ValueError(f"parameter {name}={value!r} is out of range: allowed {RANGES[name]} (finite)")


def check_value(name: str, value: float) -> float:
    """Validate one parameter value and return it as a Python float.

    Raises ``ValueError`` naming the parameter and its allowed range.
    """
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"parameter {name}={value!r} is not a number: allowed {RANGES[name]} (finite)") from None
    finite = math.isfinite(x)
    if name == "alpha":
        _check(name, finite and x >= 0.0, value)
    elif name == "beta":
        _check(name, finite and x > 0.0, value)
    elif name == "gamma":
        _check(name, finite, value)
    elif name == "r":
        _check(name, finite and 0.0 < x <= 1.0, value)
    else:  # pragma: no cover - programming error
        raise KeyError(name)
    return x


class ParamArrays(NamedTuple):
    """Parameters as float64 JAX arrays (scalars or broadcastable batches) for the kernels."""

    alpha: jnp.ndarray
    beta: jnp.ndarray
    gamma: jnp.ndarray
    r: jnp.ndarray


@dataclass(frozen=True)
class Params:
    """Validated, immutable parameter set (alpha, beta, gamma, r) of Eqs. (3)-(6) and (11)."""

    alpha: float
    beta: float
    gamma: float
    r: float

    def __post_init__(self) -> None:
        for name in ("alpha", "beta", "gamma", "r"):
            object.__setattr__(self, name, check_value(name, getattr(self, name)))

    def arrays(self) -> ParamArrays:
        """The parameters as float64 JAX scalars, for the kernels."""
        return ParamArrays(*(jnp.asarray(v, dtype=jnp.float64) for v in (self.alpha, self.beta, self.gamma, self.r)))

    def replace(self, **changes: float) -> "Params":
        """A copy with some parameters changed (validated again)."""
        d = {"alpha": self.alpha, "beta": self.beta, "gamma": self.gamma, "r": self.r}
        d.update(changes)
        return Params(**d)



def validate_arrays(alpha, beta, gamma, r) -> ParamArrays:
    """Validate (broadcastable) arrays of parameters; raise ``ValueError`` naming the first bad one."""
    out = []
    for name, v in (("alpha", alpha), ("beta", beta), ("gamma", gamma), ("r", r)):
        a = np.asarray(v, dtype=np.float64)
        bad = ~np.isfinite(a)
        if name == "alpha":
            bad |= a < 0
        elif name == "beta":
            bad |= a <= 0
        elif name == "r":
            bad |= (a <= 0) | (a > 1)
        if np.any(bad):
            first = a[bad].flat[0] if a.ndim else a.item()
            _check(name, False, float(first))
        out.append(jnp.asarray(a))
    return ParamArrays(*out)


#: Parameters a diagram or an exponent scan can vary (:func:`param_arrays`).
DIAGRAM_PARAMS = ("r", "alpha")


def param_arrays(base: Params, name: str, values) -> ParamArrays:
    """ParamArrays with ``name`` set to the array ``values`` (validated) and the others from ``base``."""
    if name not in DIAGRAM_PARAMS:
        raise ValueError(f"parameter {name!r} is out of range: allowed one of {DIAGRAM_PARAMS}")
    v = np.atleast_1d(np.asarray(values, dtype=np.float64))
    d = {k: np.full(v.shape, getattr(base, k)) for k in ("alpha", "beta", "gamma", "r")}
    d[name] = v
    return validate_arrays(d["alpha"], d["beta"], d["gamma"], d["r"])
