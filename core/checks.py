"""Checks of the inputs every layer validates the same way: a ``ValueError`` naming the argument and
its allowed range."""

from __future__ import annotations

import numbers

import numpy as np


def check_int(name: str, value, lo: int, hi: int, *, strict: bool = False) -> int:
    """``value`` as an int in ``[lo, hi]`` or ValueError naming ``name`` and the range.  A bool is not an
    integer; a float with an integral value is accepted unless ``strict`` (then only ``int`` and numpy
    integers are: a value that is stored and compared, e.g. an atlas spec's)."""
    integral = isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
    try:
        # (typeshed's numbers.Real has no __int__; every Real converts, Fraction included)
        v = int(value) if isinstance(value, (numbers.Real, np.integer, np.floating)) else None  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        v = None
    if v is None or isinstance(value, (bool, np.bool_)) or (strict and not integral):
        raise ValueError(f"{name}={value!r} is not an integer: allowed {lo} <= {name} <= {hi}")
    if v != value or not lo <= v <= hi:
        raise ValueError(f"{name}={value!r} is out of range: allowed an integer {lo} <= {name} <= {hi}")
    return v


#: Largest ``|tau0|`` accepted for an initial state (the transient engine's range too).  The phase
#: reduction (:func:`core.phase.reduce_phase`, a two-term Cody-Waite 2 pi) is exact only for
#: moderate arguments: at ``|tau0| = 1e6`` its error is below an ulp of tau0 (~1e-10); at 1e19 the
#: phase is garbage and at ~6e19 the whole-turn counter overflows.
TAU0_MAX = 1e6

#: The allowed range of tau0 in words (for messages).
TAU0_RANGE = "|tau0| <= " + f"{TAU0_MAX:.0e}".replace("e+0", "e")


def check_tau0(tau0: float) -> float:
    """``tau0`` as a float, or ValueError naming tau0 and the range ``|tau0| <= TAU0_MAX``."""
    try:
        t = float(tau0)
    except (TypeError, ValueError):
        t = float("nan")
    if not (np.isfinite(t) and abs(t) <= TAU0_MAX):
        raise ValueError(f"initial tau0={tau0!r} is out of range: allowed a finite real with {TAU0_RANGE}")
    return t


def start_wall(wall: int | None, sdot: float) -> int:
    """The wall of the pre-impact state ``(tau, sdot)`` a step starts from (``step_jacobian`` of every
    track): ``wall`` (0 or -1) or, if None, the one ``sdot`` points to (``sdot > 0``: 0, else -1).
    ``ValueError`` for another value."""
    if wall is None:
        return 0 if sdot > 0 else -1
    if isinstance(wall, bool) or wall not in (0, -1):
        raise ValueError(f"wall={wall!r} is out of range: allowed 0 (s = 0) or -1 (s = -1)")
    return int(wall)
