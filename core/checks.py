"""Checks of the inputs every layer validates the same way: one helper per kind of value, each raising a
``ValueError`` (a value out of range) or an :class:`InputTypeError` (a value of the wrong type: a
``TypeError`` that is also a ``ValueError``) that names the argument and its allowed range.

=====================  =================================================================
kind of value          helper
=====================  =================================================================
a real number          :func:`check_real` (finite, in a stated range; no str, bool, None)
a count                :func:`check_int` (an integer with a stated upper bound)
a tolerance            :func:`check_tol` (finite, ``TOL_FLOOR <= tol <= hi``)
an initial time/phase  :func:`check_tau0` (finite, ``|tau0| <= TAU0_MAX``)
a wall                 :func:`check_wall` (0: ``s = 0``; -1: ``s = -1``)
an array of reals      :func:`check_array` (finite floats, 1-D unless stated, bounded size)
a choice               :func:`check_choice` (one of a few names)
=====================  =================================================================

They run at the library's Python boundary, once per call, before any compilation or computation --
never inside traced (jitted) code: a JAX function that is also a public entry point checks its
arguments only when they are concrete values (:func:`is_traced`).  Arrays are checked with one
vectorised ``np.isfinite``.

Bounds on counts (the constants below) keep memory bounded and a run finite: an orbit keeps every
impact in memory (:data:`MAX_IMPACTS`), an average streams them (:data:`MAX_AVERAGED`).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence

import numpy as np

from .errors import InputTypeError

#: Impacts of one orbit kept in memory (``gr.orbit``, ``map_orbit``, the numerical tracks, the certified
#: orbit): ~1 GB of events at most.
MAX_IMPACTS = 10_000_000

#: Impacts streamed through an average (``gr.lyapunov``'s ``n_impacts`` and ``transient``).
MAX_AVERAGED = 50_000_000

#: Values of a parameter scanned at once (``gr.lyapunov``'s ``values``; a diagram's points).
MAX_VALUES = 20_000

#: Initial conditions of one engine call (``transient_times``, ``engine.run``): ~1.5 GB of results.
MAX_ORBITS = 20_000_000

#: Most impacts (and most driving periods) per period of a periodic orbit.
MAX_PERIOD = 100_000

#: Most iterations of a solver (Newton's ``max_iter``).
MAX_ITER = 10_000

#: Bootstrap resamples of one fit (``n_boot`` of the transient fits).
MAX_RESAMPLES = 1_000_000

#: Largest count summed over many orbits (the escapes of an exposure): every such count is exact in float64.
MAX_TOTAL = 2**53

#: Smallest tolerance accepted: a residual of float64 states of size ~2 pi cannot be asked below ~1e-15.
TOL_FLOOR = 1e-15


def _range(lo: float, hi: float, name: str, lo_open: bool = False, hi_open: bool = False) -> str:
    """`` with lo <= name <= hi`` in words (an infinite end left out; empty for no bound)."""
    if not (math.isfinite(lo) or math.isfinite(hi)):
        return ""
    parts = [" with "]
    if math.isfinite(lo):
        parts.append(f"{lo:g} {'<' if lo_open else '<='} ")
    parts.append(name)
    if math.isfinite(hi):
        parts.append(f" {'<' if hi_open else '<='} {hi:g}")
    return "".join(parts)


def _not_a_number(value) -> bool:
    """True for a value that is no real number (str, bytes, bool, None, complex, a sequence, an array of
    more than one value, any other object)."""
    if isinstance(value, (bool, np.bool_, str, bytes, complex, np.complexfloating)) or value is None:
        return True
    if isinstance(value, (numbers.Real, np.integer, np.floating)):
        return False
    if hasattr(value, "shape") and hasattr(value, "dtype"):  # a 0-d numpy or JAX array of reals
        return tuple(value.shape) != () or np.dtype(value.dtype).kind not in "iuf"
    return True


def check_real(
    name: str,
    value,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    nonzero: bool = False,
    allowed: str | None = None,
) -> float:
    """``value`` as a finite Python float with ``lo <= value <= hi`` (``<`` at an open end; ``!= 0`` with
    ``nonzero``).  :class:`InputTypeError` for a str, bool, None, complex or non-scalar value;
    ``ValueError`` for NaN, an infinity or a value out of range; both name ``name`` and the range
    (``allowed``: the range in words, default from ``lo`` and ``hi``)."""
    words = allowed or (
        "a finite real" + _range(lo, hi, name, lo_open, hi_open) + (f", {name} != 0" if nonzero else "")
    )
    if _not_a_number(value):
        raise InputTypeError(f"{name}={value!r} is a {type(value).__name__}: allowed {words}")
    x = float(value)
    ok = math.isfinite(x) and (lo < x if lo_open else lo <= x) and (x < hi if hi_open else x <= hi)
    if not ok or (nonzero and x == 0.0):
        raise ValueError(f"{name}={value!r} is out of range: allowed {words}")
    return x


def check_int(name: str, value, lo: int, hi: int, *, strict: bool = False) -> int:
    """``value`` as an int in ``[lo, hi]`` or ValueError naming ``name`` and the range.  A bool is not an
    integer; a float with an integral value is accepted unless ``strict`` (then only ``int`` and numpy
    integers are: a value that is stored and compared, e.g. an atlas spec's).  A value of another type
    (str, None, bool, complex) is an :class:`InputTypeError` (also a ValueError)."""
    integral = isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
    wrong_type = _not_a_number(value)
    try:
        v = None if wrong_type else int(value)
    except (TypeError, ValueError, OverflowError):
        v = None
    if v is None or (strict and not integral):
        err = InputTypeError if wrong_type else ValueError
        raise err(f"{name}={value!r} is not an integer: allowed {lo} <= {name} <= {hi}")
    if v != value or not lo <= v <= hi:
        raise ValueError(f"{name}={value!r} is out of range: allowed an integer {lo} <= {name} <= {hi}")
    return v


def check_tol(name: str, value, hi: float, lo: float = TOL_FLOOR) -> float:
    """A solver's tolerance: a finite float with ``lo <= value <= hi`` (default floor :data:`TOL_FLOOR`:
    below it float64 cannot tell the difference, above ``hi`` the answer would be no answer)."""
    return check_real(name, value, lo, hi)


#: Largest ``|tau0|`` accepted for an initial state (the transient engine's range too).  The phase
#: reduction (:func:`core.phase.reduce_phase`, a two-term Cody-Waite 2 pi) is exact only for
#: moderate arguments: at ``|tau0| = 1e6`` its error is below an ulp of tau0 (~1e-10); at 1e19 the
#: phase is garbage and at ~6e19 the whole-turn counter overflows.
TAU0_MAX = 1e6

#: The allowed range of tau0 in words (for messages).
TAU0_RANGE = "|tau0| <= " + f"{TAU0_MAX:.0e}".replace("e+0", "e")


def check_tau0(tau0, name: str = "tau0") -> float:
    """An initial time or phase ``name`` as a float with ``|value| <= TAU0_MAX`` (1e6)."""
    return check_real(name, tau0, -TAU0_MAX, TAU0_MAX, allowed="a finite real with " + TAU0_RANGE.replace("tau0", name))


def check_start(tau0, sdot0, s0=None, names: tuple[str, str] = ("tau0", "sdot0")) -> tuple[float, float, float | None]:
    """An initial state of an orbit as floats ``(tau0, sdot0, s0)``: with ``s0`` None a pre-impact state
    (``sdot0 != 0``: > 0 hits ``s = 0``, < 0 hits ``s = -1``), else a free state with ``-1 <= s0 <= 0``;
    ``|tau0| <= TAU0_MAX`` in both cases (every track's rule).  ``names``: the arguments' names for
    tau0 and sdot0 (a step's ``tau``, ``sdot``)."""
    nt, ns = names
    tau0 = check_tau0(tau0, nt)
    if s0 is None:
        return (
            tau0,
            check_real(
                ns,
                sdot0,
                nonzero=True,
                allowed=f"a finite real {ns} != 0 (a pre-impact state: > 0 hits s = 0, < 0 hits s = -1)",
            ),
            None,
        )
    return tau0, check_real(ns, sdot0), check_real("s0", s0, -1.0, 0.0)


#: The walls: 0 is ``s = 0``, -1 is ``s = -1``.
WALLS = (0, -1)


def check_wall(name: str, value) -> int:
    """A wall: 0 (``s = 0``) or -1 (``s = -1``) as an int; an integral float is accepted, a bool is not."""
    if _not_a_number(value):
        raise InputTypeError(f"{name}={value!r} is a {type(value).__name__}: allowed 0 (s = 0) or -1 (s = -1)")
    if value not in WALLS:
        raise ValueError(f"{name}={value!r} is out of range: allowed 0 (s = 0) or -1 (s = -1)")
    return int(value)


def start_wall(wall: int | None, sdot: float) -> int:
    """The wall of the pre-impact state ``(tau, sdot)`` a step starts from (``step_jacobian`` of every
    track): ``wall`` (0 or -1, :func:`check_wall`) or, if None, the one ``sdot`` points to (``sdot > 0``:
    0, else -1)."""
    if wall is None:
        return 0 if sdot > 0 else -1
    return check_wall("wall", wall)


def check_array(
    name: str,
    value,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    nonzero: bool = False,
    max_size: int = MAX_ORBITS,
    ndim: int | None = 1,
    allowed: str | None = None,
) -> np.ndarray:
    """``value`` (a scalar, a sequence or an array of real numbers) as a flat float64 numpy array of
    ``1 <= size <= max_size`` finite values in ``[lo, hi]`` (``!= 0`` with ``nonzero``).  ``ndim``: the
    most dimensions allowed (None: any shape, flattened).  :class:`InputTypeError` for strings, None,
    bools, complex or ragged/nested values; ``ValueError`` for NaN, infinities, out-of-range values and
    an empty or too large array -- one vectorised check, not one per element."""
    words = allowed or ("finite reals" + _range(lo, hi, name) + (f", {name} != 0" if nonzero else ""))
    shape_words = f"a scalar or a {ndim}-D sequence of " if ndim is not None else "an array of "
    kind = np.asarray(value).dtype.kind if not isinstance(value, (str, bytes)) and value is not None else "U"
    try:
        a = np.asarray(value, dtype=np.float64) if kind in "iuf" else None
    except (TypeError, ValueError):
        a = None
    if a is None:
        raise InputTypeError(f"{name}={value!r} is not an array of numbers: allowed {shape_words}{words}")
    if ndim is not None and a.ndim > ndim:
        raise InputTypeError(f"{name} has shape {a.shape}: allowed {shape_words}{words}")
    a = np.atleast_1d(a).ravel()
    if a.size == 0:
        raise ValueError(f"{name} is empty: allowed 1 to {max_size} {words}")
    if a.size > max_size:
        raise ValueError(f"{name} has {a.size} values: allowed at most {max_size} {words}")
    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(a) | (a < lo) | (a > hi)
        if nonzero:
            bad |= a == 0.0
    if bad.any():
        raise ValueError(f"{name}[{int(np.argmax(bad))}]={float(a[bad][0])!r} is out of range: allowed {words}")
    return a


def check_choice(name: str, value, choices: Sequence[str]) -> str:
    """``value`` if it is one of ``choices`` (exact names); ``ValueError`` listing them otherwise
    (:class:`InputTypeError` for a value that is not a str)."""
    if not isinstance(value, str):
        raise InputTypeError(f"{name}={value!r} is a {type(value).__name__}: allowed one of {', '.join(choices)}")
    if value not in choices:
        raise ValueError(f"{name}={value!r} is out of range: allowed one of {', '.join(choices)}")
    return value


def is_traced(*values) -> bool:
    """True when one of ``values`` is a JAX tracer: the function runs inside ``jit``/``vmap``, and its
    arguments were checked where the traced computation was entered (not here, not per element)."""
    import jax

    return any(isinstance(v, jax.core.Tracer) for v in values)


__all__ = [
    "MAX_IMPACTS",
    "MAX_AVERAGED",
    "MAX_VALUES",
    "MAX_ORBITS",
    "MAX_PERIOD",
    "MAX_ITER",
    "MAX_RESAMPLES",
    "MAX_TOTAL",
    "TOL_FLOOR",
    "InputTypeError",
    "check_real",
    "check_int",
    "check_tol",
    "TAU0_MAX",
    "TAU0_RANGE",
    "check_tau0",
    "check_start",
    "WALLS",
    "check_wall",
    "start_wall",
    "check_array",
    "check_choice",
    "is_traced",
]
