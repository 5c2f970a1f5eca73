"""The typed results of the Figs. 9-11 experiments (:mod:`.experiments`): what each computed, with
``arrays()`` / ``table()`` / ``summary()`` giving the content of its NPZ / CSV / JSON file (written by
:mod:`gear_rattle.validation.io.transients`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...core.outcome import Outcome
from ...core.params import Params
from ...core.paper import PAPER_PARAMS
from ...mapimpl.engine.release import WALLS, TPost, ReleaseSource, certified_dict
from ...mapimpl.engine.t_post import decimal_params
from ...mapimpl.engine.transients import TransientResult
from ..paper import PAPER
from . import analysis as A

#: Most rows of the survival table written beside Fig. 11 (the curve is subsampled beyond).
SURVIVAL_ROWS = 4000


def stick_counts(res: TransientResult, delta: float | None = None) -> dict:
    """Orbits that stick before coming within ``delta``, per wall of their first sticking episode
    (``"0"``, ``"-1"``: the engine's ``stick_wall``)."""
    m = res.composed(delta)
    return {str(w): int(np.sum(m & (res.stick_wall == w))) for w in WALLS}


class ComparedWithPaper:
    """What the Figs. 9-11 results share about the paper: ``paper_setting`` (:func:`paper_setting` of their
    ``params``) and ``paper_entry`` (the ``paper`` entry of their JSON, :func:`paper_comparison`)."""

    params: Params

    @property
    def paper_setting(self) -> bool:
        """Whether the parameters are the paper's Figs. 9-11 ones: only then is anything compared with the paper."""
        return paper_setting(self.params)

    def paper_entry(self, values):
        """``values`` (the paper's numbers) at the paper's parameters, else the line saying no comparison is made."""
        return paper_comparison(self.params, values)


@dataclass
class BasinsResult(ComparedWithPaper):
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
        return dict(
            tau0=self.tau0,
            sdot0=self.sdot0,
            duration=self.duration,
            censored=self.censored,
            nstick=self.engine.nstick.reshape(self.tau0.shape),
            ns=np.array(self.ns),
            delta=self.delta,
            window=np.array(self.window),
        )

    def summary(self) -> dict:
        """The numbers of ``basins.json``; ``paper`` (only away from the paper's parameters: the paper prints
        no number for Fig. 9): the line saying that no comparison is made."""
        return {
            "figure": "9",
            "nx": self.nx,
            "ny": self.ny,
            "window": list(self.window),
            "ns": list(self.ns),
            "delta": self.delta,
            "short_fraction": self.short_fraction,
            "orbits_with_sticking": self.engine.n_stuck_orbits,
            "stick_counts": self.stick_counts,
            "release": self.release,
            **({} if self.paper_setting else {"paper": self.paper_entry(None)}),
            "engine": self.engine.summary(),
        }


@dataclass
class UncertaintyResult(ComparedWithPaper):
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
        return dict(
            eps=self.eps,
            tauA=self.tauA,
            sdotA=self.sdotA,
            dA=self.dA,
            dB=self.dB,
            dC=self.dC,
            ns=np.array(self.ns),
            f=np.array([self.fraction(n) for n in self.ns]),
        )

    def table(self) -> tuple[list, list]:
        """``(header, rows)`` of ``uncertainty.csv``: eps and f(eps) at each n."""
        fs = [self.fraction(n) for n in self.ns]
        return ["eps"] + [f"f_n{n}" for n in self.ns], [[e] + [f[i] for f in fs] for i, e in enumerate(self.eps)]

    def summary(self) -> dict:
        """The numbers of ``uncertainty.json``; ``paper``: the paper's exponents where the parameters are the
        paper's, else a line saying that no comparison is made."""
        paper = self.paper_entry({str(n): [PAPER[f"phi_{n}"].value, PAPER[f"phi_{n}"].error] for n in (500, 1000)})
        return {
            "figure": "10",
            "n_points": self.n_points,
            "eps": self.eps.tolist(),
            "seed": self.seed,
            "delta": self.delta,
            "fits": {str(n): (f.as_dict() if f is not None else None) for n, f in self.fits.items()},
            "paper": paper,
            "release": self.release,
            "engine": self.engine.summary(),
        }


@dataclass
class SurvivalResult(ComparedWithPaper, Outcome):
    """Fig. 11: the transient durations on an ``nx`` x ``ny`` mesh of ``box`` (``tau0``, ``sdot0`` of
    shape ``(ny, nx)``); ``hit[:, j]``: the duration within ``engine.deltas[j]`` (-1: censored at
    ``cap``), the orbits that stick composed with the post-release duration from ``release`` (the
    source asked for) -- ``t_post[delta]``: the :class:`~gear_rattle.mapimpl.engine.release.TPost`
    each column was composed with (per wall the value used, its source, the float64 sample);
    ``float64_rounding``: the certified ``T_post`` for the float64 roundings of the parameters at
    ``delta`` (None unless asked for; reported, not used); ``fits[delta]``: the Eq. (14) fit (None if
    it failed; reason in ``notes``); ``fit_float64_sample``: the fit at ``delta`` with the engine's
    float64 T_post instead; ``n``, ``N``: the survival curve at ``delta``.  ``ok``, ``status``,
    ``message``: :class:`~gear_rattle.core.outcome.Outcome` (the engine's codes, and the fit at ``delta``)."""

    params: Params
    box: tuple
    nx: int
    ny: int
    cap: int
    delta: float
    ic_mode: str
    s0: float | None
    stick_time: float
    release: ReleaseSource
    confirm: bool
    tau0: np.ndarray
    sdot0: np.ndarray
    hit: np.ndarray
    fits: dict
    fit_float64_sample: A.SurvivalFit | None
    t_post: dict[float, TPost]
    float64_rounding: TPost | None
    n: np.ndarray
    N: np.ndarray
    engine: TransientResult
    notes: list = field(default_factory=list)

    @property
    def composed(self) -> np.ndarray:
        """The orbits whose duration at ``delta`` comes from the release (they stuck before coming within it)."""
        return self.engine.composed(self.delta)

    @property
    def main_t_post(self) -> TPost:
        """The :class:`~gear_rattle.mapimpl.engine.release.TPost` of the main ``delta``."""
        return self.t_post[float(self.engine.deltas[self.engine.column(self.delta)])]

    @property
    def stick_counts(self) -> dict:
        """Orbits that stick before coming within ``delta``, per wall of their first sticking episode."""
        return stick_counts(self.engine, self.delta)

    @property
    def status(self) -> np.ndarray:
        """The engine's :class:`~gear_rattle.core.status.Status` code of each orbit."""
        return self.engine.status

    @property
    def ok(self) -> bool:
        """Every orbit ran (``Outcome.ok`` of the engine's codes) and the Eq. (14) fit at ``delta`` exists."""
        return super().ok and self.main_fit is not None

    @property
    def message(self) -> str:
        """The orbits' codes (``Outcome.message``), and the fit's failure where it failed."""
        text = super().message
        return text if self.main_fit is not None else f"{text}; no Eq. (14) fit at delta={self.delta:g}"

    @property
    def main_fit(self) -> A.SurvivalFit | None:
        """The Eq. (14) fit at the main ``delta``."""
        return self.fits.get(float(self.delta))

    def durations(self, delta: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(durations, censored)`` at ``delta`` (default the main one), censored set to ``cap``."""
        h = self.hit[:, self.engine.column(delta)]
        cens = h < 0
        return np.where(cens, self.cap, h), cens

    def release_info(self) -> dict:
        """Per delta (``f"{d:g}"``) and wall the ``T_post`` used (the entries of ``transients.json``), at
        ``delta`` with ``certified_float64_rounding`` when it was certified."""
        out = {f"{d:g}": r.info() for d, r in self.t_post.items()}
        if self.float64_rounding is not None:
            main = out[f"{float(self.delta):g}"]
            for w, t in self.float64_rounding.walls.items():
                if t.certified is not None:
                    main[str(w)]["certified_float64_rounding"] = certified_dict(t.certified)
        return out

    def arrays(self) -> dict:
        """The arrays of ``transients.npz``."""
        shape, r, p = self.tau0.shape, self.engine, self.params
        sample = np.stack([np.where(c, -1, d) for d, c in (r.duration(x) for x in r.deltas)], axis=1)
        return dict(
            tau0=self.tau0,
            sdot0=self.sdot0,
            hit=self.hit.reshape(shape + (-1,)),
            hit_float64_sample=sample.reshape(shape + (-1,)),
            deltas=r.deltas,
            delta=self.delta,
            cap=self.cap,
            status=r.status.reshape(shape),
            nstick=r.nstick.reshape(shape),
            first_stick=r.first_stick.reshape(shape),
            stick_wall=r.stick_wall.reshape(shape),
            composed=self.composed.reshape(shape),
            stick_time=self.stick_time,
            release=self.release.value,
            params=np.array([p.alpha, p.beta, p.gamma, p.r]),
            n=self.n,
            N=self.N,
        )

    def survival_table(self, rows: int = SURVIVAL_ROWS) -> tuple[list, list]:
        """``(header, rows)`` of ``survival.csv``: ``n, N(n)``, every ``len(n) // rows``-th point."""
        step = max(1, len(self.n) // rows)
        return ["n", "N"], [[self.n[i], self.N[i]] for i in range(0, len(self.n), step)]

    def summary(self) -> dict:
        """The numbers of ``transients.json``; ``paper``: the paper's values where the parameters are
        the paper's, else a line saying that no comparison is made."""
        fs = self.fit_float64_sample
        return {
            "figure": "11",
            "nx": self.nx,
            "ny": self.ny,
            "cap": self.cap,
            "box": list(self.box),
            "delta": self.delta,
            "ic_mode": self.ic_mode,
            "s0": self.s0,
            "stick_time": self.stick_time,
            "release_source": self.release.value,
            "params_decimal": decimal_params(self.params),
            "fits": {f"{d:g}": (f.as_dict() if f is not None else None) for d, f in self.fits.items()},
            "fits_float64_sample": fs.as_dict() if fs is not None else None,
            "stick_counts": self.stick_counts,
            "n_composed": int(self.composed.sum()),
            "release": self.release_info(),
            "paper": self.paper_entry(
                {"mean_n": int(PAPER["mean_n"].value), "kappa": [PAPER["kappa"].value, PAPER["kappa"].error]}
            ),
            "engine": self.engine.summary(),
        }


def paper_setting(params: Params) -> bool:
    """Whether ``params`` are the paper's Figs. 9-11 parameters (alpha = 1.245, beta = gamma = 0.1, r = 0.9)."""
    return params == PAPER_PARAMS


def no_comparison(params: Params) -> str:
    """The line a result carries instead of the paper's values when its parameters are not the paper's."""
    mine = ", ".join(f"{k}={v}" for k, v in decimal_params(params).items())
    paper = ", ".join(f"{k}={v}" for k, v in decimal_params(PAPER_PARAMS).items())
    return f"no comparison with the paper: the parameters ({mine}) are not the paper's Figs. 9-11 setting ({paper})"


def paper_comparison(params: Params, values):
    """What a result shows of the paper: ``values`` (the paper's numbers) where ``params`` are the paper's
    (:func:`paper_setting`), else the line of :func:`no_comparison`."""
    return values if paper_setting(params) else no_comparison(params)


@dataclass
class StickTimeRow:
    """One chatter threshold of :func:`.experiments.stick_time_sensitivity`: ``base`` (the Fig. 11 run's own),
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
        return {
            "stick_time": self.stick_time,
            "base": self.base,
            "n_ic": self.n_ic,
            "sticking_fraction": self.sticking_fraction,
            "stick_counts": self.stick_counts,
            "T_post_upper": self.T_post_upper,
            "T_post_upper_status": self.T_post_upper_status,
            "fit": self.fit.as_dict() if self.fit is not None else None,
        }


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
        return {
            "stride": self.stride,
            "nx": self.nx,
            "ny": self.ny,
            "cap": self.cap,
            "delta": self.delta,
            "rows": [r.as_dict() for r in self.rows],
        }


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


__all__ = [
    "SURVIVAL_ROWS",
    "stick_counts",
    "ComparedWithPaper",
    "BasinsResult",
    "UncertaintyResult",
    "SurvivalResult",
    "paper_setting",
    "no_comparison",
    "paper_comparison",
    "StickTimeRow",
    "StickTimeSensitivity",
    "Float64Horizon",
]
