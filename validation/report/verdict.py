"""Verdicts of the report's summary rows, in one place: every row of every section is judged here.

* A **value** the paper states (``kind`` ``value``, ``approx``, ``theory`` or ``derived`` in
  :mod:`.paper`) is compared by its z-score ``z = (computed - paper) / sigma`` with
  ``sigma = sqrt(error_ours^2 + sigma_paper^2)``; ``sigma_paper`` is the paper's stated error, or,
  where it states none, the rounding of its last printed digit (:attr:`.paper.PaperValue.sigma`).
  The row **agrees** when ``|z| <= 2`` (:data:`Z_AGREE`), else it **disagrees**; the deviation and z
  are always printed.  A ``count`` (e.g. impacts per driving period) must be equal.
* A **bound** (``upper_bound``: the quantity must be ``<=`` the printed value; ``lower_bound``: ``>=``)
  is checked strictly in its direction against the printed value, which is the parameter the paper
  ran, not a rounded result: it is **satisfied** (the row agrees) or **violated** (it disagrees).  No
  z-score: the margin ``ours - paper`` is printed in absolute terms and in units of the paper's last
  printed digit (its printed precision, :attr:`.paper.PaperValue.printed_unit`).  Where an
  *enclosure* ``[lo, hi]`` of our value is given (a proof, e.g. a certified fold), the bound is
  **satisfied (proven)** when the whole enclosure lies on its side of the printed decimal (compared
  exactly), **violated (proven)** when it lies wholly on the other side; an enclosure that contains
  the printed value decides nothing, and the point value's verdict stands, marked not proven.
* A **qualitative** statement (e.g. "regular") agrees when the computed category is the same word.
* A quantity the paper does not state (an internal check of this implementation) is **not
  compared**; where it has a stated tolerance, it gets a separate ``check`` of ``pass``/``fail``.

:func:`row` builds a summary row (:class:`.document.Number`) from a key, the computed value and its
error, the paper value (or ``None``) and an explanation; adding a row to the report is one call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
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
    computed - paper, ``z`` = deviation / ``sigma`` (``None`` where there is no error bar, and for
    bounds), the combined ``sigma``, ``text`` (the one-line reason: deviation and z, a bound's margin,
    a check against its tolerance), for internal checks ``check`` (``"pass"``/``"fail"``) against
    ``tolerance``; for bounds ``bound`` (:data:`BOUND_OUTCOMES`), ``unit`` (one unit of the paper's last
    printed digit) and the ``enclosure`` ``(lo, hi)`` of our value that was judged (``None``: none)."""

    verdict: str
    deviation: float | None = None
    z: float | None = None
    sigma: float | None = None
    text: str = ""
    check: str | None = None
    tolerance: float | None = None
    bound: str | None = None
    unit: float | None = None
    enclosure: tuple[float, float] | None = None

    @property
    def proven(self) -> bool:
        """Whether a bound's verdict is decided by the enclosure (a proof), not by the point value."""
        return bool(self.bound and self.bound.endswith("(proven)"))


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
        return Verdict(AGREES if ok else DISAGREES, d, None, None, "equal" if ok else f"{d:+g} (counts must be equal)")
    if not math.isfinite(c):
        return Verdict(DISAGREES, float("nan"), None, None, f"computed value is {c}")
    s = math.hypot(_err(error), paper.sigma)
    if s > 0:
        z = d / s
    else:
        z = 0.0 if d == 0 else math.copysign(math.inf, d)
    ok = abs(z) <= Z_AGREE
    return Verdict(AGREES if ok else DISAGREES, d, z, s, f"{d:+.3g}{_rel(d, p)}, z = {z:+.2f}")


SATISFIED, VIOLATED = "satisfied", "violated"
#: What a bound row can say: decided by the point value, or by an enclosure (a proof).
BOUND_OUTCOMES = (SATISFIED, VIOLATED, f"{SATISFIED} (proven)", f"{VIOLATED} (proven)")


def _enclosure(enclosure, computed: float) -> tuple[float, float] | None:
    """``(lo, hi)`` as floats (the caller rounds a ball outward); it must contain the computed value."""
    if enclosure is None:
        return None
    try:
        lo, hi = enclosure
    except (TypeError, ValueError):
        raise ValueError(f"enclosure={enclosure!r} is out of range: allowed a pair (lo, hi) of finite reals") from None
    lo, hi = _num(lo, "enclosure lo"), _num(hi, "enclosure hi")
    if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi):
        raise ValueError(f"enclosure={enclosure!r} is out of range: allowed finite lo <= hi")
    if not lo <= computed <= hi:
        raise ValueError(f"enclosure={enclosure!r} is out of range: it must contain the computed value {computed!r}")
    return lo, hi


