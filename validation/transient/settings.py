"""The settings of the Section 4 experiments (Figs. 9-11) as objects, each checked once, when it is made
(a ``ValueError`` naming the field and its range), before any computation.

* :class:`BasinsSettings` -- Fig. 9 (:func:`.experiments.basins`);
* :class:`UncertaintySettings` -- Fig. 10 (:func:`.experiments.uncertainty`);
* :class:`SurvivalSettings` -- Fig. 11 (:func:`.experiments.transients`).

Each is made for a run-size profile by ``of_profile(profile, **fields)`` (the profile's mesh, cap and
certification setting for what is not given: :mod:`validation.profiles`), and holds the engine's part as
one :class:`~gear_rattle.mapimpl.engine.transients.TransientSettings` (``transient``: how the initial
conditions are read, the capture distances, the cap, the chatter threshold), which
:func:`~gear_rattle.mapimpl.engine.transients.transient_times` takes as it is.  How the engine spreads the
run is apart from what is computed: :class:`~gear_rattle.mapimpl.engine.options.Execution`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from ...core.checks import MAX_AVERAGED, MAX_RESAMPLES, check_int
from ...core.paper import DELTA, DELTAS, PAPER_BOX
from ...mapimpl.engine.release import ReleaseSource
from ...mapimpl.engine.transients import MAX_MESH, TransientSettings, check_box
from ...mapimpl.sticking import STICK_TIME
from ..profiles import get_profile

#: Fig. 9's thresholds n: black = duration < n.
BASIN_NS = (90, 500, 1000, 2000)
#: Fig. 9 window: the whole phase circle, 0 < sdot0 < 0.5 (contains the paper's box).
BASIN_WINDOW = (0.0, 2.0 * math.pi, 0.0, 0.5)
#: The eps range of Fig. 10 (log-spaced; the number of values is the profile's ``n_eps``).
EPS_RANGE = (1e-9, 1e-3)
#: Largest seed (numpy's generators take 0 <= seed < 2**32 here).
MAX_SEED = 2**32 - 1


def _thresholds(name: str, ns) -> tuple[int, ...]:
    """``ns`` as a sorted tuple of one or more counts ``1 <= n <= MAX_AVERAGED``."""
    out = tuple(sorted(check_int(name, n, 1, MAX_AVERAGED) for n in ns))
    if not out:
        raise ValueError(f"{name}=() is out of range: allowed one or more integers 1 <= n <= {MAX_AVERAGED}")
    return out


def _mesh(nx: int, ny: int) -> tuple[int, int]:
    return check_int("nx", nx, 1, MAX_MESH), check_int("ny", ny, 1, MAX_MESH)


def default_eps(profile: str, n_eps: int | None = None, lo: float = EPS_RANGE[0], hi: float = EPS_RANGE[1]):
    """``n_eps`` (default: the profile's) log-spaced eps values from ``lo`` to ``hi``."""
    n_eps = get_profile(profile, "uncertainty")["n_eps"] if n_eps is None else int(n_eps)
    return np.logspace(np.log10(lo), np.log10(hi), n_eps)


def basins_mesh(profile: str, nx: int | None, ny: int | None) -> tuple[int, int]:
    """The Fig. 9 mesh ``(nx, ny)``: the profile's, ``ny`` with ``nx`` given keeping the profile's ratio
    ``ny/nx`` (quick 120 x 60: ``nx=121`` gives 121 x 60)."""
    size = get_profile(profile, "basins")
    if ny is None:
        ny = size["ny"] if nx is None else max(1, round(int(nx) * size["ny"] / size["nx"]))
    return (size["nx"] if nx is None else int(nx)), int(ny)


@dataclass(frozen=True)
class BasinsSettings:
    """Fig. 9: durations on an ``nx`` x ``ny`` mesh of ``window`` (``(tau_lo, tau_hi, sdot_lo, sdot_hi)``),
    computed once with cap ``max(ns)`` and thresholded at each ``n`` of ``ns``; the initial conditions
    read by ``ic_mode`` (and ``s0``) and captured within ``delta``; ``confirm``: the certified ``T_post``
    confirmed at a second precision.  ``transient``: the engine's settings (made from these)."""

    nx: int
    ny: int
    window: tuple = BASIN_WINDOW
    ns: tuple = BASIN_NS
    delta: float = DELTA
    ic_mode: str = "pre-impact"
    s0: float | None = None
    confirm: bool = False
    transient: TransientSettings = field(init=False, repr=False)

    def __post_init__(self) -> None:
        put = partial(object.__setattr__, self)
        nx, ny = _mesh(self.nx, self.ny)
        put("nx", nx)
        put("ny", ny)
        put("window", check_box("window", self.window))
        put("ns", _thresholds("ns", self.ns))
        put("confirm", bool(self.confirm))
        t = TransientSettings(ic_mode=self.ic_mode, s0=self.s0, delta=self.delta, deltas=(self.delta,), cap=self.ns[-1])
        put("transient", t)
        put("delta", t.delta)

    @classmethod
    def of_profile(
        cls, profile: str = "quick", nx: int | None = None, ny: int | None = None, **fields
    ) -> BasinsSettings:
        """The settings of ``profile`` with ``fields`` given (the mesh: :func:`basins_mesh`)."""
        nx, ny = basins_mesh(profile, nx, ny)
        return cls(nx=nx, ny=ny, confirm=get_profile(profile, "confirm"), **fields)


@dataclass(frozen=True)
class UncertaintySettings:
    """Fig. 10: ``n_points`` random points of ``box`` (``seed``), each with its two neighbours at
    ``tau0 +- eps`` for every ``eps`` (at least 3 values, ``0 < eps <= 0.1``); durations with cap
    ``max(ns)`` within ``delta``; ``n_boot`` bootstrap resamples of each exponent's fit; ``confirm``: as
    :class:`BasinsSettings`.  ``transient``: the engine's settings (made from these)."""

    n_points: int
    eps: tuple
    ns: tuple = (500, 1000)
    seed: int = 0
    box: tuple = PAPER_BOX
    delta: float = DELTA
    n_boot: int = 200
    confirm: bool = False
    transient: TransientSettings = field(init=False, repr=False)

    def __post_init__(self) -> None:
        put = partial(object.__setattr__, self)
        put("n_points", check_int("n_points", self.n_points, 10, MAX_AVERAGED))
        eps = np.asarray(self.eps, float) if np.ndim(self.eps) == 1 else np.array([])
        if eps.size < 3 or np.any(~np.isfinite(eps)) or np.any(eps <= 0) or np.any(eps > 0.1):
            raise ValueError("eps is out of range: allowed at least 3 values with 0 < eps <= 0.1")
        put("eps", tuple(eps.tolist()))
        put("ns", _thresholds("ns", self.ns))
        put("seed", check_int("seed", self.seed, 0, MAX_SEED))
        put("box", check_box("box", self.box))
        put("n_boot", check_int("n_boot", self.n_boot, 0, MAX_RESAMPLES))
        put("confirm", bool(self.confirm))
        t = TransientSettings(delta=self.delta, deltas=(self.delta,), cap=self.ns[-1])
        put("transient", t)
        put("delta", t.delta)

    @classmethod
    def of_profile(cls, profile: str = "quick", n_points: int | None = None, eps=None, **fields) -> UncertaintySettings:
        """The settings of ``profile`` with ``fields`` given (``n_points`` and ``eps``: the profile's)."""
        size = get_profile(profile, "uncertainty")
        n_points = size["n_points"] if n_points is None else n_points
        eps = default_eps(profile) if eps is None else eps
        return cls(n_points=n_points, eps=eps, confirm=get_profile(profile, "confirm"), **fields)


@dataclass(frozen=True)
class SurvivalSettings:
    """Fig. 11: durations on an ``nx`` x ``ny`` mesh of ``box`` with the engine's ``transient`` settings
    (the capture distances ``delta`` and ``deltas``, the ``cap``, ``ic_mode`` and ``s0``, the chatter
    threshold ``stick_time``); the Eq. (14) fit over ``[n_lo, n_hi]`` (default: from the median duration
    to where too few orbits are left) with ``n_boot`` bootstrap resamples of ``seed``; the orbits that
    stick composed with the ``T_post`` of ``release`` (:class:`~gear_rattle.mapimpl.engine.release.ReleaseSource`),
    confirmed at a second precision with ``confirm``; ``float64_rounding``: also certify ``T_post`` for
    the float64 roundings of the parameters (reported beside, not used)."""

    nx: int
    ny: int
    box: tuple = PAPER_BOX
    delta: float = DELTA
    deltas: tuple = DELTAS
    cap: int = 20000
    ic_mode: str = "pre-impact"
    s0: float | None = None
    stick_time: float = STICK_TIME
    n_lo: int | None = None
    n_hi: int | None = None
    n_boot: int = 200
    seed: int = 0
    release: ReleaseSource = ReleaseSource.CERTIFIED
    float64_rounding: bool = False
    confirm: bool = False
    transient: TransientSettings = field(init=False, repr=False)

    def __post_init__(self) -> None:
        put = partial(object.__setattr__, self)
        put("release", ReleaseSource.of(self.release))
        nx, ny = _mesh(self.nx, self.ny)
        put("nx", nx)
        put("ny", ny)
        put("box", check_box("box", self.box))
        for name in ("n_lo", "n_hi"):
            if getattr(self, name) is not None:
                put(name, check_int(name, getattr(self, name), 0, MAX_AVERAGED))
        put("n_boot", check_int("n_boot", self.n_boot, 0, MAX_RESAMPLES))
        put("seed", check_int("seed", self.seed, 0, MAX_SEED))
        put("float64_rounding", bool(self.float64_rounding))
        put("confirm", bool(self.confirm))
        t = TransientSettings(
            ic_mode=self.ic_mode,
            s0=self.s0,
            delta=self.delta,
            deltas=self.deltas,
            cap=self.cap,
            stick_time=self.stick_time,
        )
        put("transient", t)
        for name in ("delta", "cap", "s0", "stick_time"):
            put(name, getattr(t, name))

    @classmethod
    def of_profile(
        cls, profile: str = "quick", nx: int | None = None, ny: int | None = None, cap: int | None = None, **fields
    ) -> SurvivalSettings:
        """The settings of ``profile`` with ``fields`` given (the mesh ``nx`` x ``ny``, ``ny`` = ``nx``, and
        the ``cap``: the profile's)."""
        size = get_profile(profile, "transients")
        nx = size["n"] if nx is None else nx
        ny = nx if ny is None else ny
        cap = size["cap"] if cap is None else cap
        return cls(nx=nx, ny=ny, cap=cap, confirm=get_profile(profile, "confirm"), **fields)

    def fit_keywords(self) -> dict:
        """The keyword arguments of :func:`.analysis.fit_survival` these settings give."""
        return dict(cap=self.cap, n_lo=self.n_lo, n_hi=self.n_hi, n_boot=self.n_boot, seed=self.seed)

    def replace(self, **changes) -> SurvivalSettings:
        """A copy with some fields changed (checked again)."""
        return dataclasses.replace(self, **changes)


def settings_from(cls, settings, profile: str, fields: dict):
    """The settings of an experiment: ``settings`` (a ``cls``) with ``fields`` replaced, or
    ``cls.of_profile(profile, **fields)``; ``TypeError`` for ``settings`` of another type."""
    if settings is None:
        return cls.of_profile(profile, **fields)
    if not isinstance(settings, cls):
        raise TypeError(f"settings is a {type(settings).__name__}: allowed a {cls.__name__} or None")
    return dataclasses.replace(settings, **fields) if fields else settings


__all__ = [
    "BASIN_NS",
    "BASIN_WINDOW",
    "EPS_RANGE",
    "MAX_SEED",
    "default_eps",
    "basins_mesh",
    "BasinsSettings",
    "UncertaintySettings",
    "SurvivalSettings",
    "settings_from",
]
