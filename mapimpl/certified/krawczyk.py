"""The Krawczyk operator: a proof that a box holds exactly one zero of a smooth system ``F(x) = 0``.

For a box ``X`` (a vector of balls) with centre ``c``, an (exact) approximate inverse ``C`` of the
Jacobian and ``DF(X)`` the Jacobian enclosed over the whole box (forward mode over balls,
:mod:`.jets`), the Krawczyk operator is

    K(X) = c - C F(c) + (I - C DF(X)) (X - c).

If ``K(X)`` lies in the interior of ``X``, then ``F`` has **exactly one** zero in ``X``, it lies in
``K(X)``, and every matrix in ``DF(X)`` is invertible (Krawczyk 1969; Moore, Kearfott and Cloud,
*Introduction to Interval Analysis*, SIAM 2009, Thm. 8.2 and Sec. 8.2).  :func:`krawczyk` applies it
to a box around a high-precision Newton point (:func:`newton`), so the enclosure is ``K(X)``, of the
width of the rounding errors of the working precision; :func:`verify_box` applies it to a given box
(e.g. the decimal intervals of a golden file) and thereby proves that box.

The result records the contraction: ``max_i rad(K_i)/rad(X_i)`` and an upper bound of
``||I - C DF(X)||_inf`` (< 1 is the classical contraction condition, which inclusion implies).
"""

from __future__ import annotations

from dataclasses import dataclass

from flint import arb, arb_mat, ctx

from .balls import CertificationError, span
from .jets import jacobian

#: Newton iterations allowed before :func:`newton` gives up.
MAX_NEWTON = 60


@dataclass
class KrawczykResult:
    """A certified zero: ``box`` (``K(X)``, holding the unique zero of ``F`` in ``X``), the Newton
    ``center``, the tried box ``X`` (``trial``), ``contraction`` (``max_i rad(K_i)/rad(X_i)``),
    ``norm`` (an upper bound of ``||I - C DF(X)||_inf``), ``residual`` (an upper bound of
    ``|F(center)|_inf``), ``inverse`` (``C`` as float64 rows: the conditioning of the zero) and the
    working precision ``prec``."""

    box: list
    center: list
    trial: list
    contraction: float
    norm: float
    residual: float
    inverse: list
    prec: int


def _mat(rows) -> arb_mat:
    return arb_mat([list(r) for r in rows])


def _col(v) -> arb_mat:
    return arb_mat(len(v), 1, list(v))


def _mid_inverse(rows) -> arb_mat:
    """An exact approximate inverse of a (ball) matrix: the midpoints of the ball inverse of its midpoint."""
    try:
        return _mat(rows).mid().inv().mid()
    except ZeroDivisionError:
        raise CertificationError("the Jacobian is singular at the Newton point") from None


#: Bits below the working precision dropped from the Newton point (:func:`canonical`).
CANONICAL_DROP = 48


def canonical(x: arb, bits: int) -> arb:
    """The exact ``x`` rounded to ``bits`` significant bits (nearest): Newton runs from different
    guesses end within ~2^-(prec - 16) of the zero and of each other, so their rounded points agree
    (unless the zero lies that close to a rounding boundary, a chance of ~2^-32), and so does all that
    is computed from them."""
    man, exp = (int(v) for v in x.man_exp())
    k = abs(man).bit_length() - bits
    if k > 0:
        mag = (abs(man) + (1 << (k - 1))) >> k
        man, exp = (mag if man > 0 else -mag), exp + k
    return arb(man) * arb(2) ** exp


def newton(fun, x0, max_iter: int = MAX_NEWTON) -> list:
    """Newton's method at the working precision on exact midpoints, from the guess ``x0`` (floats or
    balls); stops when the step is below ``2^-(prec - 16)`` of the scale.  Returns exact balls,
    rounded to ``prec -`` :data:`CANONICAL_DROP` bits (:func:`canonical`).  The result is only a
    candidate: :func:`krawczyk` proves it."""
    x = [arb(arb(v).mid()) for v in x0]
    tiny = arb(2) ** (-(ctx.prec - 16))
    for _ in range(max_iter):
        vals, rows = jacobian(fun, x)
        step = _mid_inverse(rows) * _col([v.mid() for v in vals])
        x = [(xi - step[i, 0]).mid() for i, xi in enumerate(x)]
        if all(abs(step[i, 0]) < tiny * (abs(xi) + 1) for i, xi in enumerate(x)):
            return [canonical(arb(v), ctx.prec - CANONICAL_DROP) for v in x]
    raise CertificationError(f"Newton did not converge in {max_iter} iterations from the guess")