def compare_bound(computed, error, paper: PaperValue, enclosure=None) -> Verdict:
    """A bound of the paper (Fig. 5's ``r = 0.82144 >~ r2``: ``r2 <= 0.82144``), checked strictly in its
    direction against the printed value: satisfied or violated, with the margin ``computed - paper`` in
    absolute terms and in units of the paper's last printed digit (no z-score: the printed value is a
    parameter the paper ran, exact, and the question is on which side we are).  ``enclosure``
    ``(lo, hi)`` (floats containing a proven enclosure of the quantity) decides the side by proof
    when it lies wholly on one side of the printed decimal, compared exactly.  Where we have an error
    bar and the margin is within :data:`Z_AGREE` of them, the text says the side is not decided by
    our accuracy; the verdict stays the strict one."""
    c = _num(computed, "computed")
    if paper.kind not in ("upper_bound", "lower_bound"):
        raise ValueError(f"paper value {paper.key!r} has kind={paper.kind!r}: allowed upper_bound or lower_bound")
    upper = paper.kind == "upper_bound"
    if not math.isfinite(c):
        return Verdict(DISAGREES, float("nan"), None, None, f"computed value is {c}")
    enc = _enclosure(enclosure, c)
    p, unit, e = float(paper.value), paper.printed_unit, _err(error)
    assert unit is not None, "a bound's printed digits carry its precision (PaperValue.printed_unit)"
    d = c - p
    ok = d <= 0 if upper else d >= 0
    need = "<=" if upper else ">="
    side = "at" if d == 0 else "above" if d > 0 else "below"
    txt = (
        f"{abs(d):.3g} {side} {paper.printed} ({abs(d) / unit:.3g} × its last digit, {unit:g})"
        if d
        else f"at {paper.printed}"
    )
    txt += f"; must be {need} it"
    if e > 0 and abs(d) <= Z_AGREE * e:
        txt += f"; within {Z_AGREE:g} of our error bars (+- {e:.2g}): the side is not decided by our accuracy"
    outcome = SATISFIED if ok else VIOLATED
    if enc is not None:
        lo, hi, exact = Fraction(enc[0]), Fraction(enc[1]), Fraction(paper.printed)
        good = hi <= exact if upper else lo >= exact
        bad = lo > exact if upper else hi < exact
        if good or bad:
            ok, outcome = good, f"{SATISFIED if good else VIOLATED} (proven)"
            txt += f"; proven: our enclosure lies wholly {'below' if good == upper else 'above'} {paper.printed}"
        else:
            txt += f"; not proven: our enclosure contains {paper.printed}"
    return Verdict(AGREES if ok else DISAGREES, d, None, None, txt, bound=outcome, unit=unit, enclosure=enc)


def compare_category(category: str, paper: PaperValue) -> Verdict:
    """A qualitative statement: the computed category must be the paper's word."""
    ok = str(category) == paper.printed
    return Verdict(
        AGREES if ok else DISAGREES, None, None, None, "same" if ok else f"{category!s} instead of {paper.printed}"
    )


def internal_check(measured, tolerance: float, ok: bool = True) -> Verdict:
    """A check of this implementation the paper does not state: never compared with the paper; passes
    when ``measured <= tolerance`` (a NaN fails) and ``ok`` (a further condition, e.g. no mismatches)."""
    m = _num(measured, "measured")
    t = _num(tolerance, "tolerance")
    within = math.isfinite(m) and m <= t
    txt = f"{m:.2g} {'<=' if within else '>' if math.isfinite(m) else 'against'} tolerance {t:.0e}"
    if within and not ok:
        txt += ", but a further condition failed (see the explanation)"
    ok = bool(ok) and within
    return Verdict(NOT_COMPARED, None, None, None, txt, PASS if ok else FAIL, t)


