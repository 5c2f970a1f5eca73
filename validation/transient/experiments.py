"""The experiments of Section 4 (Figs. 9-11), computed and returned as typed results.

Each function runs the transient engine (:func:`mapimpl.engine.transients.transient_times`) and its
statistics (:mod:`.analysis`) and returns a dataclass; nothing is written, drawn or printed here.  The
commands ``gear-rattle basins | uncertainty | transients`` and the report compose them: compute ->
write (:mod:`gear_rattle.validation.io.transients`) -> plot (:mod:`gear_rattle.validation.plots.transients`).
A fit that fails is ``None`` in the result, with its reason in ``notes``.  Run sizes per profile:
:mod:`.profiles`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...core.paper import DELTA, DELTAS, PAPER_BOX, PAPER_PARAMS
from ...core.params import Params
from ...mapimpl.engine.transients import TransientResult, grid, transient_times
from ...mapimpl.sticking import STICK_TIME
from ..paper import PAPER
from . import analysis as A
from .post_release import (RELEASE_SOURCES, certified_t_post, composed_mask, decimal_params, release_durations,
                           stick_counts)
from .profiles import get_profile

BASIN_NS = (90, 500, 1000, 2000)
#: Fig. 9 window: the whole phase circle, 0 < sdot0 < 0.5 (contains the paper's box).
BASIN_WINDOW = (0.0, 2.0 * math.pi, 0.0, 0.5)
#: The eps range of Fig. 10 (log-spaced; the number of values is the profile's ``n_eps``).
EPS_RANGE = (1e-9, 1e-3)
#: Most rows of the survival table written beside Fig. 11 (the curve is subsampled beyond).
SURVIVAL_ROWS = 4000


def _fit_or_note(notes: list, label: str, fit, *args, **kwargs):
    """``fit(*args, **kwargs)``, or None with ``"label: reason"`` appended to ``notes`` (a fit that
    cannot be made: too few points, no decay)."""
    try:
        return fit(*args, **kwargs)
    except ValueError as e:
        notes.append(f"{label}: {e}")
        return None


# ------------------------------------------------------------------------------------- Fig. 9

@dataclass
class BasinsResult:
    """Fig. 9: durations on an ``nx`` x ``ny`` mesh of ``window`` (arrays of shape ``(ny, nx)``),
    thresholded at each ``n`` of ``ns``: ``short_fraction[n]`` = fraction with duration < n."""

    params: Params
    window: tuple
    nx: int
    ny: int
    ns: tuple
    delta: float
    ic_mode: str
    tau0: np.ndarray
    sdot0: np.ndarray
    duration: np.ndarray
    censored: np.ndarray
    short_fraction: dict
    stick_counts: dict
    release: dict
    engine: TransientResult
    notes: list = field(default_factory=list)

    def arrays(self) -> dict:
        """The arrays of ``basins.npz``."""
        return dict(tau0=self.tau0, sdot0=self.sdot0, duration=self.duration, censored=self.censored,
                    nstick=self.engine.nstick.reshape(self.tau0.shape), ns=np.array(self.ns), delta=self.delta,
                    window=np.array(self.window))

    def summary(self) -> dict:
        """The numbers of ``basins.json``."""
        return {"figure": "9", "nx": self.nx, "ny": self.ny, "window": list(self.window), "ns": list(self.ns),
                "delta": self.delta, "short_fraction": self.short_fraction,
                "orbits_with_sticking": self.engine.n_stuck_orbits, "stick_counts": self.stick_counts,
                "release": self.release, "engine": self.engine.summary()}


def basins(profile="quick", nx=None, ny=None, window=BASIN_WINDOW, ns=BASIN_NS, delta=DELTA,
           params: Params = PAPER_PARAMS, ic_mode="pre-impact", s0=None, progress=None, lanes=None) -> BasinsResult:
    """Fig. 9: durations on an ``nx`` x ``ny`` mesh computed once (cap = max(ns)), thresholded at each
    n: black = duration < n ("short" transients).  ``ny`` defaults to the profile's when ``nx`` is the
    profile's, else to ``nx``."""
    size = get_profile(profile, "basins")
    nx = size["nx"] if nx is None else int(nx)
    ny = (size["ny"] if nx == size["nx"] else nx) if ny is None else int(ny)
    ns = tuple(sorted(int(n) for n in ns))
    if not ns or ns[0] < 1:
        raise ValueError(f"ns={ns!r} is out of range: allowed integers >= 1")
    T, S = grid(window, nx, ny)
    res = transient_times(T.ravel(), S.ravel(), params, ic_mode=ic_mode, s0=s0, delta=delta, deltas=(delta,),
                          cap=ns[-1], progress=progress, label="basins", lanes=lanes)
    dur, cens, rinfo = release_durations(res, delta, confirm=get_profile(profile, "confirm"))
    D = dur.reshape(T.shape)
    fractions = {int(n): float(np.mean(D < n)) for n in ns}
    return BasinsResult(params, tuple(window), nx, ny, ns, delta, ic_mode, T, S, D, cens.reshape(T.shape), fractions,
                        stick_counts(res, delta), rinfo, res)