def _image(fun, box, c):
    """``(K(box), I - C DF(box), C, F(c))`` for the centre ``c`` (exact balls)."""
    n = len(box)
    fc = [arb(v) for v in fun(c)]
    if len(fc) != n:
        raise ValueError(f"the system has {len(fc)} equations in {n} unknowns: allowed a square system")
    _, rows = jacobian(fun, box)
    C = _mid_inverse(jacobian(fun, c)[1])
    A = _identity(n) - C * _mat(rows)
    K = _col(c) - C * _col(fc) + A * _col([b - ci for b, ci in zip(box, c)])
    return [K[i, 0] for i in range(n)], A, C, fc


def verify_box(fun, box, center=None) -> KrawczykResult:
    """Krawczyk's test on the box ``box`` (balls); ``center`` (exact) defaults to the box's midpoints.
    Raises :class:`CertificationError` unless ``K(box)`` lies in the interior of ``box``."""
    n = len(box)
    c = [arb(b.mid()) for b in box] if center is None else [arb(v) for v in center]
    K, A, C, fc = _image(fun, box, c)
    bad = [i for i in range(n) if not box[i].contains_interior(K[i])]
    if bad:
        raise CertificationError(f"Krawczyk test failed: K(X) is not inside X in components {bad}")
    norm = max(sum(A[i, k].abs_upper() for k in range(n)) for i in range(n))
    contraction = max(float(K[i].rad()) / float(box[i].rad()) for i in range(n))
    residual = max(float(v.abs_upper()) for v in fc)
    inverse = [[float(C[i, k]) for k in range(n)] for i in range(n)]
    return KrawczykResult(K, c, list(box), contraction, float(norm.upper()), residual, inverse, ctx.prec)


def refine(fun, box, steps: int = 4) -> list:
    """Narrow an enclosure of the unique zero in ``box`` (a box that passed :func:`verify_box`):
    ``X <- K(X) /\\ X`` (every zero of ``F`` in ``X`` lies in ``K(X)``, inclusion or not), ``steps``
    times or until the radius stops halving."""
    for _ in range(int(steps)):
        K, _, _, _ = _image(fun, box, [arb(b.mid()) for b in box])
        new = []
        for k, b in zip(K, box):
            if not k.overlaps(b):  # pragma: no cover - cannot happen when box holds a zero
                raise CertificationError("refine: K(X) and X are disjoint (no zero in X)")
            new.append(k.intersection(b))
        shrunk = max(float(a.rad()) for a in new) < 0.5 * max(float(b.rad()) for b in box)
        box = new
        if not shrunk:
            break
    return box


def _identity(n: int) -> arb_mat:
    return arb_mat([[1 if i == k else 0 for k in range(n)] for i in range(n)])


def krawczyk(fun, x0, *, radius_bits: int | None = None, tries: int = 6) -> KrawczykResult:
    """Newton from ``x0``, then Krawczyk's test on the box of relative radius ``2^-radius_bits``
    (default half the working precision) around the Newton point; the radius grows by ``2^16``
    per failed try (a box too small to hold the rounding errors of ``F(c)``)."""
    c = newton(fun, x0)
    bits = ctx.prec // 2 if radius_bits is None else int(radius_bits)
    last = None
    for _ in range(tries):
        rad = arb(2) ** (-bits)
        box = [span(ci - rad * (abs(ci) + 1), ci + rad * (abs(ci) + 1)) for ci in c]
        try:
            return verify_box(fun, box, c)
        except CertificationError as e:
            last = e
            bits -= 16
            if bits < 8:
                break
    raise CertificationError(f"no Krawczyk box around the Newton point: {last}")


__all__ = [
    "MAX_NEWTON",
    "KrawczykResult",
    "CANONICAL_DROP",
    "canonical",
    "newton",
    "verify_box",
    "refine",
    "krawczyk",
]
