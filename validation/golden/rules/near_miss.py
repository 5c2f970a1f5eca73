"""The near-miss rule of ``gear-rattle case`` (docs/reference/golden_commands.md, "Asking the oracle"): a case stops before an
impact whose flight turns back closer to a wall than :data:`NEAR_MISS_SAFETY` times the gap error of a
correct float64 implementation (:func:`.conditioning.gap_error`): such an implementation may take that near
miss for a contact.  The flight's turning points are searched on a grid fine where a slow departure turns
back (:func:`turn_grid`) and refined (:func:`turning_gap`); :func:`near_miss_limit` applies the rule to a
certified orbit.
"""

from __future__ import annotations

import math

import numpy as np

from ....core.params import Params
from ....mapimpl import certified as cert
from ..formats.case_writer import certified_rows
from ..formats.spec import Spec
from .conditioning import flight_height, gap_error

__all__ = ["NEAR_MISS_SAFETY", "TURN_SAMPLES", "TURN_SAMPLES_PER_UNIT", "turn_grid", "turning_gap", "near_miss_limit"]

#: A flight that turns back closer to a wall than this many times the gap error ``e`` of a correct float64
#: implementation (:func:`conditioning.gap_error`: ``2 2^-52 + 3e-14 h`` for a flight within one period) may be
#: taken for a contact by one: a case stops before the impact that ends such a flight (the near-miss rule; the
#: shipped near misses lie at 6.6e6 e, 3.3e4 e and 330 e).
NEAR_MISS_SAFETY = 10.0
#: Samples of a flight per refinement when its turning points are searched (three refinements), and per unit of
#: time in the first round (at least :data:`TURN_SAMPLES`; the forcing's period is 2 pi).
TURN_SAMPLES, TURN_SAMPLES_PER_UNIT = 257, 64


_FLIGHT: list = []  # the flight's (ds, v) at TURN_SAMPLES times, compiled once


def turn_grid(dt: float, departure: bool = True):
    """The first round's sample times of a flight of ``dt``: :data:`TURN_SAMPLES_PER_UNIT` per unit of time (a
    long flight oscillates with the forcing) and, for a ``departure`` with a speed (after an impact), ``dt 2^-k``
    for k = 1 ... 64 (a slow departure against a weakening force turns back twice within 1e-6 of its start: a
    257-point grid saw neither turning point of a flight that came back within 1.6e-19 of its start wall,
    found by ``gear-rattle fuzz``).  Not after a release from rest: there the force vanishes to rounding and
    ``sdot`` dips to ~-1e-31 just after the start, no turning point of the model."""
    import numpy as np

    n = max(TURN_SAMPLES, int(math.ceil(dt * TURN_SAMPLES_PER_UNIT)))
    early = dt * 2.0 ** -np.arange(64.0, 0.0, -1.0) if departure else np.zeros(0)
    return np.unique(np.concatenate([early, np.linspace(0.0, dt, n)]))


def turning_gap(p: Params, th0: float, v0: float, s_start: float, dt: float) -> float:
    """The smallest distance to a wall at which the flight from ``(th0, s_start, v0)`` turns back before
    ``dt`` (interior extrema of ``s``, located on :func:`turn_grid` and two refinements of
    :data:`TURN_SAMPLES` samples: the float64 closed form, Eqs. 7-8); ``inf`` without a turning point."""
    if not _FLIGHT:
        import jax

        from ....mapimpl.flight import flight

        _FLIGHT.append(jax.jit(lambda t, th, v, a, b, g: (flight(t, th, v, a, b, g).ds, flight(t, th, v, a, b, g).v)))

    def at(t):
        """``(t, s, v)`` at the times ``t``, in chunks of TURN_SAMPLES (one compiled shape)."""
        ds, vs = [], []
        for k in range(0, len(t), TURN_SAMPLES):
            chunk = t[k : k + TURN_SAMPLES]
            d, w = _FLIGHT[0](
                np.pad(chunk, (0, TURN_SAMPLES - len(chunk)), mode="edge"), th0, v0, p.alpha, p.beta, p.gamma
            )
            ds.append(np.asarray(d)[: len(chunk)])
            vs.append(np.asarray(w)[: len(chunk)])
        return t, s_start + np.concatenate(ds), np.concatenate(vs)

    def zoom(a: float, b: float, pick) -> tuple[float, float]:
        """``(s, v)`` at the sample ``pick(s, v)`` of ``[a, b]`` after two refinements around it."""
        for _ in range(2):
            tt, ss, vv = at(np.linspace(a, b, TURN_SAMPLES))
            k = int(pick(ss, vv))
            a, b = tt[max(k - 1, 0)], tt[min(k + 1, TURN_SAMPLES - 1)]
        return float(ss[k]), float(vv[k])

    t, s, v = at(turn_grid(dt, v0 != 0))
    best = math.inf
    for i in np.nonzero(np.sign(v[1:-1]) != np.sign(v[2:]))[0] + 1:
        up = v[i] > 0
        s_k, _ = zoom(t[i], t[i + 1], lambda ss, vv: np.argmax(ss) if up else np.argmin(ss))
        best = min(best, -s_k if up else s_k + 1.0)
    # two turning points inside one interval (a dip of v through 0 and back, unseen at the samples): where the
    # acceleration changes sign, the extremum of v; after a departure with a speed only (:func:`turn_grid`)
    if v0 != 0:
        acc = p.gamma - p.alpha * np.sin(th0 + t) + p.alpha * p.beta * np.cos(th0 + t) - p.beta * v
        for i in np.nonzero((np.sign(acc[:-1]) != np.sign(acc[1:])) & (np.sign(v[:-1]) == np.sign(v[1:])))[0]:
            up = v[i] > 0
            s_k, v_k = zoom(t[i], t[i + 1], lambda ss, vv: np.argmin(vv) if up else np.argmax(vv))
            if (v_k < 0) == up and v_k != 0:
                best = min(best, -s_k, s_k + 1.0)
    return best


def near_miss_limit(spec: Spec, orb: cert.CertifiedOrbit) -> tuple[int, str] | None:
    """``(impact, note)``: the first impact whose flight turns back within :data:`NEAR_MISS_SAFETY` times the
    gap error of a wall (the case must stop before it), or ``None``."""
    p = spec.params
    rows = certified_rows(orb)
    start = None if spec.s0 is None else (spec.tau0 % (2 * math.pi), spec.sdot0, spec.tau0, spec.s0)
    prev = None
    for i, kind in enumerate(rows.kind):
        tau = float(rows.tau[i])
        if kind == "stick":
            continue
        if kind == "release":
            start = (float(rows.tau_mod_2pi[i]), 0.0, tau, float(rows.wall[i]))
            continue
        if start is None and prev is not None:
            start = (
                float(rows.tau_mod_2pi[prev]),
                -p.r * float(rows.sdot[prev]),
                float(rows.tau[prev]),
                float(rows.wall[prev]),
            )
        if start is not None:
            dt = tau - start[2]
            gap = turning_gap(p, start[0], start[1], start[3], dt)
            e = gap_error(flight_height(p, start[0], start[1], dt), dt)
            if gap < NEAR_MISS_SAFETY * e:
                return int(rows.n[i]), (
                    f"the flight to impact {int(rows.n[i])} turns back {gap:.3g} from a wall, "
                    f"within {NEAR_MISS_SAFETY:g} times the gap error {e:.3g} of a correct float64 "
                    "implementation (it may take it for a contact)"
                )
        prev, start = i, None
    return None
