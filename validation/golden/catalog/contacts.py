"""Contacts that are hard to find, for the golden cases: grazes and near misses.

A **graze**: the first flight of a case crosses a wall with a small normal speed ``v``, so the
un-reset flight would stay beyond the wall only for a short *excursion* ``[t_enter, t_exit]``
(length ``~ 2 v / |s''|``).  A **near miss**: the flight approaches a wall tangentially and turns
back at a small distance from it without touching.  Both are found by bisection on the initial
velocity ``sdot0`` of a pre-impact state (the first impact switches wall at a threshold), with the
map track's first impact as the oracle; the certified numbers that matter (the excursion, the
closest approach) are then computed in ball arithmetic (the certified track, :mod:`mapimpl.certified`).

What a **fixed-step sign-change finder** sees of a graze: sampling the flight at ``t = k h``
(``k = 1, 2, ...`` from the start of the flight) it finds the crossing only if some sample falls
inside the excursion.  :func:`steps_that_catch` gives the set of steps ``h`` that do, as intervals;
:func:`steps_catching_all` intersects them over several grazes: an empty result proves that every
such finder with a step in the range misses at least one of the grazes.
"""

from __future__ import annotations

import math

from flint import arb

from ....core.params import Params
from ....mapimpl import certified as cert

#: Excursion beyond the wall (time units) of the grazes of cases 0020-0023.
GRAZE_EXCURSION = 5e-5
#: Gap-error budget of a float64 implementation near a graze: the impact time error is about
#: (gap error) / (normal speed), so a graze with speed ``v`` gets the tolerance ``GAP_BUDGET / v``
#: (the rule of case 0004: 1e-7 at v = 1e-3).
GAP_BUDGET = 1e-10
#: The range of steps of a fixed-step finder that the graze cases must defeat.
STEP_RANGE = (1e-3, 1.0)
#: Relative widening of every interval of steps that catch a graze (rounding of ``t / k``, and
#: conservative: a larger catching set can only make the coverage claim harder to meet).
STEP_SLACK = 1e-12


def first_contact(params: Params, tau0: float, sdot0: float) -> tuple[int, float, float]:
    """``(wall, flight time, pre-impact sdot)`` of the first impact after the pre-impact state
    ``(tau0, sdot0)`` on the map track (float64; a search oracle, not a certified value)."""
    from ....mapimpl.tracks import orbit

    seq = orbit(params, tau0, sdot0, 1, track="map")
    if len(seq.n) < 2:
        raise RuntimeError(f"no first impact from tau0={tau0!r}, sdot0={sdot0!r}")
    return int(seq.wall[1]), float(seq.tau[1] - seq.tau[0]), float(seq.sdot[1])


def bisect(pred, lo: float, hi: float, iters: int = 60) -> tuple[float, float]:
    """``pred(lo)`` false, ``pred(hi)`` true; returns the final ``(lo, hi)`` after ``iters`` halvings."""
    if pred(lo) or not pred(hi):
        raise RuntimeError("bisection bracket does not bracket the predicate change")
    for _ in range(iters):
        m = 0.5 * (lo + hi)
        if pred(m):
            hi = m
        else:
            lo = m
    return lo, hi


def contact_threshold(
    params: Params, tau0: float, lo: float, hi: float, wall: int, iters: int = 80
) -> tuple[float, float]:
    """``(miss, reach)``: adjacent initial velocities (bisection in ``[lo, hi]``) at which the first
    flight from ``(tau0, sdot0)`` does not reach ``wall`` and does reach it first."""
    reach = lambda s: first_contact(params, tau0, s)[0] == wall  # noqa: E731
    if reach(lo) == reach(hi):
        raise RuntimeError(f"[{lo}, {hi}] does not bracket the first contact switching to wall {wall}")
    return bisect(reach, lo, hi, iters) if reach(hi) else bisect(reach, hi, lo, iters)


def grazing_speed_sdot0(params: Params, tau0: float, lo: float, hi: float, speed: float) -> float:
    """The rule of case 0004: the initial pre-impact velocity (12 significant digits) whose flight
    reaches the lower wall with pre-impact speed about ``speed`` (bisection on the first impact)."""

    def pred(s):
        w, _, v = first_contact(params, tau0, s)
        return w == -1 and abs(v) >= speed

    _, h = bisect(pred, lo, hi)
    return float(f"{h:.12g}")


def near_miss_offset_sdot0(params: Params, tau0: float, lo: float, hi: float, offset: float) -> float:
    """The rule of case 0005: the initial velocity ``offset`` below the threshold at which the flight
    first reaches the lower wall (12 significant digits): it approaches it tangentially, misses, and
    returns to the wall it left."""
    lo, _ = bisect(lambda s: first_contact(params, tau0, s)[0] == -1, lo, hi)
    return float(f"{lo - offset:.12g}")


