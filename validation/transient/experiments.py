"""The experiments of Section 4 (Figs. 9-11), computed and returned as typed results.

Each function runs the transient engine (:func:`mapimpl.engine.transients.transient_times`) and its
statistics (:mod:`.analysis`) and returns a dataclass; nothing is written, drawn or printed here.  The
commands ``gear-rattle basins | uncertainty | transients`` and the report compose them: compute ->
write (:mod:`gear_rattle.validation.io.transients`) -> plot (:mod:`gear_rattle.validation.plots.transients`).
A fit that fails is ``None`` in the result, with its reason in ``notes``.  Run sizes per profile:
:mod:`validation.profiles`.
"""

from __future__ import annotations

import numpy as np

import math
from functools import partial

from ...core.checks import MAX_ORBITS, check_int
from ...core.paper import DELTA, PAPER_PARAMS
from ...core.params import Params
from ...mapimpl.engine.options import EXECUTION_FIELDS, Execution, options_from_keywords
from ...mapimpl.engine.release import ReleaseSource
from ...mapimpl.engine.t_post import certified_t_post, release_for
from ...mapimpl.engine.transients import TransientSettings, grid, transient_times
from . import analysis as A
from ..profiles import get_profile
from .results import (
    BasinsResult,
    Float64Horizon,
    StickTimeRow,
    StickTimeSensitivity,
    SurvivalResult,
    UncertaintyResult,
    stick_counts,
)
from .settings import BasinsSettings, SurvivalSettings, UncertaintySettings, settings_from


def _fit_or_note(notes: list, label: str, fit, *args, **kwargs):
    """``fit(*args, **kwargs)``, or None with ``"label: reason"`` appended to ``notes`` (a fit that
    cannot be made: too few points, no decay)."""
    try:
        return fit(*args, **kwargs)
    except ValueError as e:
        notes.append(f"{label}: {e}")
        return None


# ------------------------------------------------------------------------------------- Fig. 9


def basins(
    profile: str = "quick",
    params: Params = PAPER_PARAMS,
    *,
    settings: BasinsSettings | None = None,
    execution: Execution | None = None,
    progress=None,
    **fields,
) -> BasinsResult:
    """Fig. 9: durations on an ``nx`` x ``ny`` mesh computed once (cap = max(ns)), thresholded at each
    n: black = duration < n ("short" transients).  ``settings`` (a :class:`~.settings.BasinsSettings`),
    default :meth:`~.settings.BasinsSettings.of_profile` of ``profile``; its fields may be given as
    keywords instead or besides (``nx=121``: the profile's ratio ``ny/nx`` kept, 121 x 60 in the quick
    profile).  ``execution``: lanes, block, chunk, devices (:class:`~gear_rattle.mapimpl.engine.options.Execution`;
    the old keyword ``lanes`` still works, deprecated)."""
    s, execution = _settings_and_execution(BasinsSettings, settings, profile, execution, fields, "basins")
    T, S = grid(s.window, s.nx, s.ny)
    res = transient_times(
        params, T.ravel(), S.ravel(), settings=s.transient, execution=execution, progress=progress, label="basins"
    )
    rel = release_for(res, s.delta, ReleaseSource.CERTIFIED, confirm=s.confirm, progress=progress)
    dur, cens = res.duration(release=rel)
    D = dur.reshape(T.shape)
    fractions = {int(n): float(np.mean(D < n)) for n in s.ns}
    return BasinsResult(
        params,
        tuple(s.window),
        s.nx,
        s.ny,
        s.ns,
        s.delta,
        s.transient.ic_mode,
        T,
        S,
        D,
        cens.reshape(T.shape),
        fractions,
        stick_counts(res, s.delta),
        rel.info(),
        res,
    )


def _settings_and_execution(cls, settings, profile: str, execution, fields: dict, function: str):
    """The settings (a ``cls``: :func:`.settings.settings_from`) and the execution (:func:`_execution`) of
    an experiment's call."""
    execution = _execution(function, execution, fields)
    return settings_from(cls, settings, profile, fields), execution


