"""Golden periodic orbits and bifurcation points: a certified result as a JSON record, its tolerances
from the conditioning of the zero, and the re-verification of a record (docs/golden.md).

A record (``validation/golden/orbits/<id>.json``) holds every number as a decimal interval
``[lo, hi]`` with :data:`DIGITS` significant digits whose ends are the ball's ends rounded outward
(exactly, :func:`mapimpl.certified.balls.decimal_interval`): the interval contains the proven
enclosure.  :func:`verify_record` proves a record again from its own intervals: the Krawczyk test on
the box they span (the zero of the orbit or extended system is unique there and lies inside the
decimal intervals), the flights proven over it, and the multipliers enclosed inside the record's
intervals.  It needs no float64 seed and takes well under a second.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass

from flint import arb

from ....core.params import Params
from ....mapimpl.certified import jets
from ....mapimpl.certified.balls import PREC, CertificationError, decimal_interval, precision
from ....mapimpl.certified.krawczyk import refine, verify_box
from ....mapimpl.certified.model import Model
from ....mapimpl.certified.periodic import CertifiedBifurcation, CertifiedPeriodicOrbit, floquet, prove_flights, unwrap
from ....mapimpl.certified.shooting import Numbers, Shape, extended_residual, monodromy, orbit_residual

#: Significant digits of the decimal interval ends (the enclosures are ~1e-90 wide: the printed
#: interval is one unit of the 20th digit wide, far below any float64 tolerance).
DIGITS = 20
#: Kinds of record.
KINDS = ("periodic-orbit", "fold", "period-doubling")
#: The residual of one orbit equation (a flight's gap or velocity) at which a float64 Newton stops:
#: the default tolerance of :func:`mapimpl.periodic.find_periodic` (whose error is then up to the
#: conditioning times it: measured 9e-13 on the 4-impact saddle).  A Newton polished to rounding
#: does ~100 times better (the terms of Eqs. 7-8 are at most ~10 here, ~50 units of roundoff).
RESIDUAL_FLOOR = 1e-12
#: Safety factor between the propagated residual floor and the tolerance (then rounded up to a power of 10).
SAFETY = 10.0


@dataclass(frozen=True)
class OrbitCase:
    """One golden orbit or bifurcation point: ``params`` are the float64 values used (for a
    bifurcation point the fixed ones; ``params[parameter]`` is only the seed's value), ``impacts``
    per ``turns`` driving periods."""

    id: str
    kind: str
    description: str
    params: Params
    impacts: int
    turns: int = 1
    parameter: str | None = None

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind={self.kind!r} is out of range: allowed one of {KINDS}")
        if (self.parameter is None) != (self.kind == "periodic-orbit"):
            raise ValueError(f"case {self.id}: a bifurcation point needs its parameter, an orbit has none")


# ------------------------------------------------------------------------------------------------
# JSON with exact decimals


class _Dec:
    """A decimal string written into JSON as a number, unquoted."""

    def __init__(self, text: str):
        self.text = text


def _interval(x: arb) -> list:
    lo, hi = decimal_interval(x, DIGITS)
    return [_Dec(lo), _Dec(hi)]


def dumps(record: dict) -> str:
    """The record as JSON text (indent 1, keys in insertion order), decimal intervals as numbers."""
    marks: list[str] = []

    def default(o):
        if isinstance(o, _Dec):
            marks.append(o.text)
            return f"@@DEC{len(marks) - 1}@@"
        raise TypeError(f"{type(o).__name__} is not JSON serialisable")

    text = json.dumps(record, indent=1, default=default, allow_nan=False)
    return re.sub(r'"@@DEC(\d+)@@"', lambda m: marks[int(m.group(1))], text) + "\n"


def loads_exact(text: str) -> dict:
    """Parse a record keeping every non-integer number as its decimal string (exact)."""
    return json.loads(text, parse_float=str)


# ------------------------------------------------------------------------------------------------
# tolerances from conditioning


def _pow10_up(x: float) -> float:
    return float(10.0 ** math.ceil(math.log10(max(x, 1e-300))))


def _kappa(M, lam) -> float:
    """Sensitivity of the eigenvalues of a 2x2 ``M`` to a perturbation of its entries (max norm)."""
    m = max(abs(float(a)) for row in M for a in row)
    h = abs(float((M[0][0] + M[1][1]).mid())) / 2
    gap = abs(complex(lam[0]) - complex(lam[1]))
    return 1.0 + (2 * h + 4 * m) / max(gap, 1e-300)


def tolerances(orbit: CertifiedPeriodicOrbit, unknowns: list, fun_M) -> dict:
    """Absolute tolerances a float64 Newton meets (the residual floor propagated through the zero's
    conditioning, times :data:`SAFETY`, rounded up to a power of 10): the error of unknown ``k`` is
    ``sum_j |C_kj| e_j`` (``C`` the inverse Jacobian of the Krawczyk proof, ``e_j`` the float64 floor
    of equation ``j``: :data:`RESIDUAL_FLOOR`, for the determinant row ``p (1 + max|M|)^2`` times it);
    the multipliers move by ``kappa`` times the change of ``M`` that those errors cause (``dM/dx`` by
    forward mode) plus ``M``'s own rounding (``p`` floors times ``max|M|``)."""
    C = orbit.krawczyk.inverse
    p = orbit.shape.impacts
    mmax = max(abs(float(a)) for row in orbit.monodromy for a in row)
    e = [RESIDUAL_FLOOR] * (2 * p) + [RESIDUAL_FLOOR * p * (1 + mmax) ** 2] * (len(C) - 2 * p)
    err = [sum(abs(c) * ej for c, ej in zip(row, e)) for row in C]
    _, dM = jets.jacobian(fun_M, unknowns)
    err_M = max(sum(abs(float(d)) * ek for d, ek in zip(row, err)) for row in dM) + p * RESIDUAL_FLOOR * mmax
    out = {
        "tau_mod_2pi": _pow10_up(SAFETY * max(err[0 : 2 * p : 2])),
        "sdot": _pow10_up(SAFETY * max(err[1 : 2 * p : 2])),
        "multipliers": _pow10_up(SAFETY * _kappa(orbit.monodromy, orbit.multipliers) * err_M),
    }
    if len(C) > 2 * p:
        out["value"] = _pow10_up(SAFETY * err[-1])
    return out


# ------------------------------------------------------------------------------------------------
# records


def _orbit_fields(orbit: CertifiedPeriodicOrbit, bifurcation: bool) -> dict:
    """Points, multipliers and the proven stability (``non-hyperbolic`` at a bifurcation point, where
    a multiplier is exactly +1 or -1)."""
    pts = [
        {"tau_mod_2pi": _interval(th), "sdot": _interval(v), "wall": w}
        for th, v, w in zip(orbit.theta, orbit.sdot, orbit.walls)
    ]
    mult = [{"re": _interval(z.real), "im": _interval(z.imag)} for z in orbit.multipliers]
    if bifurcation:
        stability = "non-hyperbolic"
    elif all(abs(z) < 1 for z in orbit.multipliers):
        stability = "stable"
    elif any(abs(z) > 1 for z in orbit.multipliers):
        stability = "unstable"
    else:  # pragma: no cover - a multiplier on the unit circle away from a bifurcation point
        raise CertificationError("stability not decided: a multiplier's modulus encloses 1")
    return {
        "impacts_per_period": orbit.shape.impacts,
        "turns": orbit.shape.turns,
        "points": pts,
        "multipliers": mult,
        "stability": stability,
    }


def record(case: OrbitCase, result, seed: str) -> dict:
    """The JSON record of a certified orbit (:class:`CertifiedPeriodicOrbit`) or bifurcation point
    (:class:`CertifiedBifurcation`) of ``case``; ``seed`` says where the float64 guess came from."""
    with precision(result.orbit.krawczyk.prec if isinstance(result, CertifiedBifurcation) else result.krawczyk.prec):
        orbit = result.orbit if isinstance(result, CertifiedBifurcation) else result
        P = Numbers(orbit.model)
        shape = orbit.shape
        params = case.params.as_dict()
        rec: dict[str, object] = {"id": case.id, "kind": case.kind, "description": case.description, "params": params}
        x = [v for pair in zip(orbit.tau, orbit.sdot) for v in pair]
        if isinstance(result, CertifiedBifurcation):
            params[result.name] = float(result.value.mid())
            rec["parameter"], rec["value"] = result.name, _interval(result.value)
            base = Model(case.params)

            def fun_M(y):
                return [a for row in monodromy(y[:-1], Numbers(base, result.name, y[-1]), shape) for a in row]

            unknowns = x + [result.value]
        else:

            def fun_M(y):
                return [a for row in monodromy(y, P, shape) for a in row]

            unknowns = x
        rec.update(_orbit_fields(orbit, case.parameter is not None))
        rec["tolerances"] = tolerances(orbit, unknowns, fun_M)
        k = orbit.krawczyk
        rec["provenance"] = {
            "method": (
                "Krawczyk operator on the multiple-shooting system in the pre-impact states (closed-form "
                "flights, Eqs. 7-8, reset Eq. 11)"
                + (
                    f" extended by det(M {'-' if case.kind == 'fold' else '+'} I) = 0 with {case.parameter} unknown"
                    if case.parameter
                    else ""
                )
                + "; Jacobian enclosed by forward mode over balls; no earlier wall contact proven over the "
                "enclosure for every flight (mapimpl/certified/contact.py); multipliers: eigenvalues of "
                "the monodromy matrix enclosed over the box (mapimpl/certified/periodic.py)"
            ),
            "precision_bits": k.prec,
            "krawczyk": {
                "box_radius": float(f"{max(float(b.rad()) for b in k.trial):.3g}"),
                "contraction": float(f"{k.contraction:.3g}"),
                "norm_I_minus_CJ": float(f"{k.norm:.3g}"),
                "residual_at_center": float(f"{k.residual:.3g}"),
                "max_radius": float(f"{max(float(b.rad()) for b in k.box):.3g}"),
            },
            "flights": [{"pieces": c.pieces, "evals": c.evals} for c in orbit.flights],
            "decimal_digits": DIGITS,
            "tolerances": (
                f"float64 residual floor {RESIDUAL_FLOOR:g} per equation propagated through the inverse "
                f"Jacobian, times {SAFETY:g}, rounded up to a power of 10"
            ),
            "seed": seed,
        }
        return rec


# ------------------------------------------------------------------------------------------------
# re-verification


def _ball(pair) -> arb:
    lo, hi = (arb(str(v)) for v in pair)
    return lo.union(hi)


def _inside(x: arb, pair) -> bool:
    """``x`` lies strictly inside the exact decimal interval ``pair`` (strings or numbers)."""
    lo, hi = (arb(str(v)) for v in pair)
    return bool(x > lo and x < hi) or (lo.is_exact() and hi.is_exact() and lo == hi == x)


@dataclass
class Verified:
    """What :func:`verify_record` proved: the Krawczyk contraction on the record's own box and the
    radius of the refined enclosure."""

    id: str
    contraction: float
    radius: float


def verify_record(rec: dict, prec: int = PREC) -> Verified:
    """Prove a record from its own intervals (module docstring); raises :class:`CertificationError`
    (or ``ValueError`` for a malformed record)."""
    kind = rec["kind"]
    if kind not in KINDS:
        raise ValueError(f"{rec.get('id')}: kind={kind!r} is out of range: allowed one of {KINDS}")
    pts = rec["points"]
    shape = Shape(tuple(int(p["wall"]) for p in pts), int(rec["turns"]))
    if len(pts) != int(rec["impacts_per_period"]):
        raise ValueError(f"{rec['id']}: {len(pts)} points for impacts_per_period={rec['impacts_per_period']}")
    with precision(prec):
        two_pi = 2 * arb.pi()
        mids = unwrap([float(p["tau_mod_2pi"][0]) for p in pts], shape.turns)
        box = []
        for p, t in zip(pts, mids):
            turns = round((t - float(p["tau_mod_2pi"][0])) / (2 * math.pi))
            box += [_ball(p["tau_mod_2pi"]) + turns * two_pi, _ball(p["sdot"])]
        params = Params(**{k: float(v) for k, v in rec["params"].items()})
        base = Model(params)
        if kind == "periodic-orbit":
            P = Numbers(base)

            def fun(y):
                return orbit_residual(y, P, shape)
        else:
            name = rec["parameter"]
            box.append(_ball(rec["value"]))

            def fun(y):
                return extended_residual(y, base, shape, name, kind)

        res = verify_box(fun, box)  # a unique zero in the box spanned by the record's intervals
        tight = refine(fun, res.box)
        x = tight[: 2 * shape.impacts]
        model = base
        if kind != "periodic-orbit":
            balls = base.balls()
            balls[rec["parameter"]] = tight[-1]
            model = Model.from_balls(**balls)
            if not _inside(tight[-1], rec["value"]):
                raise CertificationError(f"{rec['id']}: the value is not inside the record's interval")
        prove_flights(model, shape, x[0::2], x[1::2], prec)
        for p, th, v in zip(pts, x[0::2], x[1::2]):
            k = (th / two_pi).floor()
            if not (k.is_exact() and _inside(th - k * two_pi, p["tau_mod_2pi"]) and _inside(v, p["sdot"])):
                raise CertificationError(f"{rec['id']}: a point is not inside the record's intervals")
        lam = floquet(monodromy(x, Numbers(model), shape))
        for z, m in zip(lam, rec["multipliers"]):
            if not (_inside(z.real, m["re"]) and _inside(z.imag, m["im"])):
                raise CertificationError(f"{rec['id']}: a multiplier is not inside the record's intervals")
        return Verified(rec["id"], res.contraction, max(float(b.rad()) for b in tight))
