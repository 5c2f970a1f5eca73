"""Deliberately wrong implementations of the golden suite's model ("mutants"), for
tests/test_golden_mutants.py: each has one bug an outside implementer could make, and
``gear-rattle check`` must fail it.

:func:`run` is a small implementation written from docs/golden.md alone (the impact law Eq. 11, the
sticking policy in Python floats, the row conventions) around a flight finder: the correct one is the
map track's certified :func:`mapimpl.finder.first_impact` (Eqs. 7-8); :func:`fixed_step_contact` samples
the flight at ``t = k h`` and looks for a sign change of the gap.  A mutant is a :class:`Mutant`: the
base with one decision changed, each field a few lines of :func:`run` and :func:`policy`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import gear_rattle  # noqa: F401  (float64: importing the package switches JAX to it)
import jax

from gear_rattle.core.horizons import T_MAX
from gear_rattle.mapimpl.finder import first_impact
from gear_rattle.mapimpl.flight import flight
from gear_rattle.validation.golden.rules.conditioning import FLIGHT_ERROR, gap_error, largest_force

TWO_PI = 2 * math.pi
_first_impact = jax.jit(first_impact)
#: Samples per evaluation of the fixed-step and extremum scans (one compiled shape).
CHUNK = 4096
_flight = jax.jit(lambda t, th, v0, a, b, g: flight(t, th, v0, a, b, g))


@dataclass(frozen=True)
class Mutant:
    """The base implementation (all defaults) or one of its mutants (one field changed)."""

    name: str = "base"
    bug_class: str = ""
    #: fixed-step sign-change finder with this step (0: the certified finder)
    step: float = 0.0
    #: accept a contact where the gap has a local minimum below this tolerance
    contact_tol: float = 0.0
    #: sticking threshold: t_acc <= stick_scale * STICK_TIME
    stick_scale: float = 1.0
    lower_wall_sticks: bool = True
    #: f_in = lower_sign * f on the lower wall (the force presses into s = -1 where f < 0)
    lower_sign: float = -1.0
    #: the lower wall's release phase phi + pi - asin(gamma/R); False: the upper wall's phi + asin(gamma/R)
    lower_branch: bool = True
    #: never released where gamma/R >= 1 on the pressing side (d gamma/R >= 1); False: gamma/R >= 1 on every wall
    never_on_pressing_side: bool = True
    #: stick only if the release delay exceeds t_acc
    delay_check: bool = True
    #: t_acc where (1 - r) f_in = 0: +inf (correct) or 0 (a 'safe division')
    t_acc_if_no_loss: float = math.inf
    #: the finder re-detects the wall it leaves after a release (the t^3 trap): an impact row at the release
    redetect_after_release: bool = False
    #: a flight that never lands gets an impact row at the search horizon T_MAX
    row_at_horizon: bool = False
    #: the stick/release rows of a step whose flight never lands are dropped
    drop_rows_if_no_landing: bool = False
    #: the policy of the last counted impact is applied and its stick/release rows written
    trailing_rows: bool = False
    #: tau_mod_2pi written as this constant (None: tau mod 2 pi)
    phase_value: float | None = None
    #: not a bug: the position held in float64 as ``y = s + coordinate`` (None: the finder's exact gaps), the
    #: contact where the computed ``y`` reaches the wall's value (:func:`rounded_coordinate_contact`)
    coordinate: float | None = None
    #: not a bug: every contact displaced by the per-impact error the tolerances assume (docs/golden.md): to
    #: where the true gap is ``gap_scale e`` beyond the wall (``e = 2 2^-52 + 3e-14 h max(1, dt / 2 pi)``,
    #: ``"late"``), before it (``"early"``), or a sign per contact from the bits of its time (``"random"``); ""
    #: none (:func:`displaced_contact`)
    gap_error: str = ""
    #: the multiple of the modelled gap error a ``gap_error`` variant makes (1: a correct implementation; > 1 a
    #: planted error of that size, for the sensitivity of the suite)
    gap_scale: float = 1.0
    #: a planted error of a size (the sensitivity of the suite, issue 36): the restitution ``r (1 + eps)`` in
    #: every bounce (0: none), and every value written with this many significant digits (0: ``repr``)
    restitution: float = 0.0
    digits: int = 0
    #: more planted errors of a size: ``2 pi (1 + eps)`` wherever the implementation reduces a phase, and the
    #: forcing amplitude ``alpha (1 + eps)`` in its flights (0: none)
    two_pi: float = 0.0
    forcing: float = 0.0


BASE = Mutant()


# ---------------------------------------------------------------------------------------------
# finders: (theta0, s0, v0, params, release) -> (t, wall, v) or None (no wall within T_MAX)


def certified_contact(th, s0, v0, p, release, m: Mutant):
    h = _first_impact(th, s0, v0, p["alpha"], p["beta"], p["gamma"])
    if int(h.status) not in (0, 1):  # HIT, GRAZE
        return None
    return float(h.t), int(h.wall), float(h.v)


def _s(t, th, s0, v0, p):
    """``s`` at the flight times ``t`` (an array of CHUNK, or a scalar)."""
    return s0 + np.asarray(_flight(t, th, v0, p["alpha"], p["beta"], p["gamma"]).ds)


def _v(t, th, v0, p) -> float:
    return float(_flight(t, th, v0, p["alpha"], p["beta"], p["gamma"]).v)


def _bisect(fun, lo, hi, n=200):
    """Root of ``fun`` (``fun(lo) > 0 >= fun(hi)``) in ``[lo, hi]`` by bisection to float resolution."""
    for _ in range(n):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if fun(mid) > 0:
            lo = mid
        else:
            hi = mid
    return hi


def fixed_step_contact(th, s0, v0, p, release, m: Mutant):
    """Samples at ``t = k h`` (``k >= 1``); the first one beyond a wall brackets the contact, which is
    then bisected.  Misses every excursion that falls between two samples."""
    h = m.step
    for k0 in range(1, int(T_MAX / h) + 1, CHUNK):
        t = h * np.arange(k0, k0 + CHUNK, dtype=float)
        s = _s(t, th, s0, v0, p)
        out = np.nonzero((s > 0.0) | (s < -1.0))[0]
        if out.size:
            i = int(out[0])
            wall = 0 if s[i] > 0.0 else -1
            side = -1.0 if wall == 0 else 1.0  # gap = side * s + (wall == -1)
            lo = t[i - 1] if i > 0 else h * (k0 - 1)
            tr = _bisect(lambda x: side * _s(x, th, s0, v0, p) - wall, lo, t[i])
            return float(tr), wall, _v(tr, th, v0, p)
    return None


def tolerant_contact(th, s0, v0, p, release, m: Mutant):
    """The certified contact, or earlier a local extremum of ``s`` within ``contact_tol`` of a wall
    (found as a sign change of ``s'`` on a grid of 0.01, then bisected), taken as a contact with
    ``sdot = 0``."""
    hit = certified_contact(th, s0, v0, p, release, m)
    t_end = hit[0] if hit else T_MAX
    dt = 0.01
    for k0 in range(1, int(t_end / dt) + 2, CHUNK):
        t = dt * np.arange(k0, k0 + CHUNK, dtype=float)
        fp = _flight(t, th, v0, p["alpha"], p["beta"], p["gamma"])
        v = np.asarray(fp.v)
        for i in np.nonzero(np.sign(v[1:]) != np.sign(v[:-1]))[0]:
            if t[i + 1] > t_end:
                break
            sgn = 1.0 if v[i] > 0 else -1.0
            te = _bisect(lambda x: sgn * _v(x, th, v0, p), t[i], t[i + 1])
            s = float(_s(te, th, s0, v0, p))
            if sgn > 0 and -s < m.contact_tol:
                return float(te), 0, 0.0
            if sgn < 0 and s + 1.0 < m.contact_tol:
                return float(te), -1, 0.0
    return hit


def rounded_coordinate_contact(hit, th, s0, v0, p, m: Mutant):
    """The contact as an implementation finds it that holds the position as the float64 ``y = s + c`` and
    stops where the computed ``y`` reaches the wall's value ``w + c``: the first sign change of
    ``fl(y0 + ds(t)) - (w + c)`` before the true contact ``t*``, bisected on ``[t*/2, t*]``.  Correct, but
    the rounding step of ``y`` at the wall (2^-53 for ``s`` at ``s = -1`` and for ``s + 1`` at ``s = 0``)
    makes a bounce of speed ``v`` land up to ``2^-54 / v`` early, every bounce on the same side: what the
    chatter rule of docs/golden.md budgets for."""
    t, wall, v = hit
    y0, yw, side = s0 + m.coordinate, wall + m.coordinate, 1.0 if wall == 0 else -1.0

    def reached(x):  # the computed coordinate is at the wall or beyond
        return side * ((y0 + float(_s(x, th, 0.0, v0, p))) - yw) >= 0.0

    if reached(0.5 * t) or not reached(t):
        return hit
    tr = _bisect(lambda x: -1.0 if reached(x) else 1.0, 0.5 * t, t)
    return tr, wall, _v(tr, th, v0, p)


def displaced_contact(hit, th, s0, v0, p, m: Mutant):
    """The contact as found by an implementation whose computed gap is off by ``gap_scale`` times
    ``e = gap_error(h, t)`` (``h`` the flight's height, sampled; ``t`` its duration): the time moves by
    ``e / |v|`` and the velocity is the flight's there, plus an error of ``FLIGHT_ERROR V`` of the same sign
    (``V = max(|v0|, |v|, F)``).  The per-contact error of the tolerance rule, made on purpose."""
    t, wall, v = hit
    h = min(1.0, float(np.max(np.abs(_s(np.linspace(0.0, t, CHUNK), th, 0.0, v0, p)))))
    e = m.gap_scale * gap_error(h, t)
    sign = {"late": 1.0, "early": -1.0}.get(m.gap_error) or (1.0 if hash(t) & 1 else -1.0)
    tr = t + sign * e / abs(v)
    scale = max(abs(v0), abs(v), largest_force(_params(p)))
    return tr, wall, _v(tr, th, v0, p) + sign * m.gap_scale * FLIGHT_ERROR * scale


def _params(p: dict):
    from gear_rattle.core.params import Params

    return Params(p["alpha"], p["beta"], p["gamma"], p["r"])


def two_pi(m: Mutant) -> float:
    """The implementation's ``2 pi`` (perturbed by :attr:`Mutant.two_pi`)."""
    return TWO_PI * (1.0 + m.two_pi)


def contact(th, s0, v0, p, release, m: Mutant):
    if m.forcing:
        p = {**p, "alpha": p["alpha"] * (1.0 + m.forcing)}
    if release and m.redetect_after_release:
        return 0.0, int(s0), 0.0
    finder = fixed_step_contact if m.step else (tolerant_contact if m.contact_tol else certified_contact)
    hit = finder(th, s0, v0, p, release, m)
    if hit is not None and m.gap_error:
        return displaced_contact(hit, th, s0, v0, p, m)
    return hit if hit is None or m.coordinate is None else rounded_coordinate_contact(hit, th, s0, v0, p, m)


# ---------------------------------------------------------------------------------------------
# the sticking policy (docs/golden.md)


def policy(tau, wall, sdot, p, stick_time, m: Mutant):
    """``None`` (bounce), ``(t_acc, None)`` (stuck forever) or ``(t_acc, (release_tau, release_phase))``."""
    a, b, g, r = p["alpha"], p["beta"], p["gamma"], p["r"]
    if wall == -1 and not m.lower_wall_sticks:
        return None
    d = 1.0 if wall == 0 else m.lower_sign
    f_in = d * (-a * math.sin(tau) + a * b * math.cos(tau) + g)
    if not f_in > 0:
        return None
    u, denom = r * abs(sdot), (1 - r) * f_in
    t_acc = 2 * u / denom if denom > 0 else m.t_acc_if_no_loss
    if not t_acc <= m.stick_scale * stick_time:
        return None
    R, phi = a * math.sqrt(1 + b * b), math.atan(b)
    c = g / R if R > 0 else math.copysign(math.inf, g)
    if R == 0 or (c if wall == 0 else (-c if m.never_on_pressing_side else c)) >= 1:
        return t_acc, None
    c = max(-1.0, min(1.0, c))
    phase = phi + (math.asin(c) if wall == 0 or not m.lower_branch else math.pi - math.asin(c))
    delay = (phase - tau) % two_pi(m)
    if m.delay_check and not delay > t_acc:
        return None
    return t_acc, (tau + delay, phase % two_pi(m))


# ---------------------------------------------------------------------------------------------
# the orbit and its rows


def run(settings: dict, m: Mutant = BASE) -> list[tuple]:
    """Rows ``(n, tau, wall, sdot, kind)`` of a case (``settings.json`` as a dict)."""
    p, ini, st = settings["params"], settings["initial_state"], settings["stick_time"]
    rows: list[tuple] = []
    if ini["kind"] == "pre-impact":
        tau, sdot = ini["tau0"], ini["sdot0"]
        wall = 0 if sdot > 0 else -1
    else:
        hit = contact(ini["tau0"] % two_pi(m), ini["s0"], ini["sdot0"], p, False, m)
        if hit is None:
            return rows
        tau, wall, sdot = ini["tau0"] + hit[0], hit[1], hit[2]
    rows.append((0, tau, wall, sdot, "impact"))
    for n in range(1, int(settings["n_impacts"]) + 1):
        dec = policy(tau, wall, sdot, p, st, m)
        step_rows = []
        if dec is None:
            start, th, v0, release = tau, tau % two_pi(m), -p["r"] * (1.0 + m.restitution) * sdot, False
        else:
            step_rows.append((n - 1, tau + dec[0], wall, math.nan, "stick"))
            if dec[1] is None:
                return rows + step_rows
            (start, th), v0, release = dec[1], 0.0, True
            step_rows.append((n - 1, start, wall, math.nan, "release"))
        hit = contact(th, float(wall), v0, p, release, m)
        if hit is None:
            if m.row_at_horizon:
                step_rows.append((n, start + T_MAX, wall, 0.0, "impact"))
            return rows + ([] if m.drop_rows_if_no_landing else step_rows)
        tau, wall, sdot = start + hit[0], hit[1], hit[2]
        rows += step_rows + [(n, tau, wall, sdot, "impact")]
    if m.trailing_rows:
        dec = policy(tau, wall, sdot, p, st, m)
        if dec is not None:
            n = int(settings["n_impacts"])
            rows.append((n, tau + dec[0], wall, math.nan, "stick"))
            if dec[1] is not None:
                rows.append((n, dec[1][0], wall, math.nan, "release"))
    return rows


def write_csv(rows: list[tuple], path: Path, m: Mutant = BASE) -> None:
    """The documented output layout ``n,tau,tau_mod_2pi,wall,sdot,kind`` (repr of every float)."""
    lines = ["n,tau,tau_mod_2pi,wall,sdot,kind"]

    def text(x: float) -> str:
        return f"{x:.{m.digits}g}" if m.digits else repr(x)

    for n, tau, wall, sdot, kind in rows:
        phase = tau % two_pi(m) if m.phase_value is None else m.phase_value
        lines.append(f"{n},{text(tau)},{text(phase)},{wall},{'' if math.isnan(sdot) else text(sdot)},{kind}")
    Path(path).write_text("\n".join(lines) + "\n")
