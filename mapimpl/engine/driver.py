"""Run the engine: many orbits of the impact map on every device, each watched by observers.

:func:`run` takes initial conditions (pre-impact states ``(theta, sdot, wall)``), parameters (one
set for all, or one per initial condition), observers (:mod:`gear_rattle.mapimpl.engine.observers`)
and a cap on the impacts per orbit, and returns per initial condition the impacts done, how the
orbit ended (:class:`gear_rattle.core.status.Status`), its sticking episodes, its final state and
the observers' outputs (:class:`EngineResult`).

How: the initial conditions are split over the devices of JAX's default backend (on the CPU one
device per core when :func:`gear_rattle.use_cpu_devices` was called; an accelerator otherwise), every
``ndev``-th one to a device, and one Python thread per device drives its queue through
:func:`kernel.run_blocks` (JAX releases the GIL while it compiles and runs).  Within a device,
``lanes`` orbits advance together and idle lanes are refilled from the queue after every block of
micro-steps; once the queue is empty and few lanes are busy, the busy ones move to a smaller block
(:func:`kernel.compact`).  Memory holds the lanes and the per-orbit results of one chunk of initial
conditions, never histories.  Queues are padded to a power of two so one compilation serves many
sizes.  Ctrl-C stops every device thread within one kernel call (a fraction of a second) and raises
``KeyboardInterrupt``.  Deterministic: no randomness inside, and each orbit's arithmetic does not
depend on its lane, block, chunk or device (see :mod:`kernel`).
"""

from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from ...core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from ...core.jax_config import xla_tuning_active
from ...core.checks import TAU0_MAX, TAU0_RANGE, InputTypeError, check_array, check_int
from ...core.params import ParamArrays, Params, validate_arrays
from ...core.progress import Bar, sink, wanted
from ...core.status import Status
from . import kernel as K
from .lanes import RESULT_DTYPES, Lane, Queue, Results, RunConsts
from .observers import Observer
from .options import Execution, StepRules, options_from_keywords

#: Tail of a run: once the queue is empty and at most 1/TAIL_SHRINK of the lanes are busy, the busy
#: ones move to a block TAIL_SHRINK times smaller (not below TAIL_MIN_LANES lanes).
TAIL_SHRINK, TAIL_MIN_LANES = 8, 32
#: Largest cap on impacts per orbit.
MAX_CAP = 2_000_000_000
#: Memory budget for the per-orbit results of one chunk (bytes).
CHUNK_BYTES = 256 << 20


@dataclass
class EngineResult:
    """Per-initial-condition results (flat arrays in input order) of :func:`run`.

    ``n``: impacts done (the index of the last pre-impact state reached); ``status``: how the orbit
    ended (:class:`~gear_rattle.core.status.Status` codes); ``nstick``: sticking episodes;
    ``first_stick``: index of the impact whose step first stuck (-1: never); ``theta, sdot, wall,
    cycles``: the last pre-impact state (tau = 2 pi cycles + theta, counted from the start);
    ``obs``: one dict of output arrays per observer.
    """

    n: np.ndarray
    status: np.ndarray
    nstick: np.ndarray
    first_stick: np.ndarray
    theta: np.ndarray
    sdot: np.ndarray
    wall: np.ndarray
    cycles: np.ndarray
    obs: tuple
    elapsed: float
    meta: dict = field(default_factory=dict)

    @property
    def impacts(self) -> int:
        """Map iterations performed (the engine's work)."""
        return int(np.sum(self.n))

    def status_counts(self) -> dict[str, int]:
        """``{status name: count}``."""
        return {Status(int(s)).label: int(np.sum(self.status == s)) for s in np.unique(self.status)}


def engine_devices(devices=None) -> list:
    """Devices the engine spreads its queue over: ``devices`` (a count or a list of JAX devices),
    default all devices of JAX's default backend (:meth:`.options.Execution.device_list`)."""
    return Execution(devices=devices).device_list()


def default_lanes(n_per_device: int) -> int:
    """As many lanes as there are orbits per device, up to :func:`cpu_lanes` on the CPU and 65536 on an
    accelerator.  A micro-step has a fixed cost besides its per-lane cost, so narrower blocks only
    lengthen runs of few orbits; the tail of a run, when the queue is dry and few orbits are left,
    moves to a smaller block (``_drive``).  A multiple of :data:`kernel.LANE_QUANTUM`."""
    top = cpu_lanes() if jax.default_backend() == "cpu" else 65536
    return K.padded_lanes(min(top, max(int(n_per_device), 1)))


