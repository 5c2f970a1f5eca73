"""Forward-mode differentiation over balls: a first-order jet (dual number) whose value and partial
derivatives are ``arb`` balls.

A :class:`Jet` carries ``val`` and ``der`` (one ball per independent variable).  Arithmetic and the
elementary functions the closed-form flight needs (:func:`sin`, :func:`cos`, :func:`exp`,
:func:`expm1`) propagate derivatives by the chain rule, every operation in ball arithmetic; so a
function written once over "numbers" (``arb`` or :class:`Jet`) gives, evaluated on jets seeded by
:func:`variables` over a *box* of balls, an enclosure of its Jacobian over the whole box
(:func:`jacobian`), which is what the Krawczyk operator needs (:mod:`.krawczyk`).  Plain ``arb``,
``int`` and ``float`` operands are constants (a float is its exact binary value).
"""

from __future__ import annotations

from flint import arb

from ...core.checks import MAX_PERIOD, check_int


class Jet:
    """``val + sum_k der[k] dx_k``: a value and its gradient, all balls."""

    __slots__ = ("val", "der")

    def __init__(self, val: arb, der: tuple):
        self.val, self.der = val, der

    # -- arithmetic (a non-Jet operand is a constant) -------------------------------------------
    def __add__(self, o):
        if isinstance(o, Jet):
            return Jet(self.val + o.val, tuple(a + b for a, b in zip(self.der, o.der)))
        return Jet(self.val + o, self.der)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.val, tuple(-a for a in self.der))

    def __sub__(self, o):
        if isinstance(o, Jet):
            return Jet(self.val - o.val, tuple(a - b for a, b in zip(self.der, o.der)))
        return Jet(self.val - o, self.der)

    def __rsub__(self, o):
        return Jet(o - self.val, tuple(-a for a in self.der))

    def __mul__(self, o):
        if isinstance(o, Jet):
            return Jet(self.val * o.val, tuple(a * o.val + self.val * b for a, b in zip(self.der, o.der)))
        return Jet(self.val * o, tuple(a * o for a in self.der))

    __rmul__ = __mul__

    def __truediv__(self, o):
        if isinstance(o, Jet):
            q = self.val / o.val
            return Jet(q, tuple((a - q * b) / o.val for a, b in zip(self.der, o.der)))
        return Jet(self.val / o, tuple(a / o for a in self.der))

    def __rtruediv__(self, o):
        q = o / self.val
        return Jet(q, tuple(-q * a / self.val for a in self.der))

    def __pow__(self, n: int):
        check_int("exponent", n, 1, MAX_PERIOD, strict=True)
        out = self
        for _ in range(n - 1):
            out = out * self
        return out

    def __repr__(self) -> str:
        return f"Jet({self.val}, {list(self.der)})"


def _chain(x: Jet, f: arb, df: arb) -> Jet:
    return Jet(f, tuple(df * a for a in x.der))


def sin(x):
    """``sin x`` of a ball or a jet."""
    if isinstance(x, Jet):
        s, c = x.val.sin_cos()
        return _chain(x, s, c)
    return x.sin()


def cos(x):
    """``cos x`` of a ball or a jet."""
    if isinstance(x, Jet):
        s, c = x.val.sin_cos()
        return _chain(x, c, -s)
    return x.cos()


def exp(x):
    """``exp x`` of a ball or a jet."""
    if isinstance(x, Jet):
        e = x.val.exp()
        return _chain(x, e, e)
    return x.exp()


def expm1(x):
    """``exp x - 1`` of a ball or a jet (no cancellation for small ``x``)."""
    if isinstance(x, Jet):
        return _chain(x, x.val.expm1(), x.val.exp())
    return x.expm1()


def value(x) -> arb:
    """The value (ball) of a jet or a ball."""
    return x.val if isinstance(x, Jet) else x


def variables(balls) -> list[Jet]:
    """Independent variables: one jet per ball, seeded with the unit gradients."""
    balls = list(balls)
    n = len(balls)
    zero, one = arb(0), arb(1)
    return [Jet(b, tuple(one if k == j else zero for k in range(n))) for j, b in enumerate(balls)]


def jacobian(fun, balls) -> tuple[list[arb], list[list[arb]]]:
    """``(F(X), DF(X))``: the values and the Jacobian (rows: outputs) of ``fun`` (a function of a list
    of numbers returning a list of numbers) enclosed over the box ``balls``.  An output that does
    not depend on the inputs (a plain ball) gets a zero row."""
    n = len(balls)
    out = fun(variables(balls))
    vals = [value(y) for y in out]
    rows = [list(y.der) if isinstance(y, Jet) else [arb(0)] * n for y in out]
    return vals, rows


__all__ = [
    "Jet",
    "sin",
    "cos",
    "exp",
    "expm1",
    "value",
    "variables",
    "jacobian",
]
