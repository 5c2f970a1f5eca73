"""Verdicts of the report's summary rows, in one place: every row of every section is judged here.

* A **value** the paper states (``kind`` ``value``, ``approx``, ``theory`` or ``derived`` in
  :mod:`.paper`) is compared by its z-score ``z = (computed - paper) / sigma`` with
  ``sigma = sqrt(error_ours^2 + sigma_paper^2)``; ``sigma_paper`` is the paper's stated error, or,
  where it states none, the rounding of its last printed digit (:attr:`.paper.PaperValue.sigma`).
  The row **agrees** when ``|z| <= 2`` (:data:`Z_AGREE`), else it **disagrees**; the deviation and z
  are always printed.  A ``count`` (e.g. impacts per driving period) must be equal.
* A **bound** (``upper_bound``: the quantity must be ``<=`` the printed value; ``lower_bound``: ``>=``)
  is checked strictly in its direction against the printed value, which is the parameter the paper
  ran, not a rounded result; the margin (and its size in units of our error bar, where we have one)
  is printed either way.
* A **qualitative** statement (e.g. "regular") agrees when the computed category is the same word.
* A quantity the paper does not state (an internal check of this implementation) is **not
  compared**; where it has a stated tolerance, it gets a separate ``check`` of ``pass``/``fail``.

:func:`row` builds a summary row (:class:`.document.Number`) from a key, the computed value and its
error, the paper value (or ``None``) and an explanation; adding a row to the report is one call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

from ..paper import PAPER, PaperValue

AGREES, DISAGREES, NOT_COMPARED = "agrees", "disagrees", "not compared"
VERDICTS = (AGREES, DISAGREES, NOT_COMPARED)
#: |z| at or below which a value agrees with the paper's.
Z_AGREE = 2.0
PASS, FAIL = "pass", "fail"


@dataclass(frozen=True)
class Verdict:
    """The outcome of one comparison: ``verdict`` (one of :data:`VERDICTS`), the signed ``deviation``
    computed - paper, ``z`` = deviation / ``sigma`` (``None`` where there is no error bar), the
    combined ``sigma``, ``text`` (the deviation column), and for internal checks ``check``
    (``"pass"``/``"fail"``) against ``tolerance``."""

    verdict: str
    deviation: float | None = None
    z: float | None = None
    sigma: float | None = None
    text: str = ""
    check: str | None = None
    tolerance: float | None = None


def _num(x, name: str) -> float:
    if isinstance(x, bool) or not isinstance(x, Real):
        raise ValueError(f"{name}={x!r} is out of range: allowed a real number")
    return float(x)


def _err(error) -> float:
    if error is None:
        return 0.0
    e = _num(error, "error")
    if not (math.isfinite(e) and e >= 0):
        raise ValueError(f"error={error!r} is out of range: allowed a finite error >= 0 or None")
    return e


def _rel(d: float, ref: float) -> str:
    return f" ({d / ref:+.2%})" if ref else ""


def compare_value(computed, error, paper: PaperValue) -> Verdict:
    """z-score comparison of a computed value (with its standard error, or ``None``) with a paper value."""
    c = _num(computed, "computed")
    p = float(paper.value)
    d = c - p
    if paper.kind == "count":  # exact
        ok = d == 0
        return Verdict(AGREES if ok else DISAGREES, d, None, None,
                       "equal" if ok else f"{d:+g} (counts must be equal)")
    if not math.isfinite(c):
        return Verdict(DISAGREES, float("nan"), None, None, f"computed value is {c}")
    s = math.hypot(_err(error), paper.sigma)
    if s > 0:
        z = d / s
    else:
        z = 0.0 if d == 0 else math.copysign(math.inf, d)
    ok = abs(z) <= Z_AGREE
    return Verdict(AGREES if ok else DISAGREES, d, z, s, f"{d:+.3g}{_rel(d, p)}, z = {z:+.2f}")


def compare_bound(computed, error, paper: PaperValue) -> Verdict:
    """Strict check of a bound in its direction against the printed value; the margin and its size in
    units of our error bar (where there is one) are printed either way."""
    c = _num(computed, "computed")
    p = float(paper.value)
    d = c - p
    if paper.kind == "upper_bound":
        ok, side, need = d <= 0, ("below" if d < 0 else "above" if d > 0 else "at"), "<="
    elif paper.kind == "lower_bound":
        ok, side, need = d >= 0, ("above" if d > 0 else "below" if d < 0 else "at"), ">="
    else:
        raise ValueError(f"paper value {paper.key!r} has kind={paper.kind!r}: allowed upper_bound or lower_bound")
    if not math.isfinite(c):
        return Verdict(DISAGREES, float("nan"), None, None, f"computed value is {c}")
    e = _err(error)
    z = d / e if e > 0 else None
    txt = f"{abs(d):.3g} {side} {paper.printed} (must be {need} it)"
    if z is not None:
        txt += f", {abs(z):.1f} sigma"
    return Verdict(AGREES if ok else DISAGREES, d, z, e if e > 0 else None, txt)


def compare_category(category: str, paper: PaperValue) -> Verdict:
    """A qualitative statement: the computed category must be the paper's word."""
    ok = str(category) == paper.printed
    return Verdict(AGREES if ok else DISAGREES, None, None, None,
                   "same" if ok else f"{category!s} instead of {paper.printed}")