# ------------------------------------------------------------------------------------ Fig. 10

@dataclass
class UncertaintyResult:
    """Fig. 10: durations ``dA`` of ``n_points`` random points of ``box`` and ``dB``, ``dC`` (shape
    ``(n_points, len(eps))``) at ``tau0 +- eps``; ``fits[n]``: the exponent fit at threshold ``n``
    (None if it failed; the reason in ``notes``)."""

    params: Params
    n_points: int
    eps: np.ndarray
    seed: int
    delta: float
    ns: tuple
    tauA: np.ndarray
    sdotA: np.ndarray
    dA: np.ndarray
    dB: np.ndarray
    dC: np.ndarray
    fits: dict
    release: dict
    engine: TransientResult
    notes: list = field(default_factory=list)

    def fraction(self, n: int) -> np.ndarray:
        """``f(eps)``: the fraction of eps-uncertain points at threshold ``n``."""
        return A.uncertain_fraction(self.dA, self.dB, self.dC, n)

    def arrays(self) -> dict:
        """The arrays of ``uncertainty.npz``."""
        return dict(eps=self.eps, tauA=self.tauA, sdotA=self.sdotA, dA=self.dA, dB=self.dB, dC=self.dC,
                    ns=np.array(self.ns), f=np.array([self.fraction(n) for n in self.ns]))

    def table(self) -> tuple[list, list]:
        """``(header, rows)`` of ``uncertainty.csv``: eps and f(eps) at each n."""
        fs = [self.fraction(n) for n in self.ns]
        return ["eps"] + [f"f_n{n}" for n in self.ns], [[e] + [f[i] for f in fs] for i, e in enumerate(self.eps)]

    def summary(self) -> dict:
        """The numbers of ``uncertainty.json``."""
        paper = {str(n): [PAPER[f"phi_{n}"].value, PAPER[f"phi_{n}"].error] for n in (500, 1000)}
        return {"figure": "10", "n_points": self.n_points, "eps": self.eps.tolist(), "seed": self.seed,
                "delta": self.delta,
                "fits": {str(n): (f.as_dict() if f is not None else None) for n, f in self.fits.items()},
                "paper": paper, "release": self.release, "engine": self.engine.summary()}


def default_eps(profile: str, n_eps: int | None = None, lo: float = EPS_RANGE[0], hi: float = EPS_RANGE[1]):
    """``n_eps`` (default: the profile's) log-spaced eps values from ``lo`` to ``hi``."""
    n_eps = get_profile(profile, "uncertainty")["n_eps"] if n_eps is None else int(n_eps)
    return np.logspace(np.log10(lo), np.log10(hi), n_eps)


