"""Balls and precision: the helpers every certified computation uses (python-flint ``arb``).

A ball ``[m +- r]`` encloses a real number; python-flint's ``ctx.prec`` is the working precision in
bits (:func:`precision` sets it for a block).  Decisions on balls are definite or raise
:class:`CertificationError`: a certified computation never guesses.
"""

from __future__ import annotations

import math
from contextlib import contextmanager

from flint import arb, ctx

from ...core.checks import InputTypeError, check_int

#: Default working precision in bits (about 96 decimal digits).
PREC = 320
#: Highest working precision accepted (bits).
MAX_PREC = 1 << 16


class CertificationError(RuntimeError):
    """The enclosure could not be certified (ambiguous decision, grazing, budget exhausted)."""


def check_prec(bits, name: str = "prec") -> int:
    """A working precision in bits (the argument ``name``): an integer ``64 <= bits <= MAX_PREC``
    (:func:`core.checks.check_int`)."""
    return check_int(name, bits, 64, MAX_PREC, strict=True)


def check_ball(name: str, x) -> arb:
    """``x`` if it is a finite ball (``arb``); ``TypeError`` (:class:`core.checks.InputTypeError`) for
    another type, ``ValueError`` for a ball that is not finite, naming ``name``."""
    if not isinstance(x, arb):
        raise InputTypeError(f"{name}={x!r} is a {type(x).__name__}: allowed a finite ball (flint.arb)")
    if not x.is_finite():
        raise ValueError(f"{name}={x!r} is out of range: allowed a finite ball (flint.arb)")
    return x


@contextmanager
def precision(bits: int):
    """Temporarily set python-flint's working precision."""
    bits = check_prec(bits)
    old = ctx.prec
    ctx.prec = bits
    try:
        yield
    finally:
        ctx.prec = old


def exact(x: float) -> arb:
    """The float64 ``x`` as an exact ball."""
    return arb(float(x))


def span(a: arb, b: arb) -> arb:
    """The ball enclosing ``[a, b]`` (``a``, ``b`` balls)."""
    return a.union(b)


def upper_float(x: arb) -> float:
    """A float64 ``>= `` every point of the ball ``x`` (rounded up)."""
    u = float(x.upper())
    return math.nextafter(u, math.inf)


def float_bounds(x: arb) -> tuple[float, float]:
    """The float64 interval ``[lo, hi]`` that contains the ball ``x``, as narrow as float64 allows:
    ``lo`` is the largest float64 ``<=`` every point of ``x``, ``hi`` the smallest ``>=`` (each end
    rounded outward exactly, so at most one ulp beyond the ball's end)."""
    if not x.is_finite():
        raise ValueError(f"x={x!r} is out of range: allowed a finite ball")
    lo_end, hi_end = x.lower(), x.upper()
    lo, hi = float(lo_end), float(hi_end)
    while arb(lo) > lo_end:  # float() may round the exact end either way: step outward until it is below
        lo = math.nextafter(lo, -math.inf)
    while arb(hi) < hi_end:
        hi = math.nextafter(hi, math.inf)
    return lo, hi


def nearest_float(x: arb) -> float:
    """The float64 nearest to the ball's midpoint (40-digit decimal, then correctly rounded)."""
    return float(x.mid().str(45, radius=False))


def mod_two_pi(tau: arb) -> arb:
    """``tau mod 2 pi`` as a ball; raises if the ball straddles a multiple of ``2 pi``."""
    two_pi = 2 * arb.pi()
    k = (tau / two_pi).floor()
    if not k.is_exact():
        raise CertificationError("tau mod 2 pi: the ball straddles a multiple of 2 pi")
    return tau - k * two_pi


def _decimal(x: arb, digits: int, rounding: str) -> str:
    """The exact number ``x`` (an exact ball) rounded to ``digits`` significant decimal digits in the
    direction ``rounding`` (``decimal.ROUND_FLOOR`` or ``ROUND_CEILING``)."""
    import decimal

    man_f, exp_f = x.man_exp()
    man, exp = int(man_f), int(exp_f)
    with decimal.localcontext() as c:
        c.prec = max(50, abs(exp) + len(str(abs(man))) + 10)  # exact: man * 2^exp has that many digits
        c.Emax, c.Emin = decimal.MAX_EMAX, decimal.MIN_EMIN
        exact_value = decimal.Decimal(man) * decimal.Decimal(2) ** exp
        c.prec, c.rounding = digits, rounding
        return str(+exact_value)


def decimal_interval(x: arb, digits: int = 20) -> tuple[str, str]:
    """Decimal strings ``(lo, hi)`` with ``digits`` significant digits such that the decimal interval
    ``[lo, hi]`` contains the ball ``x`` (the ball's ends rounded outward, exactly)."""
    import decimal

    check_int("digits", digits, 1, 1000, strict=True)
    check_ball("x", x)
    return _decimal(x.lower(), digits, decimal.ROUND_FLOOR), _decimal(x.upper(), digits, decimal.ROUND_CEILING)


__all__ = [
    "PREC",
    "MAX_PREC",
    "CertificationError",
    "check_prec",
    "check_ball",
    "precision",
    "exact",
    "span",
    "upper_float",
    "float_bounds",
    "nearest_float",
    "mod_two_pi",
    "decimal_interval",
]