def _float_flight(params: Params, tau0: float, sdot0: float):
    """The float64 gap functions of the first flight from the pre-impact state (map closed form)."""
    from ....mapimpl.flight import flight

    start = 0.0 if sdot0 > 0 else -1.0
    th = math.fmod(tau0, 2 * math.pi)

    def s_of(t):
        return start + float(flight(t, th, -params.r * sdot0, params.alpha, params.beta, params.gamma).ds)

    return s_of


def float_excursion(params: Params, tau0: float, sdot0: float) -> tuple[int, float, float]:
    """``(wall, t_enter, t_exit)`` of the first impact's excursion beyond the wall (float64 estimate:
    the map's impact time and a bisection for the exit, where the un-reset flight comes back)."""
    wall, t1, v = first_contact(params, tau0, sdot0)
    s_of = _float_flight(params, tau0, sdot0)
    beyond = (lambda s: s > 0.0) if wall == 0 else (lambda s: s < -1.0)
    step = max(abs(v), 1e-12)
    lo = t1 + 1e-3 * step
    hi = t1 + step
    while beyond(s_of(hi)):
        hi = t1 + 2 * (hi - t1)
        if hi - t1 > 1.0:
            raise RuntimeError("excursion longer than 1: not a graze")
    if not beyond(s_of(lo)):
        raise RuntimeError("the flight does not go beyond the wall after its first contact")
    for _ in range(80):
        m = 0.5 * (lo + hi)
        if beyond(s_of(m)):
            lo = m
        else:
            hi = m
    return wall, t1, hi


def graze_sdot0(
    params: Params, tau0: float, lo: float, hi: float, wall: int, excursion: float = GRAZE_EXCURSION
) -> float:
    """Initial velocity (15 significant digits) whose first flight crosses ``wall`` with an excursion
    beyond it of about ``excursion``: the threshold of :func:`contact_threshold`, then bisection on
    the offset beyond it (the excursion grows like the square root of the offset)."""
    miss, hit = contact_threshold(params, tau0, lo, hi, wall)
    sign = 1.0 if hit > miss else -1.0

    def length(off):
        _, a, b = float_excursion(params, tau0, hit + sign * off)
        return b - a

    lo_off, hi_off = 0.0, 1e-9
    while length(hi_off) < excursion:
        hi_off *= 2
    for _ in range(60):
        m = 0.5 * (lo_off + hi_off)
        if length(m) < excursion:
            lo_off = m
        else:
            hi_off = m
    return float(f"{hit + sign * hi_off:.15g}")


def float_closest_approach(params: Params, tau0: float, sdot0: float, wall: int) -> float:
    """Smallest float64 distance to ``wall`` along the first flight (before its first impact)."""
    _, t1, _ = first_contact(params, tau0, sdot0)
    s_of = _float_flight(params, tau0, sdot0)
    n = 4000
    gap = (lambda s: -s) if wall == 0 else (lambda s: s + 1.0)
    return min(gap(s_of(t1 * k / n)) for k in range(1, n))


def near_miss_sdot0(params: Params, tau0: float, lo: float, hi: float, wall: int, distance: float) -> float:
    """Initial velocity (15 significant digits) whose first flight approaches ``wall`` tangentially
    and turns back about ``distance`` from it: the threshold of :func:`contact_threshold` moved to
    the missing side by ``distance / c``, ``c`` the rate at which the closest approach grows with
    the offset (measured at an offset of 1e-6; the closest approach is linear in the offset)."""
    miss, hit = contact_threshold(params, tau0, lo, hi, wall)
    sign = 1.0 if miss > hit else -1.0
    probe = 1e-6
    c = float_closest_approach(params, tau0, miss + sign * probe, wall) / probe
    return float(f"{miss + sign * distance / c:.15g}")


# ---------------------------------------------------------------------------------------------
# certified numbers


def _first_flight(model: cert.Model, tau0: float, sdot0: float) -> cert.Flight:
    start = 0.0 if sdot0 > 0 else -1.0
    return cert.Flight(model, cert.exact(tau0), cert.exact(start), -model.r * cert.exact(sdot0))