def uncertainty(profile="quick", n_points=None, eps=None, ns=(500, 1000), seed=0, box=PAPER_BOX, delta=DELTA,
                params: Params = PAPER_PARAMS, n_boot=200, progress=None, lanes=None) -> UncertaintyResult:
    """Fig. 10: fraction f(eps) of eps-uncertain points among ``n_points`` random points of ``box``
    (deterministic ``seed``); B, C = (tau0 +- eps, sdot0).  Fits f ~ eps^phi for each n."""
    n_points = get_profile(profile, "uncertainty")["n_points"] if n_points is None else int(n_points)
    eps = default_eps(profile) if eps is None else np.asarray(eps, float)
    if n_points < 10:
        raise ValueError(f"n_points={n_points} is out of range: allowed n_points >= 10")
    if eps.ndim != 1 or eps.size < 3 or np.any(~np.isfinite(eps)) or np.any(eps <= 0) or np.any(eps > 0.1):
        raise ValueError("eps is out of range: allowed at least 3 values with 0 < eps <= 0.1")
    ns = tuple(sorted(int(n) for n in ns))
    rng = np.random.default_rng(seed)
    tA = rng.uniform(box[0], box[1], n_points)
    sA = rng.uniform(box[2], box[3], n_points)
    sA = np.where(sA == 0.0, box[3] * 1e-12, sA)
    E = eps.size
    tau = np.concatenate([tA, (tA[:, None] + eps).ravel(), (tA[:, None] - eps).ravel()])
    sd = np.concatenate([sA, np.repeat(sA, E), np.repeat(sA, E)])
    res = transient_times(tau, sd, params, delta=delta, deltas=(delta,), cap=ns[-1], progress=progress,
                          label="uncertainty", lanes=lanes)
    dur, _, rinfo = release_durations(res, delta, confirm=get_profile(profile, "confirm"))
    dA = dur[:n_points]
    dB = dur[n_points:n_points * (1 + E)].reshape(n_points, E)
    dC = dur[n_points * (1 + E):].reshape(n_points, E)
    notes: list = []
    fits = {n: _fit_or_note(notes, f"uncertainty: n={n}", A.fit_uncertainty, eps, A.uncertain_mask(dA, dB, dC, n),
                            n, n_boot=n_boot, seed=seed) for n in ns}
    return UncertaintyResult(params, n_points, eps, seed, delta, ns, tA, sA, dA, dB, dC, fits, rinfo, res, notes)


# ------------------------------------------------------------------------------------ Fig. 11

