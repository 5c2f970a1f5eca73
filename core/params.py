"""Model parameters of Eq. (3) and their validation.

The nondimensional parameters are defined in Eqs. (4)-(6) of the paper:
``alpha`` (driving amplitude), ``beta`` (damping), ``gamma`` (constant torque term) and the
restitution coefficient ``r`` of Eq. (11).  The allowed ranges are

=========  ===================================
alpha      ``0 <= alpha <= PARAM_MAX`` (1e10)
beta       ``0 < beta <= PARAM_MAX``
gamma      ``|gamma| <= PARAM_MAX`` (any sign)
r          ``0 < r <= 1``
=========  ===================================

Why a bound (:data:`PARAM_MAX`): the map keeps the phase ``theta`` in float64, whose rounding near
``2 pi`` is ``delta ~ 4.4e-16``.  With a forcing of size ``M = alpha sqrt(1 + beta^2) + |gamma|`` the
forcing at a rounded phase is off by ``M delta``: the release from a wall (where the contact force is
zero) is decided to that level, and a tooth pressed back by a rounding-level force ``M delta`` sinks
``~ M delta^3`` into the wall before the force turns (about ``1e-47 M``), and crosses the whole gap in
``sqrt(2 / M)``.  Both stay far below the resolution of ``s`` and of the phase only while ``M`` is far
below ``1e30``; above that the float64 map misses impacts (``alpha = 1e150`` flew through the gap with
``sdot ~ 1e119``) and above ``~1e154`` squares of velocities overflow.  ``PARAM_MAX = 1e10`` keeps
``M <= ~1e20``, ten orders inside, and every kernel of the project has been run at the corners of
this box (tests/test_extremes.py).  Values near zero (down to the smallest subnormal) are allowed:
XLA on the CPU computes with subnormals flushed to zero, which changes no decision of the model
(tested against the scipy track, which keeps them).

``Params`` is the immutable, validated object used by the library and the CLI.  Kernels that are
vectorised over parameter values take :class:`ParamArrays` (a JAX pytree of float64 arrays);
:func:`validate_arrays` checks such arrays with the same rules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from . import jax_config  # noqa: F401  (enables float64)

if TYPE_CHECKING:  # JAX is imported where arrays are made, not on import (``gear-rattle check``: numpy only)
    import jax.numpy as jnp

#: The names of the model's parameters, in the order of Eqs. (3)-(6) and (11) and of :class:`Params`'s fields:
#: every module that lists them takes them from here.
PARAM_NAMES = ("alpha", "beta", "gamma", "r")

#: Largest magnitude of alpha, beta and gamma (see the module docstring: where the float64 map is valid).
PARAM_MAX = 1e10

#: Human-readable allowed range of each parameter, used in error messages.
RANGES: dict[str, str] = {
    "alpha": "0 <= alpha <= 1e10",
    "beta": "0 < beta <= 1e10",
    "gamma": "|gamma| <= 1e10",
    "r": "0 < r <= 1",
}


def _check(name: str, ok: bool, value: object) -> None:
    if not ok:
        raise ValueError(f"parameter {name}={value!r} is out of range: allowed {RANGES[name]} (finite)")


def check_value(name: str, value: float | str) -> float:
    """Validate one parameter value and return it as a Python float.

    Raises ``ValueError`` naming the parameter and its allowed range.
    """
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"parameter {name}={value!r} is not a number: allowed {RANGES[name]} (finite)") from None
    finite = math.isfinite(x)
    if name == "alpha":
        _check(name, finite and 0.0 <= x <= PARAM_MAX, value)
    elif name == "beta":
        _check(name, finite and 0.0 < x <= PARAM_MAX, value)
    elif name == "gamma":
        _check(name, finite and abs(x) <= PARAM_MAX, value)
    elif name == "r":
        _check(name, finite and 0.0 < x <= 1.0, value)
    else:  # pragma: no cover - programming error
        raise KeyError(name)
    return x


def check_param(name: str, value) -> float:
    """One parameter given as a number (a :class:`Params` field, or ``alpha, beta, gamma, r`` of a
    low-level function): ``TypeError`` (:class:`core.checks.InputTypeError`) for a str, bool, None,
    complex or non-scalar value -- no silent coercion of ``'3'`` -- else :func:`check_value`."""
    from .checks import _not_a_number, InputTypeError

    if _not_a_number(value):
        raise InputTypeError(
            f"parameter {name}={value!r} is a {type(value).__name__}: allowed a real number, {RANGES[name]}"
        )
    return check_value(name, float(value))


def check_params(params, name: str = "params") -> "Params":
    """``params`` if it is a :class:`Params`; ``TypeError`` naming the argument otherwise (a dict of
    values is not validated parameters: ``Params(**d)`` makes one)."""
    if not isinstance(params, Params):
        hint = " (make one with gear_rattle.Params(**d))" if isinstance(params, dict) else ""
        raise TypeError(f"{name} is a {type(params).__name__}: allowed a gear_rattle.Params{hint}")
    return params


class ParamArrays(NamedTuple):
    """Parameters as float64 arrays (scalars or broadcastable batches) with the field names of
    :class:`Params`: JAX arrays in the kernels, numpy arrays where per-orbit values are assembled (the
    engine's queue), the same form from the caller to the kernel."""

    alpha: jnp.ndarray | np.ndarray
    beta: jnp.ndarray | np.ndarray
    gamma: jnp.ndarray | np.ndarray
    r: jnp.ndarray | np.ndarray


@dataclass(frozen=True)
class Params:
    """Validated, immutable parameter set (alpha, beta, gamma, r) of Eqs. (3)-(6) and (11)."""

    alpha: float
    beta: float
    gamma: float
    r: float

    def __post_init__(self) -> None:
        for name in PARAM_NAMES:
            object.__setattr__(self, name, check_param(name, getattr(self, name)))

    def arrays(self) -> ParamArrays:
        """The parameters as float64 JAX scalars, for the kernels."""
        import jax.numpy as jnp

        return ParamArrays(*(jnp.asarray(v, dtype=jnp.float64) for v in (self.alpha, self.beta, self.gamma, self.r)))

    def as_dict(self) -> dict[str, float]:
        """``{"alpha": ..., "beta": ..., "gamma": ..., "r": ...}`` (the order of :data:`PARAM_NAMES`)."""
        return {k: getattr(self, k) for k in PARAM_NAMES}

    def replace(self, **changes: float) -> "Params":
        """A copy with some parameters changed (validated again)."""
        return Params(**{**self.as_dict(), **changes})


def validate_arrays(alpha, beta, gamma, r) -> ParamArrays:
    """Validate (broadcastable) arrays of parameters; raise ``ValueError`` naming the first bad one."""
    import jax.numpy as jnp

    out = []
    for name, v in zip(PARAM_NAMES, (alpha, beta, gamma, r)):
        a = np.asarray(v, dtype=np.float64)
        with np.errstate(invalid="ignore"):
            bad = ~np.isfinite(a)
            bad |= np.abs(np.where(bad, 0.0, a)) > (1.0 if name == "r" else PARAM_MAX)
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
    d = {k: np.full(v.shape, getattr(base, k)) for k in PARAM_NAMES}
    d[name] = v
    return validate_arrays(*(d[k] for k in PARAM_NAMES))


__all__ = [
    "PARAM_NAMES",
    "PARAM_MAX",
    "RANGES",
    "check_value",
    "check_param",
    "check_params",
    "ParamArrays",
    "Params",
    "validate_arrays",
    "DIAGRAM_PARAMS",
    "param_arrays",
]