def certified_excursion(params: Params, tau0: float, sdot0: float, prec: int = cert.PREC) -> dict:
    """The excursion beyond the wall of the first flight from the pre-impact state, certified:
    ``t_enter`` (the certified impact) and ``t_exit`` (where the un-reset flight comes back: a sign
    change of the gap, bisected in balls), as outward-rounded float64 bounds, and its length."""
    with cert.precision(prec):
        model = cert.Model(params)
        start = 0.0 if sdot0 > 0 else -1.0
        c = cert.certified_flight(model, cert.exact(tau0), start, -model.r * cert.exact(sdot0), prec=prec)
        fl = _first_flight(model, tau0, sdot0)
        t_in = c.t
        v = abs(float(c.v.mid()))
        lo = arb(t_in.upper())
        hi = lo + arb(1e-12)
        while fl.gap(c.wall, hi) < 0:
            hi = lo + 2 * (hi - lo)
        if not fl.gap(c.wall, hi) > 0 or not fl.gap(c.wall, lo) < 0:
            raise cert.CertificationError("excursion exit not bracketed")
        for _ in range(200):
            m = arb(((lo + hi) / 2).mid())
            g = fl.gap(c.wall, m)
            if g < 0:
                lo = m
            elif g > 0:
                hi = m
            else:
                break
        t_enter = math.nextafter(float(t_in.lower()), -math.inf)
        t_exit = cert.upper_float(hi)
    return {
        "wall": c.wall,
        "t_enter": t_enter,
        "t_exit": t_exit,
        "length": t_exit - t_enter,
        "speed": v,
        "meaning": "flight times from the start of the first flight (after the reset of impact 0) between "
        "which the un-reset flight lies beyond the wall; certified bounds rounded outward",
    }


def certified_closest_approach(params: Params, tau0: float, sdot0: float, prec: int = cert.PREC) -> tuple[int, arb]:
    """``(wall, distance)``: the wall the first flight from the pre-impact state turns back from, and
    a certified enclosure of the smallest distance to it (at the first zero of ``s'``)."""
    with cert.precision(prec):
        model = cert.Model(params)
        fl = _first_flight(model, tau0, sdot0)
        wall = -1 if sdot0 > 0 else 0  # the flight leaves the other wall towards this one
        sign = 1 if wall == -1 else -1  # s' moves towards the wall with sign -sign; turns back where sign s' > 0
        t_prev, t = arb(0), arb(0)
        for k in range(1, 4001):
            t = arb(k) / 400
            if sign * fl.v(t) > 0:
                break
            t_prev = t
        else:  # pragma: no cover
            raise cert.CertificationError("no turning point found")
        lo, hi = t_prev, t
        for _ in range(200):
            mid = (lo + hi) / 2
            if sign * fl.v(mid) > 0:
                hi = mid
            else:
                lo = mid
        return wall, fl.gap(wall, cert.span(lo, hi))  # the extremum of s lies in [lo, hi]


# ---------------------------------------------------------------------------------------------
# fixed-step finders


def steps_that_catch(
    t_enter: float, t_exit: float, h_min: float = STEP_RANGE[0], h_max: float = STEP_RANGE[1]
) -> list[tuple[float, float]]:
    """Steps ``h`` in ``[h_min, h_max]`` for which a sample ``k h`` (``k >= 1``) lies in the
    excursion ``[t_enter, t_exit]``: the union of ``[t_enter / k, t_exit / k]``, sorted, each
    widened by :data:`STEP_SLACK` (a superset of the exact set)."""
    if not 0 < t_enter < t_exit:
        raise ValueError(f"excursion [{t_enter}, {t_exit}] is out of range: allowed 0 < t_enter < t_exit")
    out = []
    for k in range(max(1, math.floor(t_enter / h_max)), math.ceil(t_exit / h_min) + 1):
        a, b = t_enter / k * (1 - STEP_SLACK), t_exit / k * (1 + STEP_SLACK)
        if b >= h_min and a <= h_max:
            out.append((max(a, h_min), min(b, h_max)))
    return sorted(out)


def _intersect(a: list, b: list) -> list:
    out, i, j = [], 0, 0
    while i < len(a) and j < len(b):
        lo, hi = max(a[i][0], b[j][0]), min(a[i][1], b[j][1])
        if lo <= hi:
            out.append((lo, hi))
        if a[i][1] < b[j][1]:
            i += 1
        else:
            j += 1
    return out


def steps_catching_all(
    excursions: list[tuple[float, float]], h_min: float = STEP_RANGE[0], h_max: float = STEP_RANGE[1]
) -> list[tuple[float, float]]:
    """The steps in ``[h_min, h_max]`` whose fixed-step finder catches *every* excursion
    ``(t_enter, t_exit)`` of the list (an empty list: each such finder misses one of them)."""
    sets = [steps_that_catch(a, b, h_min, h_max) for a, b in excursions]
    common = sets[0]
    for s in sets[1:]:
        common = _intersect(common, s)
    return common