def cpu_lanes() -> int:
    """The widest CPU block: where the working set of a device's micro-step stays in its core's cache.
    With the engine's XLA options (:func:`gear_rattle.core.jax_config.xla_tuning_active`) 256 lanes: Fig. 11's
    200 x 200 grid on 2 cores did 4.3e6, 5.4e6 and 4.6e6 impacts/s at 512, 256 and 128 lanes
    (2026-11-24); without them the kernel keeps more intermediate arrays and 512 lanes was best
    (Fig. 11 on 2 cores: 140 s at 512 lanes, 164 s at 2048, 2026-11-22)."""
    return 256 if xla_tuning_active() else 512


def params_arrays(params, n: int) -> ParamArrays:
    """The parameters in the engine's one form: a :class:`~gear_rattle.core.params.ParamArrays` of
    ``n`` float64 values per field (validated), from a :class:`~gear_rattle.core.params.Params` (valid
    when made: not checked again) or a ``ParamArrays`` (or a mapping or sequence with its fields) of one
    value or one per orbit."""
    if isinstance(params, Params):
        return ParamArrays(*(np.full(n, float(v), np.float64) for v in params.as_dict().values()))
    else:
        try:
            vals = ParamArrays(**params) if isinstance(params, dict) else ParamArrays(*params)
        except TypeError:
            raise InputTypeError(
                f"params is a {type(params).__name__}: allowed a Params or a ParamArrays of "
                "per-orbit arrays (alpha, beta, gamma, r)"
            ) from None
    checked = validate_arrays(*vals)
    for name, x in zip(ParamArrays._fields, checked):
        if np.ndim(x) and np.size(x) != n:
            raise ValueError(f"params.{name} has {np.size(x)} values: allowed one or one per initial condition ({n})")
    return ParamArrays(*(np.broadcast_to(np.asarray(x, np.float64), (n,)).copy() for x in checked))


def _pow2(m: int) -> int:
    return 1 << max(0, int(m - 1).bit_length())