def _execution(function: str, execution: Execution | None, fields: dict, stacklevel: int = 5) -> Execution:
    """The execution of an experiment's call: ``execution``, or made from its old keywords ``lanes``,
    ``block``, ``chunk``, ``devices`` (deprecated; taken out of ``fields``; ``lanes=None`` is the default)."""
    old = {k: fields.pop(k) for k in EXECUTION_FIELDS if k in fields}
    if "lanes" in old and old["lanes"] is None:
        old.pop("lanes")
    return options_from_keywords(function, old, None, execution, rule_fields=(), stacklevel=stacklevel)[1]


# ------------------------------------------------------------------------------------ Fig. 10


def uncertainty(
    profile: str = "quick",
    params: Params = PAPER_PARAMS,
    *,
    settings: UncertaintySettings | None = None,
    execution: Execution | None = None,
    progress=None,
    **fields,
) -> UncertaintyResult:
    """Fig. 10: fraction f(eps) of eps-uncertain points among ``n_points`` random points of ``box``
    (deterministic ``seed``); B, C = (tau0 +- eps, sdot0).  Fits f ~ eps^phi for each n.  ``settings``
    (a :class:`~.settings.UncertaintySettings`), default :meth:`~.settings.UncertaintySettings.of_profile`
    of ``profile``, its fields given as keywords instead or besides; ``execution`` as :func:`basins`."""
    s, execution = _settings_and_execution(UncertaintySettings, settings, profile, execution, fields, "uncertainty")
    n_points, eps, box = s.n_points, np.asarray(s.eps, float), s.box
    rng = np.random.default_rng(s.seed)
    tA = rng.uniform(box[0], box[1], n_points)
    sA = rng.uniform(box[2], box[3], n_points)
    sA = np.where(sA == 0.0, box[3] * 1e-12, sA)
    E = eps.size
    tau = np.concatenate([tA, (tA[:, None] + eps).ravel(), (tA[:, None] - eps).ravel()])
    sd = np.concatenate([sA, np.repeat(sA, E), np.repeat(sA, E)])
    res = transient_times(
        params, tau, sd, settings=s.transient, execution=execution, progress=progress, label="uncertainty"
    )
    rel = release_for(res, s.delta, ReleaseSource.CERTIFIED, confirm=s.confirm, progress=progress)
    dur = res.duration(release=rel)[0]
    dA = dur[:n_points]
    dB = dur[n_points : n_points * (1 + E)].reshape(n_points, E)
    dC = dur[n_points * (1 + E) :].reshape(n_points, E)
    notes: list = []
    fits = {
        n: _fit_or_note(
            notes,
            f"uncertainty: n={n}",
            A.fit_uncertainty,
            eps,
            A.uncertain_mask(dA, dB, dC, n),
            n,
            n_boot=s.n_boot,
            seed=s.seed,
        )
        for n in s.ns
    }
    return UncertaintyResult(
        params, n_points, eps, s.seed, s.delta, s.ns, tA, sA, dA, dB, dC, fits, rel.info(), res, notes
    )


# ------------------------------------------------------------------------------------ Fig. 11


