"""Observers: what the engine measures along each orbit, and when it stops one.

The engine (:mod:`gear_rattle.mapimpl.engine.kernel`) iterates the impact map (Eqs. 11-13 with the
sticking policy) for many orbits at once; an *observer* sees every pre-impact state an orbit
arrives at (an :class:`Impact`) and keeps a little per-orbit state of its own.  It can stop the
orbit (``stop``); what it keeps is returned per initial condition at the end.  An observer is a
static, hashable configuration (it is part of the compiled kernel); its numerical inputs (target
points, thresholds) are passed as run constants (:meth:`Observer.consts`), so changing them does not
recompile.  All methods are pure ``jax.numpy`` on the scalar state of one orbit (the engine vmaps).

* :class:`Capture` -- first impact within ``delta`` of a periodic orbit, for several deltas; stops
  when within the smallest (Figs. 9-11: capture by the stable 4-impact orbit; the crisis alpha1:
  escape from the pre-crisis chaotic set to that orbit).
* :class:`BandEscape` -- bursts out of a p-band chaotic set: the p-impact return time differs from
  ``2 pi m`` by more than a threshold (the interior crisis r1).
* :class:`Laminar` -- laminar phases: runs of impacts near a periodic orbit (type-I intermittency, r2).
* :class:`Sample` -- records the states of impacts ``n_start .. n_start + keep - 1``
  (bifurcation diagrams, periods).
* :class:`Tangent` -- Lyapunov exponents by QR re-orthonormalisation of the step Jacobians
  (Figs. 4b, 8b, the atlas).

The one distance to a periodic orbit used by every capture test is :func:`orbit_distance`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ...core import jax_config  # noqa: F401
import jax.numpy as jnp

from ...core.checks import MAX_AVERAGED, MAX_PERIOD, check_int
from ...core.phase import TWO_PI

_I32, _F64, _BOOL = jnp.int32, jnp.float64, jnp.bool_


class Impact(NamedTuple):
    """One arrival of an orbit at a pre-impact state (scalars of one lane).

    ``n``: impact index (0: the initial state); ``theta``: tau mod 2 pi; ``sdot``: velocity just before
    the impact; ``wall``: 0 or -1; ``cycles``: whole driving periods elapsed (tau = 2 pi cycles +
    theta); ``dt``: time since the previous impact (sticking time included; 0 for ``n = 0``);
    ``loaded``: this is the initial state; ``stick``: the step *from* this impact sticks to the wall
    (sticking policy); ``jac``: the Jacobian ``d(tau_n, sdot_n)/d(tau_{n-1}, sdot_{n-1})`` of the step
    that led here (Eqs. 12-13, analytic; zero after a sticking step; only when an observer asks for it,
    else None); ``jac_ok``: ``jac`` is meaningful (not for ``n = 0``).
    """

    n: jnp.ndarray
    theta: jnp.ndarray
    sdot: jnp.ndarray
    wall: jnp.ndarray
    cycles: jnp.ndarray
    dt: jnp.ndarray
    loaded: jnp.ndarray
    stick: jnp.ndarray
    jac: jnp.ndarray | None
    jac_ok: jnp.ndarray


def orbit_distance(theta, sdot, wall, po_theta, po_sdot, po_wall):
    """Sup-norm distance of a pre-impact state to the nearest point of a periodic orbit on the same wall:
    ``max(|theta - theta_k| wrapped to [0, pi], |sdot - sdot_k|)``, minimised over the orbit's points
    (``inf`` when no point is on ``wall``).  The capture criterion of Figs. 9-11."""
    dth = jnp.abs(theta - po_theta)
    dth = jnp.minimum(dth, TWO_PI - dth)
    d = jnp.maximum(dth, jnp.abs(sdot - po_sdot))
    return jnp.min(jnp.where(wall == po_wall, d, jnp.inf))


def euclidean_distance(theta, sdot, po_theta, po_sdot):
    """Euclidean distance in the ``(theta mod 2 pi, sdot)`` plane to the nearest periodic-orbit point."""
    dth = jnp.abs(theta - po_theta)
    dth = jnp.minimum(dth, TWO_PI - dth)
    return jnp.min(jnp.sqrt(dth * dth + (sdot - po_sdot) ** 2))


class Observer:
    """Base class: a static configuration with per-orbit fields, run constants and an update rule.

    Subclasses are frozen dataclasses whose fields are the *static* configuration (shapes, flags);
    numerical inputs go in :meth:`consts`.  ``needs_jacobian``: the engine computes the step Jacobian
    for :class:`Impact` (costs a little on every micro-step).
    """

    needs_jacobian = False

    def fields(self) -> dict:
        """``{name: (dtype, shape, initial value)}`` of the per-orbit state (shape per orbit)."""
        raise NotImplementedError

    def outputs(self) -> tuple[str, ...]:
        """Fields returned per initial condition."""
        return tuple(self.fields())

    def consts(self) -> dict:
        """Numerical run constants (arrays), available to :meth:`update` as ``k``."""
        return {}

    def update(self, o: dict, ev: Impact, k: dict):
        """New per-orbit state and whether to stop the orbit, at an arrival ``ev``."""
        raise NotImplementedError


def _target_arrays(theta, sdot, wall):
    th = np.atleast_1d(np.asarray(theta, np.float64))
    sd = np.atleast_1d(np.asarray(sdot, np.float64))
    w = np.atleast_1d(np.asarray(wall, np.int32))
    if not (th.shape == sd.shape == w.shape and th.ndim == 1 and th.size >= 1):
        raise ValueError("target: theta, sdot and wall must be 1-D arrays of the same length >= 1")
    if not (np.all(np.isfinite(th)) and np.all(np.isfinite(sd)) and np.all(np.isin(w, (0, -1)))):
        raise ValueError("target is out of range: allowed finite theta, sdot and walls 0 or -1")
    return th, sd, w


@dataclass(frozen=True, eq=False)
class Capture(Observer):
    """First impact index within each of ``deltas`` (sup norm, :func:`orbit_distance`) of the periodic
    orbit ``(theta, sdot, wall)``; stops the orbit when within all of them.  Output ``hit``: shape
    ``(len(deltas),)``, -1 = not within that delta (yet)."""

    theta: np.ndarray
    sdot: np.ndarray
    wall: np.ndarray
    deltas: np.ndarray

    def __post_init__(self):
        th, sd, w = _target_arrays(self.theta, self.sdot, self.wall)
        d = np.sort(np.atleast_1d(np.asarray(self.deltas, np.float64)))[::-1]
        if d.ndim != 1 or d.size == 0 or not np.all(np.isfinite(d)) or np.any(d <= 0):
            raise ValueError(f"deltas={self.deltas!r} is out of range: allowed one or more finite deltas > 0")
        for name, v in (("theta", th), ("sdot", sd), ("wall", w), ("deltas", d)):
            object.__setattr__(self, name, v)

    def _key(self):
        return ("Capture", self.theta.size, self.deltas.size)

    def __hash__(self):
        return hash(self._key())

    def __eq__(self, other):
        return isinstance(other, Capture) and self._key() == other._key()

    def fields(self):
        return {"hit": (_I32, (self.deltas.size,), -1)}

    def consts(self):
        return {
            "th": jnp.asarray(self.theta),
            "sd": jnp.asarray(self.sdot),
            "w": jnp.asarray(self.wall),
            "deltas": jnp.asarray(self.deltas),
        }

    def update(self, o, ev, k):
        d = orbit_distance(ev.theta, ev.sdot, ev.wall, k["th"], k["sd"], k["w"])
        newly = (o["hit"] < 0) & (d < k["deltas"])
        hit = jnp.where(newly, ev.n, o["hit"])
        return {"hit": hit}, jnp.all(hit >= 0)


@dataclass(frozen=True)
class BandEscape(Observer):
    """Bursts out of a chaotic set of ``p`` bands visited in turn once per ``m`` driving periods
    (the 6-band attractor before the interior crisis r1): an impact is *out* when the p-impact return
    time ``tau_n - tau_{n-p}`` differs from ``2 pi m`` by more than ``threshold``; a burst is an out
    impact after at least ``min_inside`` impacts in. Counted from impact ``n_start``.
    Outputs: ``first`` (impact index of the first burst, -1 none), ``bursts`` (number of bursts),
    ``exposure`` (impacts observed).  ``stop_at_first``: stop the orbit at its first burst."""

    p: int = 6
    m: int = 1
    stop_at_first: bool = False
    threshold: float = 0.6
    min_inside: int = 60
    n_start: int = 0

    def __post_init__(self):
        check_int("p", self.p, 1, MAX_PERIOD)
        check_int("m", self.m, 1, MAX_PERIOD)
        if not (np.isfinite(self.threshold) and 0 < self.threshold < np.pi):
            raise ValueError(f"threshold={self.threshold!r} is out of range: allowed 0 < threshold < pi")
        check_int("min_inside", self.min_inside, 0, MAX_AVERAGED)
        check_int("n_start", self.n_start, 0, MAX_AVERAGED)

    def __hash__(self):
        return hash(("BandEscape", self.p, self.stop_at_first))

    def __eq__(self, other):
        return isinstance(other, BandEscape) and (self.p, self.stop_at_first) == (other.p, other.stop_at_first)

    def fields(self):
        return {
            "ring": (_F64, (self.p,), 0.0),
            "pos": (_I32, (), 0),
            "cnt": (_I32, (), 0),
            "inside": (_I32, (), 0),
            "first": (_I32, (), -1),
            "bursts": (_I32, (), 0),
            "exposure": (_I32, (), 0),
        }

    def outputs(self):
        return ("first", "bursts", "exposure")

    def consts(self):
        return {
            "period": jnp.asarray(TWO_PI * self.m, _F64),
            "thr": jnp.asarray(self.threshold, _F64),
            "min_in": jnp.asarray(self.min_inside, _I32),
            "n0": jnp.asarray(self.n_start, _I32),
        }

    def update(self, o, ev, k):
        use = ~ev.loaded & (ev.n > k["n0"])
        ring = jnp.where(use, o["ring"].at[o["pos"]].set(ev.dt), o["ring"])
        pos = jnp.where(use, (o["pos"] + 1) % self.p, o["pos"])
        cnt = jnp.where(use, jnp.minimum(o["cnt"] + 1, self.p), o["cnt"])
        full = cnt >= self.p
        out = full & (jnp.abs(jnp.sum(ring) - k["period"]) > k["thr"])
        burst = use & out & (o["inside"] >= k["min_in"])
        inside = jnp.where(use & full, jnp.where(out, 0, o["inside"] + 1), o["inside"])
        first = jnp.where(burst & (o["first"] < 0), ev.n, o["first"])
        new = {
            "ring": ring,
            "pos": pos,
            "cnt": cnt,
            "inside": inside,
            "first": first,
            "bursts": o["bursts"] + burst.astype(_I32),
            "exposure": o["exposure"] + use.astype(_I32),
        }
        return new, (burst & self.stop_at_first)


@dataclass(frozen=True, eq=False)
class Laminar(Observer):
    """Laminar phases of type-I intermittency: maximal runs of consecutive impacts within Euclidean
    distance ``eps`` (:func:`euclidean_distance`) of a periodic orbit (the ghost of the fold orbit at
    r2), counted from impact ``n_start``; a run counts when it is at least ``min_length`` long and
    both ends were seen (it started after an impact outside).  Outputs: ``count``, ``total`` (sum of
    lengths), ``total_sq`` (sum of squared lengths), ``exposure`` (impacts observed) and ``run``: the
    length of the run in progress when the orbit ended (0 if its last observed impact was outside), so
    a run that lasts to the end began at impact ``n - run + 1``."""

    theta: np.ndarray
    sdot: np.ndarray
    eps: float = 0.05
    min_length: int = 12
    n_start: int = 0

    def __post_init__(self):
        th, sd, _ = _target_arrays(self.theta, self.sdot, np.zeros(np.size(self.theta), np.int32))
        object.__setattr__(self, "theta", th)
        object.__setattr__(self, "sdot", sd)
        if not (np.isfinite(self.eps) and self.eps > 0):
            raise ValueError(f"eps={self.eps!r} is out of range: allowed eps > 0")
        if int(self.min_length) < 1 or int(self.n_start) < 0:
            raise ValueError("min_length (>= 1) or n_start (>= 0) is out of range")

    def __hash__(self):
        return hash(("Laminar", self.theta.size))

    def __eq__(self, other):
        return isinstance(other, Laminar) and self.theta.size == other.theta.size

    def fields(self):
        return {
            "run": (_I32, (), 0),
            "ok_start": (_BOOL, (), False),
            "seen_out": (_BOOL, (), False),
            "count": (_I32, (), 0),
            "total": (_F64, (), 0.0),
            "total_sq": (_F64, (), 0.0),
            "exposure": (_I32, (), 0),
        }

    def outputs(self):
        return ("count", "total", "total_sq", "exposure", "run")

    def consts(self):
        return {
            "th": jnp.asarray(self.theta),
            "sd": jnp.asarray(self.sdot),
            "eps": jnp.asarray(self.eps, _F64),
            "min_len": jnp.asarray(self.min_length, _I32),
            "n0": jnp.asarray(self.n_start, _I32),
        }

    def update(self, o, ev, k):
        use = ev.n >= k["n0"]
        near = euclidean_distance(ev.theta, ev.sdot, k["th"], k["sd"]) < k["eps"]
        ends = use & ~near & (o["run"] > 0)
        done = ends & o["ok_start"] & (o["run"] >= k["min_len"])
        L = o["run"].astype(_F64)
        starts = use & near & (o["run"] == 0)
        new = {
            "run": jnp.where(use, jnp.where(near, o["run"] + 1, 0), o["run"]),
            "ok_start": jnp.where(starts, o["seen_out"], o["ok_start"]),
            "seen_out": o["seen_out"] | (use & ~near),
            "count": o["count"] + done.astype(_I32),
            "total": o["total"] + jnp.where(done, L, 0.0),
            "total_sq": o["total_sq"] + jnp.where(done, L * L, 0.0),
            "exposure": o["exposure"] + use.astype(_I32),
        }
        return new, jnp.asarray(False)


@dataclass(frozen=True)
class Sample(Observer):
    """The states of impacts ``n_start, ..., n_start + keep - 1``: ``theta``, ``sdot``, ``wall`` and
    ``cycles`` (whole periods elapsed), each of shape ``(keep,)``; stops after the last one.
    Entries never reached stay NaN (theta, sdot) / 0."""

    keep: int
    n_start: int = 0

    def __post_init__(self):
        check_int("keep", self.keep, 1, 1_000_000)
        check_int("n_start", self.n_start, 0, MAX_AVERAGED)

    def __hash__(self):
        return hash(("Sample", int(self.keep)))

    def __eq__(self, other):
        return isinstance(other, Sample) and int(self.keep) == int(other.keep)

    def fields(self):
        K = int(self.keep)
        return {
            "theta": (_F64, (K,), np.nan),
            "sdot": (_F64, (K,), np.nan),
            "wall": (_I32, (K,), 0),
            "cycles": (_I32, (K,), 0),
        }

    def consts(self):
        return {"n0": jnp.asarray(self.n_start, _I32)}

    def update(self, o, ev, k):
        i = ev.n - k["n0"]
        inside = (i >= 0) & (i < int(self.keep))
        j = jnp.where(inside, i, int(self.keep))  # out of range -> dropped
        new = {
            name: o[name].at[j].set(val, mode="drop")
            for name, val in (("theta", ev.theta), ("sdot", ev.sdot), ("wall", ev.wall), ("cycles", ev.cycles))
        }
        return new, i >= int(self.keep) - 1


def givens_qr(Z):
    """``Q, R`` of a 2x2 matrix with ``R`` upper triangular and ``R[1, 1] >= 0``, ``R[0, 0] >= 0``
    (a Givens rotation; exact for ``Z[1, 0] = 0``)."""
    a, c = Z[0, 0], Z[1, 0]
    h = jnp.hypot(a, c)
    hs = jnp.where(h > 0.0, h, 1.0)
    cs, sn = jnp.where(h > 0.0, a / hs, 1.0), jnp.where(h > 0.0, c / hs, 0.0)
    G = jnp.array([[cs, sn], [-sn, cs]])  # G Z = R
    R = G @ Z
    Q = G.T
    flip = jnp.where(R[1, 1] < 0.0, -1.0, 1.0)
    Q = Q * jnp.array([1.0, flip])[None, :]
    R = R * jnp.array([1.0, flip])[:, None]
    return Q, R


@dataclass(frozen=True)
class Tangent(Observer):
    """Lyapunov exponents (Figs. 4b, 8b) by QR re-orthonormalisation of the step Jacobians from impact
    ``n_start``: ``J_n Q_{n-1} = Q_n R_n``, ``log_r = sum ln |R_n[i, i]|`` over the free steps (a
    sticking step forgets its input, ``J = 0``: it is counted in ``n_stuck`` and Q restarts at the
    identity).  Steps ending at impacts ``n_start < n <= n_end`` are used (``n_end`` -1: no end).
    Outputs ``log_r`` (2,), ``n_free``, ``n_stuck`` and the state at ``n_start``
    (``sdot0``, ``theta0``, ``cycles0``) for the closed-form check ``lambda1 + lambda2 = mean ln|det J|``."""

    n_start: int = 0
    n_end: int = -1
    needs_jacobian = True

    def __post_init__(self):
        if int(self.n_start) < 0:
            raise ValueError(f"n_start={self.n_start!r} is out of range: allowed >= 0")
        if int(self.n_end) != -1 and int(self.n_end) <= int(self.n_start):
            raise ValueError(f"n_end={self.n_end!r} is out of range: allowed -1 (no end) or n_end > n_start")

    def __hash__(self):
        return hash("Tangent")

    def __eq__(self, other):
        return isinstance(other, Tangent)

    def fields(self):
        return {
            "Q": (_F64, (2, 2), np.eye(2)),
            "log_r": (_F64, (2,), 0.0),
            "n_free": (_I32, (), 0),
            "n_stuck": (_I32, (), 0),
            "sdot0": (_F64, (), np.nan),
            "theta0": (_F64, (), np.nan),
            "cycles0": (_I32, (), 0),
        }

    def outputs(self):
        return ("log_r", "n_free", "n_stuck", "sdot0", "theta0", "cycles0")

    def consts(self):
        end = np.iinfo(np.int32).max if int(self.n_end) < 0 else int(self.n_end)
        return {"n0": jnp.asarray(self.n_start, _I32), "n1": jnp.asarray(end, _I32)}

    def update(self, o, ev, k):
        at0 = ev.n == k["n0"]
        step = ev.jac_ok & (ev.n > k["n0"]) & (ev.n <= k["n1"])
        J = ev.jac
        stuck = step & jnp.all(J == 0.0)
        free = step & ~stuck
        Qn, R = givens_qr(J @ o["Q"])
        d = jnp.abs(jnp.diagonal(R))
        new = {
            "Q": jnp.where(free, Qn, jnp.where(at0 | stuck, jnp.eye(2), o["Q"])),
            "log_r": o["log_r"] + jnp.where(free, jnp.log(d), 0.0),
            "n_free": o["n_free"] + free.astype(_I32),
            "n_stuck": o["n_stuck"] + stuck.astype(_I32),
            "sdot0": jnp.where(at0, ev.sdot, o["sdot0"]),
            "theta0": jnp.where(at0, ev.theta, o["theta0"]),
            "cycles0": jnp.where(at0, ev.cycles, o["cycles0"]),
        }
        return new, jnp.asarray(False)


__all__ = [
    "Impact",
    "orbit_distance",
    "euclidean_distance",
    "Observer",
    "Capture",
    "BandEscape",
    "Laminar",
    "Sample",
    "givens_qr",
    "Tangent",
]
