"""Transient durations of many initial conditions (Section 4 of the paper, Figs. 9-11) on the engine.

**Setting.**  alpha = 1.245 (just past the crisis alpha_1 ~ 1.2437 of Fig. 8), r = 0.9,
beta = gamma = 0.1: the chaotic attractor has become a chaotic saddle and orbits end on the stable
4-impact period-1 orbit, found here by Newton's method (:func:`mapimpl.periodic.find_periodic`)
from the end of a long orbit, never hard-coded.

**Transient duration.**  ``n(IC)`` = the number of map iterations (impacts) until the pre-impact
state first lies within ``delta`` of a point of that periodic orbit (the
:class:`~gear_rattle.mapimpl.engine.observers.Capture` observer: sup norm of
``(tau mod 2 pi, sdot)`` with the phase difference wrapped and the wall required to match).  The
engine records the first-hit iteration for several deltas at once (``deltas``) and stops an orbit
when it is within the smallest one, or after ``cap`` iterations (censored).

**Initial conditions.**  ``ic_mode="pre-impact"`` (default, the paper's map variables): ``(tau0,
sdot0)`` is the state just before an impact, ``sdot0 > 0`` at ``s = 0``.  ``ic_mode="free"``: a
free-flight state ``s(tau0) = s0``, ``sdot(tau0) = sdot0`` (e.g. ``s0 = -1``: just after leaving
the lower wall); its first impact is found with :func:`mapimpl.impact_map.free_flight_start` and
becomes iteration 0.

**Sticking.**  Initial conditions that chatter and stick go through the sticking policy of
:mod:`mapimpl.sticking`; the tooth leaves the wall at the canonical release phase
(:func:`mapimpl.sticking.release_phase`), so every orbit that sticks to a wall continues on ONE
post-release orbit.  With ``sticking="compose"`` (default) the engine stops each orbit at its first
sticking episode (impact ``first_stick``) and runs the post-release orbit once per wall (from the
first initial condition that stuck there, :class:`~.release.PostReleaseOrbit`): the results are raw facts
(``hit`` before the first sticking, ``first_stick``, ``stick_wall``, the post-release orbits), and a
duration is composed from them by the one rule :func:`.release.compose_durations`, ``first_stick +
T_post`` with ``T_post[delta]`` the post-release orbit's own duration counted from the release (its
first impact is 1).  This equals, bit for bit, following every orbit through (``sticking="follow"``,
tested), and saves re-computing the same orbit thousands of times.  The engine's ``T_post`` is a
float64 sample of a chaotic orbit; :meth:`TransientResult.duration` takes a
:class:`~.release.TPost` from another source instead (a certified value: :func:`.t_post.release_for`).
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from dataclasses import dataclass, field
from functools import lru_cache, partial
from typing import cast

import numpy as np

from ...core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from ..impact_map import free_flight_start
from ...core.checks import TAU0_MAX, TAU0_RANGE, InputTypeError, check_array, check_choice, check_int, check_real
from ...core.paper import DELTA, DELTAS, MAX_DELTA, PAPER_BOX, PAPER_PARAMS
from ...core.deprecation import UNSET, warn_renamed
from ...core.outcome import Outcome, check_lengths, check_status
from ...core.params import Params, check_params
from ...core.status import Status
from ..sticking import STICK_TIME
from .driver import Orbits, params_arrays, run_orbits
from .options import Execution, StepRules, options_from_keywords
from .observers import Capture
from .release import PostReleaseOrbit, TPost, ReleaseSource, WallTPost, compose_durations, composed_mask, float64_t_post

IC_MODES = ("pre-impact", "free")
#: How orbits that stick are followed (see the module docstring).
STICKING_MODES = ("compose", "follow")


@dataclass
class PeriodicTarget:
    """The attracting periodic orbit: its ``impacts`` pre-impact states and Floquet multipliers."""

    theta: np.ndarray
    sdot: np.ndarray
    wall: np.ndarray
    multipliers: np.ndarray
    residual: float


def periodic_target(
    params: Params = PAPER_PARAMS, impacts: int = 4, guess: tuple = (3.2, 0.3), settle: int = 4000
) -> PeriodicTarget:
    """Find the stable ``impacts``-impact period-1 orbit by Newton (Fig. 8's orbit for alpha > alpha_1).

    A long orbit from ``guess`` settles near it; :func:`mapimpl.periodic.find_periodic` refines it.
    Raises ``ValueError`` if Newton fails or the orbit is not stable.
    """
    from ...core.checks import MAX_IMPACTS, MAX_PERIOD, check_start

    check_params(params)
    impacts = check_int("impacts", impacts, 1, MAX_PERIOD)
    settle = check_int("settle", settle, 1, MAX_IMPACTS)
    g = check_array("guess", guess, max_size=2, allowed="a pre-impact state (tau0, sdot0)")
    if g.size != 2:
        raise ValueError(f"guess={guess!r} is out of range: allowed a pre-impact state (tau0, sdot0)")
    tau, sdot, _ = check_start(g[0], g[1])
    return _periodic_target(params, impacts, (tau, sdot), settle)


@lru_cache(maxsize=16)
def _periodic_target(params: Params, impacts: int, guess: tuple[float, float], settle: int) -> PeriodicTarget:
    """:func:`periodic_target` of checked arguments (cached: one Newton search per setting)."""
    from ..orbit import map_orbit
    from ..periodic import find_periodic

    # follow the orbit until it repeats every ``impacts`` impacts (the transient has ended)
    tau, sdot = guess
    for _ in range(25):
        seq = map_orbit(params, tau, sdot, settle)
        _, th, sd, _ = seq.impact_arrays()
        if seq.status != "active" or len(th) < 2 * impacts + 1:
            raise ValueError(
                f"no capture target at these parameters (alpha={params.alpha:g}, beta={params.beta:g}, "
                f"gamma={params.gamma:g}, r={params.r:g}): the orbit from {guess} ended ({seq.status}) "
                f"before settling on a stable {impacts}-impact period-1 orbit (the transients of "
                "Figs. 9-11 end on it)"
            )
        tau, sdot = float(th[-1]), float(sd[-1])
        dth = np.abs(np.angle(np.exp(1j * (th[-1 - impacts :] - th[-1 - 2 * impacts : -impacts]))))
        if np.max(dth) < 1e-6 and np.max(np.abs(sd[-1 - impacts :] - sd[-1 - 2 * impacts : -impacts])) < 1e-6:
            break
    po = find_periodic(params, tau, sdot, impacts)
    if not po.converged or not po.stable:
        raise ValueError(
            f"no capture target at these parameters (alpha={params.alpha:g}, beta={params.beta:g}, "
            f"gamma={params.gamma:g}, r={params.r:g}): no stable {impacts}-impact period-1 orbit (the "
            f"transients of Figs. 9-11 end on it) found from {guess} (Newton converged: {po.converged}, "
            f"|multipliers| {np.array2string(np.abs(po.multipliers), precision=3)})"
        )
    # the wall of each pre-impact state follows the sign of its velocity (sdot > 0 hits s = 0);
    # (po.walls lists the same walls, aligned with po.theta and po.sdot)
    wall = np.where(np.asarray(po.sdot) > 0, 0, -1).astype(np.int32)
    return PeriodicTarget(
        np.asarray(po.theta), np.asarray(po.sdot), wall, np.asarray(po.multipliers), float(po.residual)
    )


@dataclass
class TransientResult(Outcome):
    """Per-initial-condition results (flat arrays of length N, in input order): raw facts, from which
    :meth:`duration` composes the durations (:func:`.release.compose_durations`).

    ``hit[:, j]``: first iteration within ``deltas[j]`` before the orbit first stuck (-1: never, within
    the cap, or not before it stuck: see ``first_stick``);
    ``n``: iterations the engine performed for the orbit; ``status``: orbit status codes
    (:class:`~gear_rattle.core.status.Status`: ``STOPPED`` = captured, ``CAPPED`` = censored, ...; an
    orbit that stuck: its outcome with the engine's own post-release orbit);
    ``nstick``: sticking episodes computed; ``first_stick``: impact index at which the orbit first
    stuck (-1: never); ``stick_wall``: its wall (``sticking="compose"``; 1 = not recorded when followed).
    ``post_release``: per wall that was stuck to, the engine's post-release orbit
    (:class:`~.release.PostReleaseOrbit`).  :meth:`duration` gives the durations, censored orbits set to ``cap``.
    ``ok``, ``message`` (:class:`~gear_rattle.core.outcome.Outcome`): built on ``status``, one code per orbit.
    """

    tau0: np.ndarray
    sdot0: np.ndarray
    hit: np.ndarray
    n: np.ndarray
    status: np.ndarray
    nstick: np.ndarray
    first_stick: np.ndarray
    stick_wall: np.ndarray
    deltas: np.ndarray
    delta: float
    cap: int
    params: Params
    ic_mode: str
    s0: float | None
    target: PeriodicTarget
    elapsed: float
    post_release: tuple[PostReleaseOrbit, ...] = ()
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Refuse status codes that are no :class:`~gear_rattle.core.status.Status` and per-orbit arrays whose
        lengths disagree (``ValueError`` naming them)."""
        check_status(self.status, list(Status))
        per_orbit = ("tau0", "sdot0", "n", "status", "nstick", "first_stick", "stick_wall")
        n = check_lengths("the per-orbit arrays of a TransientResult", **{k: getattr(self, k) for k in per_orbit})
        if np.shape(self.hit) != (n, np.size(self.deltas)):
            raise ValueError(
                f"hit of a TransientResult: allowed shape ({n}, {np.size(self.deltas)}) (got {np.shape(self.hit)})"
            )

    def column(self, delta: float | None = None) -> int:
        d = self.delta if delta is None else float(delta)
        j = np.flatnonzero(np.isclose(self.deltas, d, rtol=1e-12, atol=0))
        if len(j) == 0:
            raise ValueError(f"delta={delta!r} is out of range: allowed one of the recorded deltas {list(self.deltas)}")
        return int(j[0])

    def float64_t_post(self, delta: float | None = None) -> TPost:
        """The :class:`~.release.TPost` of the engine's own post-release orbits at ``delta`` (a float64
        sample)."""
        j = self.column(delta)
        return float64_t_post(self.post_release, self.deltas, float(self.deltas[j]), j)

    def float64_release(self, delta: float | None = None) -> TPost:
        """Deprecated: :meth:`float64_t_post` (same meaning)."""
        warn_renamed("TransientResult.float64_release()", "TransientResult.float64_t_post()")
        return self.float64_t_post(delta)

    def duration(
        self, delta: float | None = None, t_post: dict | None = None, *, release: TPost | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(durations, censored)``: iterations to come within ``delta`` (``cap`` when never), the
        orbits that stuck before composed with ``release`` (:func:`.release.compose_durations`;
        default the engine's own post-release orbits, a float64 sample; a certified one:
        :func:`.t_post.release_for`).

        ``t_post``: ``{wall: T_post}`` (deprecated: give ``release``) replaces the post-release duration
        of that wall (``T_post < 0`` or None: never captured)."""
        if release is None:
            release = self.float64_t_post(delta)
        elif not isinstance(release, TPost):
            raise TypeError(
                f"release is a {type(release).__name__}: allowed a TPost "
                "(gear_rattle.mapimpl.engine.t_post.release_for)"
            )
        elif delta is not None and self.column(delta) != self.column(release.delta):
            raise ValueError(f"delta={delta!r} is out of range: allowed the release's delta={release.delta!r}")
        if t_post:
            warnings.warn(
                "TransientResult.duration(t_post=) is deprecated: give release= (a TPost, "
                "gear_rattle.mapimpl.engine.t_post.release_for)",
                DeprecationWarning,
                stacklevel=2,
            )
            release = _given_release(release, t_post)
        j = self.column(release.delta)
        return compose_durations(self.hit[:, j], self.first_stick, self.stick_wall, self.cap, release)

    def composed(self, delta: float | None = None) -> np.ndarray:
        """The orbits whose duration comes from the release: they stuck before coming within ``delta``."""
        return composed_mask(self.hit[:, self.column(delta)], self.first_stick)

    @property
    def release(self) -> list[dict]:
        """Deprecated: :attr:`post_release` (typed); the post-release orbits as dicts."""
        warnings.warn("TransientResult.release is deprecated: use post_release", DeprecationWarning, stacklevel=2)
        return [r.as_dict() for r in self.post_release]

    @property
    def impacts(self) -> int:
        """Total map iterations performed (the engine's work)."""
        return int(np.sum(self.n))

    @property
    def n_stuck_orbits(self) -> int:
        """Orbits that stick at least once."""
        return int(np.sum(self.first_stick >= 0))

    def summary(self) -> dict:
        d, c = self.duration()
        return {
            "n_ic": int(len(self.n)),
            "cap": self.cap,
            "delta": self.delta,
            "ic_mode": self.ic_mode,
            "s0": self.s0,
            "censored": int(c.sum()),
            "mean_duration_uncensored": float(d[~c].mean()) if (~c).any() else math.nan,
            "orbits_with_sticking": self.n_stuck_orbits,
            "sticking_episodes": int(self.nstick.sum()),
            "release": [r.as_dict() for r in self.post_release],
            "status_counts": {Status(int(s)).label: int(np.sum(self.status == s)) for s in np.unique(self.status)},
            "impacts": self.impacts,
            "elapsed_s": self.elapsed,
            "impacts_per_s": self.impacts / self.elapsed if self.elapsed > 0 else math.nan,
        }


def _given_release(base: TPost, t_post: dict) -> TPost:
    """``base`` with the walls of ``t_post = {wall: T_post}`` (the deprecated argument of
    :meth:`TransientResult.duration`; ``T_post < 0`` or None: never captured) replaced."""
    walls = dict(base.walls)
    for wall, tp in t_post.items():
        if wall not in (0, -1) or isinstance(wall, bool):
            raise ValueError(f"t_post wall={wall!r} is out of range: allowed 0 or -1")
        old = walls.get(int(wall))
        walls[int(wall)] = WallTPost(
            int(wall),
            None if tp is None or tp < 0 else int(tp),
            ReleaseSource.CERTIFIED,
            old.float64_sample if old is not None else -1,
        )
    return TPost(base.source, base.delta, walls)


def _check_ic_arrays(tau0, sdot0, ic_mode: str) -> tuple[np.ndarray, np.ndarray]:
    """The initial conditions as flat float64 arrays, checked (:mod:`core.checks`): ``|tau0| <= 1e6``,
    finite ``sdot0`` (``!= 0`` for pre-impact states), at most ``MAX_ORBITS`` (2e7) of them."""
    tau0 = check_array("tau0", tau0, -TAU0_MAX, TAU0_MAX, allowed=f"finite reals with {TAU0_RANGE}")
    pre = ic_mode == "pre-impact"
    sdot0 = check_array(
        "sdot0",
        sdot0,
        nonzero=pre,
        allowed="finite reals" + (" != 0 (a pre-impact state: > 0 hits s = 0, < 0 hits s = -1)" if pre else ""),
    )
    if tau0.shape != sdot0.shape:
        raise ValueError(f"tau0 and sdot0 must have the same length (got {tau0.size} and {sdot0.size})")
    return tau0, sdot0


_free_start_v = jax.jit(jax.vmap(free_flight_start, in_axes=(0, None, 0, None)))


def initial_states(params: Params, tau0, sdot0, ic_mode="pre-impact", s0=None):
    """Pre-impact states ``(tau, sdot, wall, ok)`` of the initial conditions (numpy arrays; ``tau`` is
    the elapsed time of the state, reduced mod 2 pi by the engine; ``ok``: the state exists -- a free
    state's flight reaches a wall)."""
    check_params(params)
    s = TransientSettings(ic_mode=ic_mode, s0=s0)
    return _start_states(params, *_check_ic_arrays(tau0, sdot0, s.ic_mode), s)


def _start_states(params: Params, tau0: np.ndarray, sdot0: np.ndarray, s: TransientSettings):
    """:func:`initial_states` of checked arrays and settings."""
    if s.ic_mode == "pre-impact":
        return tau0.copy(), sdot0.copy(), np.where(sdot0 > 0, 0, -1).astype(np.int32), np.ones(tau0.size, bool)
    s0 = cast(float, s.s0)  # (given in free mode: TransientSettings)
    st = _free_start_v(jnp.asarray(tau0), jnp.asarray(float(s0)), jnp.asarray(sdot0), params.arrays())
    ok = np.asarray(st.status) == Status.ACTIVE
    return (np.asarray(st.theta), np.asarray(st.sdot), np.asarray(st.wall, dtype=np.int32), ok)


#: Most map iterations per orbit of :func:`transient_times` (its ``cap``).
MAX_CAP = 10**8


def _recorded_deltas(deltas, delta: float) -> tuple[float, ...]:
    """The capture distances, largest first (``delta`` with ``deltas``): ``0 < deltas <= MAX_DELTA``."""
    d = check_array(
        "deltas", deltas, 0.0, MAX_DELTA, max_size=1000, allowed=f"finite reals with 0 < deltas <= {MAX_DELTA:g}"
    )
    if np.any(d == 0.0):
        raise ValueError(f"deltas={list(d)!r} are out of range: allowed 0 < deltas <= {MAX_DELTA:g}")
    return tuple(sorted(set(d.tolist()) | {delta}, reverse=True))


@dataclass(frozen=True)
class TransientSettings:
    """What a transient duration is (the module docstring), checked when made (``ValueError`` naming the
    field): ``ic_mode`` -- ``"pre-impact"`` states or ``"free"`` states at ``s0`` (``-1 <= s0 <= 0``,
    required there); ``delta`` -- the capture distance that stops an orbit (``0 < delta <= 10``);
    ``deltas`` -- the capture distances recorded at once, held largest first with ``delta`` among them;
    ``cap`` -- most map iterations per orbit (``1 <= cap <= 1e8``, censored beyond); ``sticking`` --
    ``"compose"`` or ``"follow"`` (how orbits that stick are followed); ``stick_time`` -- the sticking
    policy's chatter threshold (:class:`~.options.StepRules`)."""

    ic_mode: str = "pre-impact"
    s0: float | None = None
    delta: float = DELTA
    deltas: tuple[float, ...] = DELTAS
    cap: int = 20000
    sticking: str = "compose"
    stick_time: float = STICK_TIME

    def __post_init__(self) -> None:
        put = partial(object.__setattr__, self)
        put("ic_mode", check_choice("ic_mode", self.ic_mode, IC_MODES))
        if self.ic_mode == "free":
            if self.s0 is None:
                raise ValueError("s0=None is out of range: allowed -1 <= s0 <= 0 for ic_mode='free'")
            check_real("s0", self.s0, -1.0, 0.0)
        elif self.s0 is not None:  # a pre-impact state has no position: an s0 given with it would be ignored
            raise ValueError(
                f"s0={self.s0!r} is out of range: allowed None for ic_mode='pre-impact' (the states are just "
                "before an impact, on the wall sdot0 points to); a start in free flight at s0 is ic_mode='free'"
            )
        put("delta", check_real("delta", self.delta, 0.0, MAX_DELTA, lo_open=True))
        put("deltas", _recorded_deltas(self.deltas, self.delta))
        put("cap", check_int("cap", self.cap, 1, MAX_CAP))
        put("sticking", check_choice("sticking", self.sticking, STICKING_MODES))
        put("stick_time", StepRules(stick_time=self.stick_time).stick_time)

    @property
    def rules(self) -> StepRules:
        """The engine's :class:`~.options.StepRules` of these settings."""
        return StepRules(stick_time=self.stick_time)

    def replace(self, **changes) -> TransientSettings:
        """A copy with some fields changed (checked again)."""
        return dataclasses.replace(self, **changes)


#: The settings of the paper's Figs. 9-11 (every field its default).
DEFAULT_SETTINGS = TransientSettings()


def transient_settings(settings: TransientSettings | None = None, **fields) -> TransientSettings:
    """``settings`` (default :class:`TransientSettings` ``()``) with ``fields`` replaced: the keywords of
    :func:`transient_times` and the experiments that stand for its fields."""
    if settings is not None and not isinstance(settings, TransientSettings):
        raise InputTypeError(f"settings is a {type(settings).__name__}: allowed a TransientSettings or None")
    base = settings or DEFAULT_SETTINGS
    return base.replace(**fields) if fields else base


def transient_times(
    params: Params | None,
    tau0,
    sdot0=UNSET,
    *,
    settings: TransientSettings | None = None,
    target: PeriodicTarget | None = None,
    execution: Execution | None = None,
    progress=None,
    label: str = "transients",
    **keywords,
) -> TransientResult:
    """Transient duration of every initial condition ``(tau0[i], sdot0[i])`` (see the module docstring).

    Deterministic: no randomness inside, and results do not depend on ``execution``.  What is computed
    is ``settings`` (a :class:`TransientSettings`, checked when made); its fields may be given as
    keywords instead, or besides it (``transient_times(p, tau0, sdot0, cap=2000)``: ``settings`` with
    those fields replaced).

    Parameters
    ----------
    params : Params or None
        The model's parameters; None for the paper's Figs. 9-11 (alpha = 1.245, beta = gamma = 0.1,
        r = 0.9, :data:`gear_rattle.core.paper.PAPER_PARAMS`).  The old order ``transient_times(tau0,
        sdot0[, params])`` still works, with a DeprecationWarning.
    tau0, sdot0 : array_like
        The initial conditions (1-D, same length, at most 2e7), ``|tau0| <= 1e6``.
    settings : TransientSettings, optional
        What a transient duration is: the fields below (default their defaults).
    ic_mode : {"pre-impact", "free"}, optional
        Pre-impact states (the paper's map variables), or free states at ``s0``.
    s0 : float, optional
        The position of free initial states (``ic_mode="free"``), ``-1 <= s0 <= 0``.
    delta : float, optional
        The capture distance that stops an orbit (the smallest of ``deltas`` and ``delta``), ``0 < delta <= 10``.
    deltas : sequence of float, optional
        Capture distances recorded at once (one column of ``hit`` each).
    cap : int, optional
        Most map iterations per orbit (censored beyond), ``1 <= cap <= 1e8``.
    sticking : {"compose", "follow"}, optional
        ``"compose"``: stop at the first sticking episode and run the one post-release orbit per wall
        (durations: :meth:`TransientResult.duration`); ``"follow"``: follow every orbit through (same
        durations, slower).
    stick_time : float, optional
        The sticking policy's chatter threshold (:class:`~.options.StepRules`), ``0 <= stick_time <= 1e-2``.
    target : PeriodicTarget, optional
        The capturing orbit (default: :func:`periodic_target` of ``params``).
    execution : Execution, optional
        Lanes, block, chunk and devices (:class:`~.options.Execution`); the old keywords ``lanes``,
        ``block``, ``chunk``, ``devices`` still work (deprecated), as does ``release`` for ``sticking``.
    progress, label : optional
        See :func:`gear_rattle.mapimpl.engine.driver.run`.

    Returns
    -------
    TransientResult
        First capture iteration per initial condition and capture distance (before sticking), with
        status, sticking and the post-release orbits; :meth:`TransientResult.duration` gives the durations
        and the censoring; ``ok`` and ``message`` say whether it worked.  A free initial condition whose
        flight never reaches a wall is not run: its status is ``NO_IMPACT`` (every one of them may be).

    Examples
    --------
    Eight initial conditions on the upper wall of Fig. 11's box, at most 2000 impacts each:

    >>> import numpy as np
    >>> import gear_rattle as gr
    >>> res = gr.transient_times(None, np.linspace(0.0, 6.0, 8), np.ones(8), cap=2000, progress=False)
    >>> res.target.wall.size, res.hit.shape == (8, res.deltas.size), res.ok
    (4, True, True)
    >>> dur, censored = res.duration()
    >>> bool(np.all(dur[~censored] <= 2000) and np.all(dur[censored] == 2000))
    True

    Following every orbit through its sticking episodes gives the same durations, bit for bit:

    >>> slow = gr.transient_times(
    ...     None, np.linspace(0.0, 6.0, 8), np.ones(8), cap=2000, sticking="follow", progress=False
    ... )
    >>> bool(np.array_equal(slow.duration()[0], dur))
    True
    """
    params, tau0, sdot0 = _params_first(params, tau0, sdot0)
    check_params(params)
    s, execution = _settings_and_execution(settings, execution, keywords)
    tau0, sdot0 = _check_ic_arrays(tau0, sdot0, s.ic_mode)  # all before any work
    if target is not None and not isinstance(target, PeriodicTarget):
        raise InputTypeError(f"target is a {type(target).__name__}: allowed None or a PeriodicTarget")
    if target is None:
        target = periodic_target(params)
    tau, sd, wall, ok = _start_states(params, tau0, sdot0, s)
    t0 = time.perf_counter()
    cap_obs = Capture(target.theta, target.sdot, target.wall, np.asarray(s.deltas))
    out = _empty_result(params, tau0, sdot0, s, target)
    out.status[~ok] = int(Status.NO_IMPACT)  # free-flight starts that never reach a wall are not run
    idx = np.flatnonzero(ok)
    if idx.size:  # (none: every free start flies off without an impact -- nothing to run)
        orbits = Orbits(tau[idx], sd[idx], wall[idx], params_arrays(params, idx.size))
        stop_at_stick = s.sticking == "compose"
        res = run_orbits(orbits, (cap_obs,), s.cap, stop_at_stick, s.rules, execution, progress=progress, label=label)
        out.hit[idx] = res.obs[0]["hit"]
        out.n[idx], out.status[idx], out.nstick[idx], out.first_stick[idx] = (
            res.n,
            res.status,
            res.nstick,
            res.first_stick,
        )
        # the wall the orbit stopped on: its first sticking wall in compose mode (unknown when followed: 1)
        out.stick_wall[idx] = res.wall if stop_at_stick else 1
        out.meta = dict(res.meta, sticking=s.sticking)
    stuck = out.status == int(Status.STUCK)
    post = []
    for w in (0, -1):
        sel = np.flatnonzero(stuck & (out.stick_wall == w))
        if sel.size:
            start = Orbits(tau[sel[:1]], sd[sel[:1]], wall[sel[:1]], params_arrays(params, 1))
            post.append(_post_release(start, int(sel[0]), int(out.first_stick[sel[0]]), w, cap_obs, s, execution))
    out.post_release = tuple(post)
    # an orbit stopped at its first sticking: its outcome with the engine's own post-release orbit
    # (within the smallest delta)
    released = stuck & np.isin(out.stick_wall, [p.wall for p in post])
    captured = ~out.duration(s.deltas[-1])[1]
    out.status[released] = np.where(captured[released], int(Status.STOPPED), int(Status.CAPPED))
    out.elapsed = time.perf_counter() - t0
    return out


def _settings_and_execution(settings, execution, keywords: dict) -> tuple[TransientSettings, Execution]:
    """The :class:`TransientSettings` and :class:`~.options.Execution` of a :func:`transient_times` call:
    its keywords that are settings fields replace those of ``settings``; ``lanes``, ``block``, ``chunk``,
    ``devices`` (deprecated) make the execution, ``release`` (deprecated) is ``sticking``."""
    fields = {k: keywords.pop(k) for k in list(keywords) if k in TransientSettings.__dataclass_fields__}
    if "release" in keywords:
        fields["sticking"] = _old_sticking_keyword(keywords.pop("release"), fields.get("sticking"))
    _, execution = options_from_keywords("transient_times", keywords, None, execution, rule_fields=(), stacklevel=4)
    return transient_settings(settings, **fields), execution


def _empty_result(params: Params, tau0, sdot0, s: TransientSettings, target: PeriodicTarget) -> TransientResult:
    """The result of :func:`transient_times` before the engine has run: every orbit ``NOT_RUN``."""
    n_ic = tau0.size
    return TransientResult(
        tau0=tau0,
        sdot0=sdot0,
        hit=np.full((n_ic, len(s.deltas)), -1, np.int32),
        n=np.zeros(n_ic, np.int32),
        status=np.full(n_ic, int(Status.NOT_RUN), np.int32),
        nstick=np.zeros(n_ic, np.int32),
        first_stick=np.full(n_ic, -1, np.int32),
        stick_wall=np.zeros(n_ic, np.int32),
        deltas=np.asarray(s.deltas, np.float64),
        delta=s.delta,
        cap=s.cap,
        params=params,
        ic_mode=s.ic_mode,
        s0=None if s.s0 is None else float(s.s0),
        target=target,
        elapsed=0.0,
        meta={"sticking": s.sticking},
    )


def _old_sticking_keyword(release, sticking) -> str:
    """``sticking`` given by its deprecated keyword ``release`` (its old spelling), with a warning."""
    check_choice("release", release, STICKING_MODES)
    if sticking is not None:
        raise InputTypeError("give sticking= or its old name release=, not both")
    warnings.warn(
        "transient_times(release=) is deprecated: the engine's handling of orbits that stick is "
        "sticking= ('compose' or 'follow'); release= names the source of T_post elsewhere",
        DeprecationWarning,
        stacklevel=4,
    )
    return release


def _post_release(
    start: Orbits, i: int, first: int, w: int, cap_obs: Capture, s: TransientSettings, execution: Execution
) -> PostReleaseOrbit:
    """The post-release orbit of wall ``w``, once: initial condition ``i`` (``start``, which first stuck at
    impact ``first``) followed through from its start, its capture counted from the release."""
    rep = run_orbits(start, (cap_obs,), first + s.cap, False, s.rules, execution, progress=False)
    h = rep.obs[0]["hit"][0].astype(np.int64)
    if int(rep.first_stick[0]) != first:  # pragma: no cover - would be an engine bug
        raise RuntimeError("post-release orbit: the representative orbit stuck at a different impact")
    return PostReleaseOrbit(w, i, first, np.where(h >= 0, h - first, -1), int(rep.n[0]) - first)


def _params_first(params, tau0, sdot0):
    """``(params, tau0, sdot0)`` of :func:`transient_times`: None is the paper's parameters; the old order
    ``(tau0, sdot0[, params])`` -- a first argument that is neither a :class:`Params` nor None -- is
    reordered, with a DeprecationWarning."""
    if params is not None and not isinstance(params, Params) and not isinstance(params, dict):
        warn_renamed("transient_times(tau0, sdot0, params)", "transient_times(params, tau0, sdot0)", stacklevel=4)
        params, tau0, sdot0 = (PAPER_PARAMS if sdot0 is UNSET else sdot0), params, tau0
    elif sdot0 is UNSET:
        raise InputTypeError(
            "transient_times() is missing sdot0 (the initial velocities): allowed transient_times(params, tau0, sdot0)"
        )
    return (PAPER_PARAMS if params is None else params), tau0, sdot0


#: Most mesh points per axis of :func:`grid`.
MAX_MESH = 20000


def check_box(name: str, box) -> tuple[float, float, float, float]:
    """``box = (tau_lo, tau_hi, sdot_lo, sdot_hi)`` as four floats with ``tau_lo < tau_hi`` and ``sdot_lo <
    sdot_hi`` (finite); ``ValueError`` naming ``name`` otherwise."""
    allowed = "four finite reals (tau_lo < tau_hi, sdot_lo < sdot_hi)"
    b = check_array(name, box, max_size=4, allowed=allowed)
    if b.size != 4 or not (b[0] < b[1] and b[2] < b[3]):
        raise ValueError(f"{name}={box!r} is out of range: allowed finite (tau_lo < tau_hi, sdot_lo < sdot_hi)")
    t_lo, t_hi, s_lo, s_hi = (float(x) for x in b)
    return t_lo, t_hi, s_lo, s_hi


def grid(box=PAPER_BOX, nx: int = 400, ny: int = 400):
    """Cell-centred ``nx`` x ``ny`` mesh over ``box = (tau_lo, tau_hi, sdot_lo, sdot_hi)``.

    Returns ``(TAU, SDOT)`` of shape ``(ny, nx)`` (cell centres: the open box's edges, e.g.
    ``sdot0 = 0``, are never sampled).
    """
    t_lo, t_hi, s_lo, s_hi = check_box("box", box)
    nx, ny = check_int("nx", nx, 1, MAX_MESH), check_int("ny", ny, 1, MAX_MESH)
    tx = t_lo + (np.arange(nx) + 0.5) * (t_hi - t_lo) / nx
    sy = s_lo + (np.arange(ny) + 0.5) * (s_hi - s_lo) / ny
    return np.meshgrid(tx, sy)


__all__ = [
    "IC_MODES",
    "STICKING_MODES",
    "PeriodicTarget",
    "periodic_target",
    "TransientResult",
    "initial_states",
    "MAX_CAP",
    "TransientSettings",
    "DEFAULT_SETTINGS",
    "transient_settings",
    "transient_times",
    "MAX_MESH",
    "check_box",
    "grid",
]