def transients(
    profile: str = "quick",
    params: Params = PAPER_PARAMS,
    *,
    settings: SurvivalSettings | None = None,
    execution: Execution | None = None,
    progress=None,
    **fields,
) -> SurvivalResult:
    """Fig. 11: survival N(n) on an ``nx`` x ``ny`` mesh of ``box``; Eq. (14) fit for every recorded
    delta (the dependence on delta).  ``settings`` (a :class:`~.settings.SurvivalSettings`), default
    :meth:`~.settings.SurvivalSettings.of_profile` of ``profile``, its fields given as keywords instead or
    besides (``nx``, ``cap``, ``deltas``, ``ic_mode``, ``s0``, ``seed``, ``release``, ...); ``execution``
    as :func:`basins`.

    The orbits that stick are composed with their wall's post-release duration, ``first_stick +
    T_post`` (:meth:`~gear_rattle.mapimpl.engine.transients.TransientResult.duration`), from the source
    ``release`` (:class:`~gear_rattle.mapimpl.engine.release.ReleaseSource`): ``"certified"`` (default)
    ``T_post`` certified in ball arithmetic for the decimal parameters (confirmed at a second precision in
    the paper profile), ``"float64"`` the engine's own post-release orbit (a sample).  The result's
    ``t_post`` gives, per delta and wall stuck to, the value used and the float64 sample;
    ``fit_float64_sample`` is the Eq. (14) fit with the sample instead.  ``float64_rounding``: also
    certify ``T_post`` for the float64 roundings of the parameters at the main ``delta`` (reported
    beside, not used for the durations; the report's conventions refit with it)."""
    s, execution = _settings_and_execution(SurvivalSettings, settings, profile, execution, fields, "transients")
    T, S = grid(s.box, s.nx, s.ny)
    res = transient_times(
        params, T.ravel(), S.ravel(), settings=s.transient, execution=execution, progress=progress, label="transients"
    )
    notes: list = []
    certify = partial(release_for, res, confirm=s.confirm, stick_time=s.stick_time, progress=progress)
    t_post = {float(d): certify(d, s.release) for d in res.deltas}
    composed = {d: res.duration(release=r) for d, r in t_post.items()}
    fits = {
        d: _fit_or_note(notes, f"transients: delta={d:g}", A.fit_survival, dur, cens, **s.fit_keywords())
        for d, (dur, cens) in composed.items()
    }
    hit = np.stack([np.where(cens, -1, dur) for dur, cens in composed.values()], axis=1)
    rounding = (
        certify(s.delta, ReleaseSource.CERTIFIED_FLOAT64_ROUNDING, deltas=(s.delta,)) if s.float64_rounding else None
    )
    fit_sample = _fit_or_note([], "", A.fit_survival, *res.duration(s.delta), **s.fit_keywords())
    n, N = A.survival(composed[float(res.deltas[res.column(s.delta)])][0], s.cap)
    return SurvivalResult(
        params,
        tuple(s.box),
        s.nx,
        s.ny,
        s.cap,
        s.delta,
        s.ic_mode,
        s.s0,
        s.stick_time,
        s.release,
        s.confirm,
        T,
        S,
        hit,
        fits,
        fit_sample,
        t_post,
        rounding,
        n,
        N,
        res,
        notes,
    )


# ------------------------------------------------------------ sensitivity to the sticking decision

#: Other values of the chatter threshold (``mapimpl.sticking.STICK_TIME``) tried by :func:`stick_time_sensitivity`.
STICK_TIMES = (1e-7, 1e-5)


def _base_row_data(fig11: SurvivalResult, stride: int, k: int):
    """The Fig. 11 run's own durations on the sub-mesh (not recomputed)."""
    shape = fig11.tau0.shape
    h = fig11.hit.reshape(shape + (-1,))[::stride, ::stride, k].ravel().astype(np.int64)
    cens = h < 0
    comp = fig11.composed.reshape(shape)[::stride, ::stride].ravel()
    sw = fig11.engine.stick_wall.reshape(shape)[::stride, ::stride].ravel()
    return np.where(cens, fig11.cap, h), cens, comp, {str(w): int(np.sum(comp & (sw == w))) for w in (0, -1)}