@dataclass
class SurvivalResult:
    """Fig. 11: the transient durations on an ``nx`` x ``ny`` mesh of ``box`` (``tau0``, ``sdot0`` of
    shape ``(ny, nx)``), the orbits that stick composed with the ``release_source`` post-release
    duration; ``hit[:, j]``: the duration within ``engine.deltas[j]`` (-1: censored at ``cap``);
    ``fits[delta]``: the Eq. (14) fit (None if it failed; reason in ``notes``);
    ``fit_float64_sample``: the fit at ``delta`` with the engine's float64 T_post instead; ``n``,
    ``N``: the survival curve at ``delta``; ``composed``: the orbits whose duration comes from the
    release; ``release``: per delta (``f"{d:g}"``) and wall the T_post used (:func:`release_durations`),
    at ``delta`` also ``certified_float64_rounding``."""

    params: Params
    box: tuple
    nx: int
    ny: int
    cap: int
    delta: float
    ic_mode: str
    s0: float | None
    stick_time: float
    release_source: str
    confirm: bool
    tau0: np.ndarray
    sdot0: np.ndarray
    hit: np.ndarray
    fits: dict
    fit_float64_sample: A.SurvivalFit | None
    release: dict
    n: np.ndarray
    N: np.ndarray
    composed: np.ndarray
    engine: TransientResult
    notes: list = field(default_factory=list)

    @property
    def stick_counts(self) -> dict:
        """Orbits that stick before coming within ``delta``, per wall of their first sticking episode."""
        return stick_counts(self.engine, self.delta)

    @property
    def main_fit(self) -> A.SurvivalFit | None:
        """The Eq. (14) fit at the main ``delta``."""
        return self.fits.get(float(self.delta))

    def durations(self, delta: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(durations, censored)`` at ``delta`` (default the main one), censored set to ``cap``."""
        h = self.hit[:, self.engine.column(delta)]
        cens = h < 0
        return np.where(cens, self.cap, h), cens

    def arrays(self) -> dict:
        """The arrays of ``transients.npz``."""
        shape, r, p = self.tau0.shape, self.engine, self.params
        return dict(tau0=self.tau0, sdot0=self.sdot0, hit=self.hit.reshape(shape + (-1,)),
                    hit_float64_sample=r.hit.reshape(shape + (-1,)), deltas=r.deltas, delta=self.delta, cap=self.cap,
                    status=r.status.reshape(shape), nstick=r.nstick.reshape(shape),
                    first_stick=r.first_stick.reshape(shape), stick_wall=r.stick_wall.reshape(shape),
                    composed=self.composed.reshape(shape), stick_time=self.stick_time, release=self.release_source,
                    params=np.array([p.alpha, p.beta, p.gamma, p.r]), n=self.n, N=self.N)

    def survival_table(self, rows: int = SURVIVAL_ROWS) -> tuple[list, list]:
        """``(header, rows)`` of ``survival.csv``: ``n, N(n)``, every ``len(n) // rows``-th point."""
        step = max(1, len(self.n) // rows)
        return ["n", "N"], [[self.n[i], self.N[i]] for i in range(0, len(self.n), step)]

    def summary(self) -> dict:
        """The numbers of ``transients.json``."""
        fs = self.fit_float64_sample
        return {"figure": "11", "nx": self.nx, "ny": self.ny, "cap": self.cap, "box": list(self.box),
                "delta": self.delta, "ic_mode": self.ic_mode, "s0": self.s0, "stick_time": self.stick_time,
                "release_source": self.release_source, "params_decimal": decimal_params(self.params),
                "fits": {f"{d:g}": (f.as_dict() if f is not None else None) for d, f in self.fits.items()},
                "fits_float64_sample": fs.as_dict() if fs is not None else None,
                "stick_counts": self.stick_counts, "n_composed": int(self.composed.sum()),
                "release": self.release,
                "paper": {"mean_n": int(PAPER["mean_n"].value), "kappa": [PAPER["kappa"].value, PAPER["kappa"].error]},
                "engine": self.engine.summary()}


def transients(profile="quick", nx=None, ny=None, cap=None, box=PAPER_BOX, delta=DELTA, deltas=DELTAS,
               params: Params = PAPER_PARAMS, ic_mode="pre-impact", s0=None, n_lo=None, n_hi=None, n_boot=200, seed=0,
               progress=None, lanes=None, stick_time: float = STICK_TIME, release: str = "certified") -> SurvivalResult:
    """Fig. 11: survival N(n) on an ``nx`` x ``ny`` mesh of ``box``; Eq. (14) fit for every recorded
    delta (the dependence on delta).

    The orbits that stick are composed with their wall's post-release duration, ``first_stick +
    T_post`` (:func:`release_durations`): ``release="certified"`` (default) uses ``T_post`` certified
    in ball arithmetic for the decimal parameters (confirmed at a second precision in the paper
    profile), ``"float64"`` the engine's own post-release orbit (a sample).  The result's ``release``
    gives, per wall stuck to, the certified values for the decimal parameters and for their float64
    roundings at the main ``delta``, and the float64 sample; ``fit_float64_sample`` is the Eq. (14)
    fit with the sample instead."""
    if release not in RELEASE_SOURCES:
        raise ValueError(f"release={release!r} is out of range: allowed one of {', '.join(RELEASE_SOURCES)}")
    size = get_profile(profile, "transients")
    nx = size["n"] if nx is None else int(nx)
    ny = nx if ny is None else int(ny)
    cap = size["cap"] if cap is None else int(cap)
    confirm = get_profile(profile, "confirm")
    T, S = grid(box, nx, ny)
    res = transient_times(T.ravel(), S.ravel(), params, ic_mode=ic_mode, s0=s0, delta=delta, deltas=deltas, cap=cap,
                          progress=progress, label="transients", lanes=lanes, stick_time=stick_time)
    fit_kw = dict(cap=cap, n_lo=n_lo, n_hi=n_hi, n_boot=n_boot, seed=seed)
    notes: list = []
    fits, release_info = {}, {}
    hit_used = np.empty(res.hit.shape, np.int64)
    for j, d in enumerate(res.deltas):
        dur, cens, info = release_durations(res, d, source=release, confirm=confirm, stick_time=stick_time)
        release_info[f"{d:g}"] = info
        hit_used[:, j] = np.where(cens, -1, dur)
        fits[float(d)] = _fit_or_note(notes, f"transients: delta={d:g}", A.fit_survival, dur, cens, **fit_kw)
    # the main delta: also the float64 roundings of the parameters (certified) and the float64 sample
    for w, entry in release_info[f"{float(delta):g}"].items():
        entry["certified_float64_rounding"] = certified_t_post(params, int(w), float(delta), rounding="float64",
                                                               stick_time=stick_time, confirm=confirm)
    fit_sample = _fit_or_note([], "", A.fit_survival, *res.duration(delta), **fit_kw)
    h = hit_used[:, res.column(delta)]
    n, N = A.survival(np.where(h < 0, cap, h), cap)
    return SurvivalResult(params, tuple(box), nx, ny, cap, delta, ic_mode, s0, stick_time, release, confirm, T, S,
                          hit_used, fits, fit_sample, release_info, n, N, composed_mask(res, delta), res, notes)


# ------------------------------------------------------------ sensitivity to the sticking decision

#: Other values of the chatter threshold (``mapimpl.sticking.STICK_TIME``) tried by :func:`stick_time_sensitivity`.
STICK_TIMES = (1e-7, 1e-5)


@dataclass
class StickTimeRow:
    """One chatter threshold of :func:`stick_time_sensitivity`: ``base`` (the Fig. 11 run's own),
    ``n_ic`` orbits, ``sticking_fraction``, ``stick_counts`` per wall, the upper wall's certified
    ``T_post`` (value and status) and the Eq. (14) ``fit`` (None if it failed)."""

    stick_time: float
    base: bool
    n_ic: int
    sticking_fraction: float
    stick_counts: dict
    T_post_upper: int | None
    T_post_upper_status: str
    fit: A.SurvivalFit | None

    def as_dict(self) -> dict:
        return {"stick_time": self.stick_time, "base": self.base, "n_ic": self.n_ic,
                "sticking_fraction": self.sticking_fraction, "stick_counts": self.stick_counts,
                "T_post_upper": self.T_post_upper, "T_post_upper_status": self.T_post_upper_status,
                "fit": self.fit.as_dict() if self.fit is not None else None}


@dataclass
class StickTimeSensitivity:
    """<n>, kappa and the sticking fraction per chatter threshold (``rows``), on the sub-mesh of a Fig. 11
    run taking every ``stride``-th row and column (``nx`` x ``ny``)."""

    stride: int
    nx: int
    ny: int
    cap: int
    delta: float
    rows: list
    notes: list = field(default_factory=list)

    def summary(self) -> dict:
        """The numbers of ``stick_time_sensitivity.json``."""
        return {"stride": self.stride, "nx": self.nx, "ny": self.ny, "cap": self.cap, "delta": self.delta,
                "rows": [r.as_dict() for r in self.rows]}


def _base_row_data(fig11: SurvivalResult, stride: int, k: int):
    """The Fig. 11 run's own durations on the sub-mesh (not recomputed)."""
    shape = fig11.tau0.shape
    h = fig11.hit.reshape(shape + (-1,))[::stride, ::stride, k].ravel().astype(np.int64)
    cens = h < 0
    comp = fig11.composed.reshape(shape)[::stride, ::stride].ravel()
    sw = fig11.engine.stick_wall.reshape(shape)[::stride, ::stride].ravel()
    return np.where(cens, fig11.cap, h), cens, comp, {str(w): int(np.sum(comp & (sw == w))) for w in (0, -1)}


def stick_time_sensitivity(fig11: SurvivalResult, profile="quick", stick_times=STICK_TIMES, stride=None,
                           n_boot=100, seed=0, progress=None, lanes=None) -> StickTimeSensitivity:
    """<n>, kappa and the sticking fraction of Eq. (14) for other values of the chatter threshold
    ``stick_time`` (the predicted accumulation time below which chatter is replaced by sticking,
    :mod:`mapimpl.sticking`), on a sub-mesh of the Fig. 11 run ``fig11`` (a :class:`SurvivalResult` with
    the certified T_post; every ``stride``-th row and column of its mesh; default: the profile's, 1 in
    the quick profile, 4 in the paper profile -- a 100 x 100 sub-mesh -- to bound the cost).  The run's
    own threshold is taken from its durations (not recomputed); every threshold uses its own certified
    ``T_post`` (the post-release orbit's sticking decisions depend on it too)."""
    stride = get_profile(profile, "stick_time")["stride"] if stride is None else int(stride)
    if stride < 1:
        raise ValueError(f"stride={stride!r} is out of range: allowed an integer >= 1")
    for st in stick_times:
        if not (math.isfinite(float(st)) and 0 < float(st) <= 1e-2):
            raise ValueError(f"stick_times: {st!r} is out of range: allowed 0 < stick_time <= 1e-2")
    if fig11.release_source != "certified":
        raise ValueError("the Fig. 11 run did not use the certified T_post")
    p, base, cap, delta = fig11.params, float(fig11.stick_time), fig11.cap, float(fig11.delta)
    k = [float(x) for x in fig11.engine.deltas].index(delta)
    T, S = fig11.tau0[::stride, ::stride], fig11.sdot0[::stride, ::stride]
    confirm = get_profile(profile, "confirm")
    rows, notes = [], []
    for st in sorted({base, *(float(x) for x in stick_times)}):
        if st == base:
            dur, cens, comp, counts = _base_row_data(fig11, stride, k)
        else:
            res = transient_times(T.ravel(), S.ravel(), p, delta=delta, deltas=(delta,), cap=cap, progress=progress,
                                  label=f"stick_time={st:g}", lanes=lanes, stick_time=st)
            dur, cens, _ = release_durations(res, delta, confirm=confirm, stick_time=st)
            comp, counts = composed_mask(res, delta), stick_counts(res, delta)
        tp = certified_t_post(p, 0, delta, stick_time=st, confirm=confirm)
        f = _fit_or_note(notes, f"stick_time={st:g}", A.fit_survival, dur, cens, cap=cap, n_boot=n_boot, seed=seed)
        rows.append(StickTimeRow(st, st == base, int(dur.size), float(comp.mean()), counts, tp["value"], tp["status"],
                                 f))
    return StickTimeSensitivity(stride, int(T.shape[1]), int(T.shape[0]), cap, delta, rows, notes)


# --------------------------------------------------------------- the float64 horizon (a sample, not a value)

@dataclass
class Float64Horizon:
    """The transient Lyapunov exponent ``lambda1`` (per impact; over ``impacts_used`` transient impacts of
    ``orbits`` orbits from an ``n_side`` x ``n_side`` grid, ``impacts`` each) and the impacts after which
    float64 roundoff has grown to ``delta`` (``horizon_delta``) and to order one (``horizon_1``)."""

    lambda1: float
    impacts_used: int
    orbits: int
    orbits_reaching_target: int
    n_side: int
    impacts: int
    delta: float
    horizon_delta: float
    horizon_1: float

    def as_dict(self) -> dict:
        return dict(self.__dict__)

    def fraction_beyond(self, durations) -> float:
        """The fraction of ``durations`` longer than the horizon at ``delta``: samples, not values."""
        return float(np.mean(np.asarray(durations) > self.horizon_delta))


def float64_horizon(params: Params = PAPER_PARAMS, profile="quick", delta: float = DELTA, n_side: int | None = None,
                    impacts: int | None = None) -> Float64Horizon:
    """The number of impacts after which a float64 transient orbit has lost the true one: the
    transient Lyapunov exponent ``lambda1`` (:func:`validation.transient.float64_release.transient_lyapunov`, a
    small grid of the Fig. 11 box: 6 x 6 orbits x 2000 impacts quick, 8 x 8 x 3000 paper) and
    ``ln(delta / u) / lambda1`` (roundoff ``u = 2^-53`` grown to the capture distance) and
    ``ln(1 / u) / lambda1`` (no digit left).  ``n_side`` and ``impacts`` override the profile's grid."""
    from . import float64_release as REL

    size = get_profile(profile, "horizon")
    n_side = size["n_side"] if n_side is None else int(n_side)
    impacts = size["impacts"] if impacts is None else int(impacts)
    ly = REL.transient_lyapunov(params, n_side=n_side, impacts=impacts)
    lam = float(ly["lambda1"])
    return Float64Horizon(lam, int(ly["impacts_used"]), int(ly["orbits"]), int(ly["orbits_reaching_target"]), n_side,
                          impacts, delta, REL.float64_horizon(lam, delta), REL.float64_horizon(lam, 1.0))