def max_kernel_calls(m: int, cap: int, block: int, max_steps: int, every: int = K.ARRIVE_EVERY) -> int:
    """An upper bound on the :func:`kernel.run_blocks` calls (64 blocks each) that a queue of ``m``
    orbits can need, from the engine's own caps: an orbit makes at most ``cap + 1`` arrivals, each
    followed by one flight search of at most :func:`kernel.flight_micro_steps` micro-steps; while the
    queue is not done at least one lane is busy in every micro-step, and an orbit that ends waits at
    most one block for its lane to be refilled.  ``_drive`` stops with an error past it: an engine
    bug then ends the run instead of hanging it (no valid run comes near the bound)."""
    per_orbit = (int(cap) + 1) * (K.flight_micro_steps(int(max_steps), int(every)) + 1) + int(block)
    return 2 + -(-int(m) * per_orbit // (int(block) * 64))


def _impacts_done(lanes_s: Lane, res_s: Results) -> tuple[int, int]:
    """``(impacts of the finished orbits, impacts so far of the busy ones)`` of a device's queue."""
    busy = lanes_s.mode != K.MODE_IDLE
    return (int(jnp.sum(res_s.n, dtype=jnp.int64)), int(jnp.sum(jnp.where(busy, lanes_s.n, 0), dtype=jnp.int64)))


@dataclass(frozen=True)
class Orbits:
    """The engine's input, checked: ``n`` initial pre-impact states (``theta`` float64 of any finite phase,
    ``|theta| <= 1e6``; ``sdot`` float64, nonzero; ``wall`` int32, 0 or -1) and their parameters
    (``params``, a :class:`~gear_rattle.core.params.ParamArrays` of ``n`` float64 values per field).  Made
    by :meth:`checked` (the checks of :func:`run`) or by a caller that built the arrays itself from
    checked inputs (:func:`.transients.transient_times`)."""

    theta: np.ndarray
    sdot: np.ndarray
    wall: np.ndarray
    params: ParamArrays

    @classmethod
    def checked(cls, theta, sdot, wall, params) -> Orbits:
        """The states and parameters checked (:func:`core.checks.check_array`: 1-D, at most
        ``MAX_ORBITS``; :func:`params_arrays`): ``ValueError`` naming the argument otherwise."""
        th, sd, w = _check_states(theta, sdot, wall)
        return cls(th, sd, w, params_arrays(params, th.size))

    @property
    def size(self) -> int:
        """The number of orbits."""
        return int(self.theta.size)


@dataclass(frozen=True)
class DeviceJob:
    """One device's share of a chunk of initial conditions: ``sel``, the indices (into the run's orbits)
    of its orbits in queue order; ``queue`` (padded to a power of two with copies of its last entry, never
    loaded), the run constants ``consts`` and the initial carry ``start`` (idle lanes, empty results, the
    next initial condition 0), all placed on the device.  Read-only: the thread that drives it keeps the
    carry (``_drive``), and its progress goes to the reporter (:class:`JobProgress`)."""

    sel: np.ndarray
    queue: Queue
    consts: RunConsts
    start: tuple

    @property
    def m(self) -> int:
        """The orbits of this job."""
        return int(self.sel.size)


@dataclass
class JobProgress:
    """What one device's thread reported last (written under the reporter's lock): orbits finished,
    ``impacts`` (of the finished orbits, of the busy ones) and the lanes of its tail block (0: none)."""

    done: int = 0
    impacts: tuple[int, int] = (0, 0)
    tail: int = 0


def _drive(job: DeviceJob, j: int, cap: int, block: int, report, stop: threading.Event, observers, count: bool):
    """Run device job ``j`` to the end and return its final carry: blocks of micro-steps, progress
    (``report(j, finished orbits, impacts, tail lanes)``; impacts counted when ``count``), and the tail
    compaction.  None when ``stop`` is set."""
    # every orbit ends within cap map iterations of bounded finder work, so the loop is bounded
    # (max_kernel_calls); the guard only turns an engine bug into an error instead of a hang
    carry, tail = job.start, 0
    for _call in range(max_kernel_calls(job.m, cap, block, int(job.consts.max_steps))):
        if stop.is_set():
            return None
        carry, _ = K.run_blocks(carry, job.queue, job.consts, observers, block=block, max_blocks=64)
        lanes_s, res_s, next_ic = carry
        n_busy = int(jnp.sum(lanes_s.mode != K.MODE_IDLE))
        drained = int(next_ic) >= job.m
        report(j, int(next_ic) - n_busy, _impacts_done(lanes_s, res_s) if count else (0, 0), tail)
        if drained and n_busy == 0:
            return carry
        size = lanes_s.mode.shape[0]
        while drained and n_busy <= size // TAIL_SHRINK and size // TAIL_SHRINK >= TAIL_MIN_LANES:
            size //= TAIL_SHRINK
        if size < lanes_s.mode.shape[0]:
            tail = K.padded_lanes(size)
            carry = (K.compact(lanes_s, size=tail), res_s, next_ic)
    raise RuntimeError("engine made no progress (bug): queue not drained")


def _check_states(theta, sdot, wall) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The initial pre-impact states as flat arrays (float64, float64, int32), validated
    (:func:`core.checks.check_array`: 1-D, at most ``MAX_ORBITS``)."""
    th = check_array(
        "theta", theta, -TAU0_MAX, TAU0_MAX, allowed="finite reals with " + TAU0_RANGE.replace("tau0", "theta")
    )
    sd = check_array("sdot", sdot, nonzero=True, allowed="finite reals sdot != 0 (pre-impact states)")
    w = check_array("wall", wall, -1.0, 0.0, allowed="0 (s = 0) or -1 (s = -1) per orbit")
    if not (th.shape == sd.shape == w.shape):
        raise ValueError(f"theta, sdot and wall must have the same length (got {th.size}, {sd.size}, {w.size})")
    if not np.all((w == 0.0) | (w == -1.0)):
        raise ValueError("wall is out of range: allowed 0 (s = 0) or -1 (s = -1) per orbit")
    return th, sd, w.astype(np.int32)


def check_observers(observers) -> tuple[Observer, ...]:
    """``observers`` (an :class:`~.observers.Observer` or a sequence of them) as a tuple, checked."""
    obs = (observers,) if isinstance(observers, Observer) else tuple(observers)
    if not all(isinstance(o, Observer) for o in obs):
        raise InputTypeError("observers is out of range: allowed an Observer or a tuple of Observer instances")
    return obs


class _Reporter:
    """The engine's progress, one per :func:`run`: its own bar in impacts (when ``progress`` asks for one)
    or the caller's ``progress(orbits done, orbits)`` -- never both (:mod:`gear_rattle.core.progress`).

    The bar counts impacts, finished and in progress; its total is ``orbits x cap`` until an orbit
    finishes, then the impacts done plus, for every orbit not finished, the mean duration still to come:
    transient durations are about exponential (Eq. 14), so an orbit's expected remaining duration does
    not shrink with its age, and the mean is estimated as for censored exponential data, all the impacts
    done over the orbits finished (the mean of the finished ones alone is biased low: the short ones
    finish first); at most ``orbits x cap``.  It shows "compiling" until the first kernel call returns, and the lanes of the
    tail once the busy orbits move to a narrower block.  Each device's thread reports into its own
    :class:`JobProgress`, under one lock."""

    def __init__(self, progress, label: str, n: int, cap: int):
        self.bar = Bar(label, enabled=wanted(progress), phase="compiling")
        self.sink, self.n, self.cap = sink(progress), n, cap
        self.lock = threading.Lock()
        self.base = [0, 0]  # orbits and impacts of the chunks done
        self.jobs: list[JobProgress] = []

    @property
    def count_impacts(self) -> bool:
        """Whether the devices' threads count impacts (for the bar)."""
        return self.bar.drawn

    def chunk(self, jobs: list[DeviceJob]):
        """The ``report(j, finished orbits, (impacts finished, impacts busy), tail lanes)`` of one chunk's
        jobs."""
        self.jobs = [JobProgress() for _ in jobs]

        def report(j: int, n_done: int, impacts: tuple[int, int], tail: int) -> None:
            with self.lock:
                self.jobs[j] = JobProgress(n_done, impacts, tail)
                fin = self.base[0] + sum(x.done for x in self.jobs)
                if self.bar.drawn:
                    imp_fin = self.base[1] + sum(x.impacts[0] for x in self.jobs)
                    done = imp_fin + sum(x.impacts[1] for x in self.jobs)
                    most = self.n * self.cap
                    est = most if fin == 0 else min(most, done + (self.n - fin) * done / fin)
                    tails = [x.tail for x in self.jobs if x.tail]
                    if tails:
                        self.bar.postfix(f"tail: {sum(tails)} lanes")
                    self.bar.update(done, max(est, done))
                if self.sink is not None:
                    self.sink(fin, self.n)

        return report

    def chunk_done(self, jobs: list[DeviceJob]) -> None:
        self.base[0] += sum(jb.m for jb in jobs)
        self.base[1] += sum(x.impacts[0] + x.impacts[1] for x in self.jobs)


def _device_jobs(idx: np.ndarray, orbits: Orbits, thr: np.ndarray, placed: list, lanes: int, obs) -> list[DeviceJob]:
    """One job per device (``placed``: ``(device, the run constants on it)`` pairs) for the initial
    conditions ``idx`` of a chunk (every ``ndev``-th one; ``thr``: their phases reduced to ``[0, 2 pi)``):
    its queue padded to a power of two (with copies of its last entry, never loaded), idle lanes and
    empty results, placed on the device."""
    jobs = []
    for j, (dv, k) in enumerate(placed):
        sel = idx[j :: len(placed)]
        m = sel.size
        if m == 0:
            continue
        mp = _pow2(max(m, lanes))
        pad = lambda a: np.pad(a[sel], (0, mp - m), mode="edge")  # noqa: E731
        q = K.prepare_queue(pad(thr), pad(orbits.sdot), pad(orbits.wall), ParamArrays(*map(pad, orbits.params)), n_ic=m)
        carry = (K.idle_lanes(min(lanes, K.padded_lanes(m)), obs), K.empty_results(mp, obs), jnp.asarray(0, jnp.int32))
        jobs.append(DeviceJob(sel, jax.device_put(q, dv), k, jax.device_put(carry, dv)))
    return jobs


def _run_jobs(jobs: list[DeviceJob], cap: int, block: int, obs, reporter: _Reporter, stop: threading.Event) -> list:
    """Drive every device's job in its own thread to the end and return their final carries; on any
    exception (Ctrl-C) stop them all within one kernel call and re-raise."""
    report, count = reporter.chunk(jobs), reporter.count_impacts
    pool = ThreadPoolExecutor(max_workers=len(jobs))
    futures = [pool.submit(_drive, jb, j, cap, block, report, stop, obs, count) for j, jb in enumerate(jobs)]
    carries = []
    try:
        for f in futures:
            while True:
                try:
                    carries.append(f.result(timeout=0.2))
                    break
                except TimeoutError:
                    continue
    except BaseException:
        stop.set()
        pool.shutdown(wait=True, cancel_futures=True)
        reporter.bar.abort()
        raise
    pool.shutdown(wait=True)
    return carries


def _gather(jobs: list[DeviceJob], carries: list, out: dict, out_obs: tuple) -> None:
    """Copy the jobs' per-orbit results (from their final ``carries``) into ``out`` and ``out_obs`` (input
    order)."""
    for jb, carry in zip(jobs, carries):
        res, sel, m = carry[1], jb.sel, jb.m
        for name in out:
            out[name][sel] = np.asarray(getattr(res, name))[:m]
        for o_out, r_o in zip(out_obs, res.obs):
            for nm in o_out:
                o_out[nm][sel] = np.asarray(r_o[nm])[:m]


def run(
    theta,
    sdot,
    wall,
    params,
    observers: tuple[Observer, ...] | Observer = (),
    *,
    cap: int,
    stop_at_stick: bool = False,
    rules: StepRules | None = None,
    execution: Execution | None = None,
    progress=None,
    label: str = "engine",
    **renamed,
) -> EngineResult:
    """Iterate the impact map from every initial condition until its observers stop it, it reaches
    ``cap`` impacts, or it ends (stuck forever, no impact, step cap); see the module docstring.

    Parameters
    ----------
    theta, sdot, wall : array_like
        Pre-impact states, one per orbit (``theta`` any finite phase, ``sdot != 0``, ``wall`` 0 or -1).
    params : Params or ParamArrays
        One :class:`~gear_rattle.core.params.Params` for all orbits, or a
        :class:`~gear_rattle.core.params.ParamArrays` (the same field names; a mapping or a sequence
        of its fields is taken too) whose fields hold one value or one per orbit.
    observers : Observer or tuple of Observer, optional
        What is measured along each orbit and when it stops (:mod:`gear_rattle.mapimpl.engine.observers`).
    cap : int
        Most impacts per orbit, ``1 <= cap <= 2e9``.
    stop_at_stick : bool, optional
        Stop an orbit at its first sticking episode (status ``STUCK``: every orbit that sticks continues
        on one post-release orbit, which the caller runs once).
    rules : StepRules, optional
        The sticking policy's threshold and the impact finder's caps (:class:`.options.StepRules`;
        default its defaults).  Results depend on them.
    execution : Execution, optional
        Lanes, block, chunk and devices (:class:`.options.Execution`; default its defaults).  Results do
        not depend on them.
    progress : bool or callable, optional
        None (a bar in impacts when stderr is a terminal), True (the bar, or lines where stderr is not
        a terminal), False, or a callable ``(orbits done, orbits)`` instead of the bar
        (:mod:`gear_rattle.core.progress`).
    label : str, optional
        The progress bar's label.
    **renamed
        The old keywords ``lanes``, ``block``, ``chunk``, ``devices`` (fields of ``execution``) and
        ``stick_time``, ``t_max``, ``max_steps`` (fields of ``rules``): deprecated, same meaning.

    Returns
    -------
    EngineResult
        Per initial condition, in input order: impacts done, status, sticking episodes, the last state
        and the observers' outputs.  Results do not depend on ``execution``.

    Examples
    --------
    Eight orbits on Fig. 4's chaotic attractor (alpha = 3, r = 0.9), with their largest Lyapunov
    exponents (the :class:`~gear_rattle.mapimpl.engine.observers.Tangent` observer, Fig. 4b):

    >>> import numpy as np
    >>> from gear_rattle.core.params import Params
    >>> from gear_rattle.mapimpl.engine.driver import run
    >>> from gear_rattle.mapimpl.engine.observers import Tangent
    >>> p = Params(3.0, 0.1, 0.1, 0.9)
    >>> theta, sdot, wall = np.linspace(0.5, 6.0, 8), np.ones(8), np.zeros(8, dtype=int)
    >>> res = run(theta, sdot, wall, p, Tangent(n_start=100), cap=3000, progress=False)
    >>> res.status_counts(), res.impacts
    ({'capped': 8}, 24000)
    >>> from gear_rattle.mapimpl.engine.exponents import exponents
    >>> lam1 = exponents(res).lam[:, 0]
    >>> bool(np.all((0.3 < lam1) & (lam1 < 0.4)))
    True

    The engine's orbit is the closed-form map's (:func:`mapimpl.orbit.map_orbit`) to rounding:

    >>> from gear_rattle.mapimpl.orbit import map_orbit
    >>> short = run(theta, sdot, wall, p, cap=50, progress=False)
    >>> seq = map_orbit(p, theta[3], sdot[3], 50)
    >>> bool(abs(short.theta[3] - seq.theta[-1]) < 1e-9 and abs(short.sdot[3] - seq.sdot[-1]) < 1e-9)
    True
    """
    rules, execution = options_from_keywords("run", renamed, rules, execution)
    obs = check_observers(observers)
    orbits = Orbits.checked(theta, sdot, wall, params)
    cap = check_int("cap", cap, 1, MAX_CAP)
    return run_orbits(orbits, obs, cap, stop_at_stick, rules, execution, progress=progress, label=label)


def run_orbits(
    orbits: Orbits,
    observers: tuple[Observer, ...],
    cap: int,
    stop_at_stick: bool,
    rules: StepRules,
    execution: Execution,
    *,
    progress=None,
    label: str = "engine",
) -> EngineResult:
    """:func:`run` of checked inputs -- :class:`Orbits`, a tuple of observers, ``1 <= cap <=``
    :data:`MAX_CAP`, the option objects -- which it does not check again (the callers inside the library
    that have checked their own inputs call it: :func:`.transients.transient_times`)."""
    from ...core.phase import reduce_phase

    th = orbits.theta
    thr = np.asarray(reduce_phase(jnp.asarray(th), jnp.zeros(th.size, jnp.int32))[0])
    cyc_start = np.floor_divide(th - thr + np.pi, 2 * np.pi).astype(np.int64)  # turns removed by the reduction
    devs = execution.device_list()
    devs = devs[: max(1, min(len(devs), th.size))]
    per_ic = 48 + sum(int(np.prod(o.fields()[nm][1], dtype=np.int64)) * 8 for o in observers for nm in o.outputs())
    chunk = execution.chunk or int(max(4096, min(1 << 18, CHUNK_BYTES // per_ic)))
    lanes = K.padded_lanes(execution.lanes or default_lanes(min(th.size, chunk) // len(devs)))
    pa = orbits.params
    uniform = all(np.all(a == a[0]) for a in pa)
    k = K.make_consts(
        cap, observers, stop_at_stick, rules, params=ParamArrays(*(a[0] for a in pa)) if uniform else None
    )
    placed = [(dv, jax.device_put(k, dv)) for dv in devs]
    n = th.size
    out = {name: np.zeros(n, np.dtype(dt)) for name, dt in RESULT_DTYPES._asdict().items() if name != "obs"}
    out["cycles"] = out["cycles"].astype(np.int64)
    out_obs = tuple(
        {nm: np.zeros((n,) + tuple(o.fields()[nm][1]), o.fields()[nm][0]) for nm in o.outputs()} for o in observers
    )
    reporter = _Reporter(progress, label, n, cap)
    stop = threading.Event()
    t0 = time.perf_counter()
    for c0 in range(0, n, chunk):
        jobs = _device_jobs(np.arange(c0, min(n, c0 + chunk)), orbits, thr, placed, lanes, observers)
        _gather(jobs, _run_jobs(jobs, cap, execution.block, observers, reporter, stop), out, out_obs)
        reporter.chunk_done(jobs)
    elapsed = time.perf_counter() - t0
    total = int(np.sum(out["n"], dtype=np.int64))
    reporter.bar.update(total, total)
    reporter.bar.close()
    out["cycles"] = out["cycles"] + cyc_start
    meta = {
        "lanes": int(lanes),
        "block": int(execution.block),
        "chunk": int(chunk),
        "backend": jax.default_backend(),
        "devices": len(devs),
        "cap": cap,
        "uniform_params": bool(uniform),
        "xla_tuning": xla_tuning_active(),
        "stop_at_stick": bool(stop_at_stick),
        "observers": [type(o).__name__ for o in observers],
    }
    return EngineResult(**out, obs=out_obs, elapsed=elapsed, meta=meta)


__all__ = [
    "TAIL_SHRINK",
    "TAIL_MIN_LANES",
    "MAX_CAP",
    "CHUNK_BYTES",
    "EngineResult",
    "Orbits",
    "DeviceJob",
    "JobProgress",
    "engine_devices",
    "default_lanes",
    "cpu_lanes",
    "params_arrays",
    "max_kernel_calls",
    "check_observers",
    "run",
    "run_orbits",
]