def stick_time_sensitivity(
    fig11: SurvivalResult,
    profile="quick",
    stick_times=STICK_TIMES,
    stride=None,
    n_boot=100,
    seed=0,
    progress=None,
    execution: Execution | None = None,
    **old,
) -> StickTimeSensitivity:
    """<n>, kappa and the sticking fraction of Eq. (14) for other values of the chatter threshold
    ``stick_time`` (the predicted accumulation time below which chatter is replaced by sticking,
    :mod:`mapimpl.sticking`), on a sub-mesh of the Fig. 11 run ``fig11`` (a :class:`SurvivalResult` with
    the certified T_post; every ``stride``-th row and column of its mesh; default: the profile's, 1 in
    the quick profile, 4 in the paper profile -- a 100 x 100 sub-mesh -- to bound the cost).  The run's
    own threshold is taken from its durations (not recomputed); every threshold uses its own certified
    ``T_post`` (the post-release orbit's sticking decisions depend on it too).  ``execution`` as
    :func:`basins` (the old keyword ``lanes`` still works, deprecated)."""
    execution = _execution("stick_time_sensitivity", execution, old, stacklevel=4)
    if old:
        raise TypeError(f"stick_time_sensitivity() got an unexpected keyword argument {next(iter(old))!r}")
    stride = (
        get_profile(profile, "stick_time")["stride"] if stride is None else check_int("stride", stride, 1, MAX_ORBITS)
    )
    for st in stick_times:
        if not (math.isfinite(float(st)) and 0 < float(st) <= 1e-2):
            raise ValueError(f"stick_times: {st!r} is out of range: allowed 0 < stick_time <= 1e-2")
    if fig11.release is not ReleaseSource.CERTIFIED:
        raise ValueError("the Fig. 11 run did not use the certified T_post")
    p, base, cap, delta = fig11.params, float(fig11.stick_time), fig11.cap, float(fig11.delta)
    k = [float(x) for x in fig11.engine.deltas].index(delta)
    T, S = fig11.tau0[::stride, ::stride], fig11.sdot0[::stride, ::stride]
    confirm = get_profile(profile, "confirm")
    rows: list[StickTimeRow] = []
    notes: list[str] = []
    for st in sorted({base, *(float(x) for x in stick_times)}):
        if st == base:
            dur, cens, comp, counts = _base_row_data(fig11, stride, k)
        else:
            at_st = TransientSettings(delta=delta, deltas=(delta,), cap=cap, stick_time=st)
            res = transient_times(
                p,
                T.ravel(),
                S.ravel(),
                settings=at_st,
                execution=execution,
                progress=progress,
                label=f"stick_time={st:g}",
            )
            rel = release_for(res, delta, ReleaseSource.CERTIFIED, confirm=confirm, stick_time=st, progress=progress)
            dur, cens = res.duration(release=rel)
            comp, counts = res.composed(delta), stick_counts(res, delta)
        tp = certified_t_post(p, 0, (delta,), stick_time=st, confirm=confirm)[delta]
        f = _fit_or_note(notes, f"stick_time={st:g}", A.fit_survival, dur, cens, cap=cap, n_boot=n_boot, seed=seed)
        rows.append(StickTimeRow(st, st == base, int(dur.size), float(comp.mean()), counts, tp.value, tp.status, f))
    return StickTimeSensitivity(stride, int(T.shape[1]), int(T.shape[0]), cap, delta, rows, notes)


# --------------------------------------------------------------- the float64 horizon (a sample, not a value)


def float64_horizon(
    params: Params = PAPER_PARAMS,
    profile="quick",
    delta: float = DELTA,
    n_side: int | None = None,
    impacts: int | None = None,
) -> Float64Horizon:
    """The number of impacts after which a float64 transient orbit has lost the true one: the
    transient Lyapunov exponent ``lambda1`` (:func:`mapimpl.float64_release.transient_lyapunov`, a
    small grid of the Fig. 11 box: 6 x 6 orbits x 2000 impacts quick, 8 x 8 x 3000 paper) and
    ``ln(delta / u) / lambda1`` (roundoff ``u = 2^-53`` grown to the capture distance) and
    ``ln(1 / u) / lambda1`` (no digit left).  ``n_side`` and ``impacts`` override the profile's grid."""
    from ...mapimpl import float64_release as REL

    size = get_profile(profile, "horizon")
    n_side = size["n_side"] if n_side is None else int(n_side)
    impacts = size["impacts"] if impacts is None else int(impacts)
    ly = REL.transient_lyapunov(params, n_side=n_side, impacts=impacts)
    lam = float(ly["lambda1"])
    return Float64Horizon(
        lam,
        int(ly["impacts_used"]),
        int(ly["orbits"]),
        int(ly["orbits_reaching_target"]),
        n_side,
        impacts,
        delta,
        REL.float64_horizon(lam, delta),
        REL.float64_horizon(lam, 1.0),
    )


__all__ = [
    "basins",
    "uncertainty",
    "transients",
    "STICK_TIMES",
    "stick_time_sensitivity",
    "float64_horizon",
]