def internal_check(measured, tolerance: float, ok: bool = True) -> Verdict:
    """A check of this implementation the paper does not state: never compared with the paper; passes
    when ``measured <= tolerance`` (a NaN fails) and ``ok`` (a further condition, e.g. no mismatches)."""
    m = _num(measured, "measured")
    t = _num(tolerance, "tolerance")
    ok = bool(ok) and math.isfinite(m) and m <= t
    return Verdict(NOT_COMPARED, None, None, None, "", PASS if ok else FAIL, t)


def compare(computed, error, paper: PaperValue | None, category: str | None = None,
            tolerance: float | None = None, check_ok: bool = True) -> Verdict:
    """Dispatch on the paper value's kind (``None``: not in the paper -> not compared, with an internal
    check when a ``tolerance`` is given)."""
    if paper is not None and computed is None and category is None:
        return Verdict(DISAGREES, text="no value computed in this run")
    if paper is None:
        if computed is None:  # an internal check that was not computed fails
            return Verdict(NOT_COMPARED, text="no value computed in this run",
                           check=FAIL if tolerance is not None else None, tolerance=tolerance)
        if tolerance is not None:
            return internal_check(computed, tolerance, check_ok)
        return Verdict(NOT_COMPARED)
    if paper.kind == "qualitative":
        if category is None:
            raise ValueError(f"paper value {paper.key!r} is qualitative: a computed category is needed")
        return compare_category(category, paper)
    if paper.kind in ("upper_bound", "lower_bound"):
        return compare_bound(computed, error, paper)
    return compare_value(computed, error, paper)


def row(key: str, quantity: str, value, error=None, *, paper: PaperValue | str | None = None,
        explanation: str = "", where: str = "", computed_text: str | None = None, error_text: str | None = None,
        category: str | None = None, tolerance: float | None = None, check_ok: bool = True):
    """A summary row with its verdict.  ``paper`` is a :class:`.paper.PaperValue`, a key of
    :data:`.paper.PAPER`, or ``None`` (not in the paper); ``value`` and ``error`` are the computed
    number and its standard error (``None`` where there is none); ``category`` the computed word of a
    qualitative row; ``tolerance`` the stated tolerance of an internal check (``check_ok=False`` fails
    it whatever the value, e.g. when the tracks disagree on a wall)."""
    from .document import Number, fmt

    if not key or not key.replace("_", "").isalnum():
        raise ValueError(f"key={key!r} is out of range: allowed a non-empty identifier of letters, digits, _")
    pv = PAPER[paper] if isinstance(paper, str) else paper
    v = compare(value, error, pv, category=category, tolerance=tolerance, check_ok=check_ok)
    if computed_text is None:
        computed_text = (f"{category} ({fmt(value)})" if category is not None and value is not None
                         else fmt(value) if value is not None else "not computed")
    if error_text is None:
        error_text = (f"+- {error:.2g}" if error is not None
                      else f"tolerance {tolerance:.0e}" if tolerance is not None else "")
    paper_text = "(not in the paper)" if pv is None else f"{pv.text()} ({pv.where})"
    return Number(key=key, quantity=quantity, paper=paper_text, computed=computed_text, error_bar=error_text,
                  deviation=v.text, verdict=v.verdict, explanation=explanation, where=where,
                  value=value, error=error, paper_value=pv, outcome=v)