def compare(
    computed,
    error,
    paper: PaperValue | None,
    category: str | None = None,
    tolerance: float | None = None,
    check_ok: bool = True,
    enclosure=None,
) -> Verdict:
    """Dispatch on the paper value's kind (``None``: not in the paper -> not compared, with an internal
    check when a ``tolerance`` is given).  ``enclosure`` (a proven ``(lo, hi)`` of the computed value) is
    used by bounds, refused elsewhere (no other verdict uses it yet)."""
    if enclosure is not None and (paper is None or paper.kind not in ("upper_bound", "lower_bound")):
        raise ValueError(f"enclosure={enclosure!r} is out of range: allowed only for a bound of the paper")
    if paper is not None and computed is None and category is None:
        return Verdict(DISAGREES, text="no value computed in this run")
    if paper is None:
        if computed is None:  # an internal check that was not computed fails
            return Verdict(
                NOT_COMPARED,
                text="no value computed in this run",
                check=FAIL if tolerance is not None else None,
                tolerance=tolerance,
            )
        if tolerance is not None:
            return internal_check(computed, tolerance, check_ok)
        return Verdict(NOT_COMPARED)
    if paper.kind == "qualitative":
        if category is None:
            raise ValueError(f"paper value {paper.key!r} is qualitative: a computed category is needed")
        return compare_category(category, paper)
    if paper.kind in ("upper_bound", "lower_bound"):
        return compare_bound(computed, error, paper, enclosure)
    return compare_value(computed, error, paper)


def row(
    key: str,
    quantity: str,
    value,
    error=None,
    *,
    paper: PaperValue | str | None = None,
    explanation: str = "",
    where: str = "",
    computed_text: str | None = None,
    error_text: str | None = None,
    category: str | None = None,
    tolerance: float | None = None,
    check_ok: bool = True,
    enclosure=None,
):
    """A summary row with its verdict.  ``paper`` is a :class:`.paper.PaperValue`, a key of
    :data:`.paper.PAPER`, or ``None`` (not in the paper); ``value`` and ``error`` are the computed
    number and its standard error (``None`` where there is none); ``category`` the computed word of a
    qualitative row; ``tolerance`` the stated tolerance of an internal check (``check_ok=False`` fails
    it whatever the value, e.g. when the tracks disagree on a wall); ``enclosure`` a proven
    ``(lo, hi)`` of the value (floats, rounded outward), for a bound of the paper (:func:`compare_bound`).

    The arguments are kept in the row's ``spec`` (``document.json``), so the row can be judged and
    drawn again from them."""
    from .document import Number, fmt

    if not key or not key.replace("_", "").isalnum():
        raise ValueError(f"key={key!r} is out of range: allowed a non-empty identifier of letters, digits, _")
    if isinstance(paper, str) and paper not in PAPER:
        raise ValueError(f"paper={paper!r} is not known: allowed a key of paper.PAPER or None")
    pv = PAPER[paper] if isinstance(paper, str) else paper
    v = compare(value, error, pv, category=category, tolerance=tolerance, check_ok=check_ok, enclosure=enclosure)
    if computed_text is None:
        computed_text = (
            f"{category} ({fmt(value)})"
            if category is not None and value is not None
            else fmt(value)
            if value is not None
            else "not computed"
        )
    if error_text is None:
        error_text = (
            f"+- {error:.2g}" if error is not None else f"tolerance {tolerance:.0e}" if tolerance is not None else ""
        )
    paper_text = "(not in the paper)" if pv is None else f"{pv.text()} ({pv.where})"
    spec = {
        "key": key,
        "quantity": quantity,
        "value": value,
        "error": error,
        "paper": None if pv is None else pv.key,
        "explanation": explanation,
        "where": where,
        "computed_text": computed_text,
        "error_text": error_text,
        "category": category,
        "tolerance": tolerance,
        "check_ok": bool(check_ok),
        "enclosure": None if v.enclosure is None else list(v.enclosure),
    }
    return Number(
        key=key,
        quantity=quantity,
        paper=paper_text,
        computed=computed_text,
        error_bar=error_text,
        deviation=v.text,
        verdict=v.verdict,
        explanation=explanation,
        where=where,
        value=value,
        error=error,
        paper_value=pv,
        outcome=v,
        spec=spec,
    )


__all__ = [
    "AGREES",
    "DISAGREES",
    "NOT_COMPARED",
    "VERDICTS",
    "Z_AGREE",
    "PASS",
    "FAIL",
    "Verdict",
    "compare_value",
    "SATISFIED",
    "VIOLATED",
    "BOUND_OUTCOMES",
    "compare_bound",
    "compare_category",
    "internal_check",
    "compare",
    "row",
]
