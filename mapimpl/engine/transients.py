"""Transient durations of many initial conditions (Section 4 of the paper), chunked and jit-compiled.

**Setting.**  alpha = 1.245 (just past the crisis alpha_1 ~ 1.2437 of Fig. 8), r = 0.9,
beta = gamma = 0.1: the chaotic attractor has become a chaotic saddle and orbits end on the stable
4-impact period-1 orbit, found here by Newton's method (:func:`mapimpl.periodic.find_periodic`)
from the end of a long orbit, never hard-coded.

**Transient duration.**  ``n(IC)`` = the number of map iterations (impacts) until the pre-impact
state first lies within ``delta`` of a point of that periodic orbit, in the sup norm of
``(tau mod 2 pi, sdot)`` with the phase difference wrapped and the wall required to match.  The
engine records the first-hit iteration for several deltas at once (``deltas``) and stops an orbit
when it is within the smallest one, or after ``cap`` iterations (censored).

**Initial conditions.**  ``ic_mode="pre-impact"`` (default, the paper's map variables): ``(tau0,
sdot0)`` is the state just before an impact, ``sdot0 > 0`` at ``s = 0``.  ``ic_mode="free"``: a
free-flight state ``s(tau0) = s0``, ``sdot(tau0) = sdot0`` (e.g. ``s0 = -1``: just after leaving
the lower wall); its first impact is found with :func:`mapimpl.impact_map.free_flight_start` and
becomes iteration 0.  Initial conditions that chatter and stick go through the sticking policy
of :mod:`mapimpl.sticking` like every impact; ``nstick`` counts the episodes per orbit.

**Engine.**  :mod:`mapimpl.engine.kernel`: ``lanes`` orbits advance together in one
vmapped micro-step kernel; lanes are refilled from the chunk's queue as orbits end; a
``lax.while_loop`` over blocks of micro-steps exits early when the chunk is done, and returns to
Python every ``max_blocks`` blocks to draw the progress bar; once the queue is empty and few lanes
are busy, the busy ones move to a smaller block (:func:`kernel.compact`).  The queue is split over
all devices of the default backend, one driver thread each (on the CPU one device per core, see
:mod:`mapimpl._jax`).  Memory holds the lanes and a few integers per initial condition of the
chunk, never histories.  Runs on a GPU unchanged (larger ``lanes`` pays there).
"""

from __future__ import annotations

import math
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from .. import _jax  # noqa: F401
import jax
import jax.numpy as jnp

from ..finder import MAX_STEPS, T_MAX
from ..impact_map import ACTIVE, free_flight_start
from ..params import Params
from ..sticking import STICK_TIME
from ..progress import Progress
from . import kernel as K

#: The setting of the paper's Figs. 9-11.
PAPER_PARAMS = Params(alpha=1.245, beta=0.1, gamma=0.1, r=0.9)
#: The paper's box (Figs. 10 and 11): 3.0 < tau0 < 3.5, 0 < sdot0 < 0.5.
PAPER_BOX = (3.0, 3.5, 0.0, 0.5)
#: Default capture distance and the distances recorded alongside it.
DELTA = 1e-3
DELTAS = (1e-2, 1e-3, 1e-4, 1e-6)
IC_MODES = ("pre-impact", "free")
#: Tail of a run: once the queue is empty and at most 1/TAIL_SHRINK of the lanes are busy, the busy
#: ones move to a block TAIL_SHRINK times smaller (not below TAIL_MIN_LANES lanes).
TAIL_SHRINK, TAIL_MIN_LANES = 8, 32


@dataclass
class PeriodicTarget:
    """The attracting periodic orbit: its ``impacts`` pre-impact states and Floquet multipliers."""

    theta: np.ndarray
    sdot: np.ndarray
    wall: np.ndarray
    multipliers: np.ndarray
    residual: float


@lru_cache(maxsize=16)
def periodic_target(params: Params = PAPER_PARAMS, impacts: int = 4, guess: tuple = (3.2, 0.3),
                    settle: int = 4000) -> PeriodicTarget:
    """Find the stable ``impacts``-impact period-1 orbit by Newton (Fig. 8's orbit for alpha > alpha_1).

    A long orbit from ``guess`` settles near it; :func:`mapimpl.periodic.find_periodic` refines it.
    Raises ``ValueError`` if Newton fails or the orbit is not stable.
    """
    from ..orbit import map_orbit
    from ..periodic import find_periodic

    # follow the orbit until it repeats every ``impacts`` impacts (the transient has ended)
    tau, sdot = float(guess[0]), float(guess[1])
    for _ in range(25):
        seq = map_orbit(params, tau, sdot, settle)
        _, th, sd, _ = seq.impact_arrays()
        if seq.status != "active" or len(th) < 2 * impacts + 1:
            raise ValueError(f"orbit from guess={guess} ended ({seq.status}); cannot locate the periodic orbit")
        tau, sdot = float(th[-1]), float(sd[-1])
        dth = np.abs(np.angle(np.exp(1j * (th[-1 - impacts:] - th[-1 - 2 * impacts:-impacts]))))
        if np.max(dth) < 1e-6 and np.max(np.abs(sd[-1 - impacts:] - sd[-1 - 2 * impacts:-impacts])) < 1e-6:
            break
    po = find_periodic(params, tau, sdot, impacts)
    if not po.converged or not po.stable:
        raise ValueError(f"no stable {impacts}-impact period-1 orbit found from guess={guess} "
                         f"(converged={po.converged}, |multipliers|={np.abs(po.multipliers)})")
    # the wall of each pre-impact state follows the sign of its velocity (sdot > 0 hits s = 0);
    # (po.walls lists the same walls, aligned with po.tau and po.sdot)
    wall = np.where(np.asarray(po.sdot) > 0, 0, -1).astype(np.int32)
    return PeriodicTarget(np.asarray(po.tau), np.asarray(po.sdot), wall,
                          np.asarray(po.multipliers), float(po.residual))


@dataclass
class TransientResult:
    """Per-initial-condition results (flat arrays of length N, in input order).

    ``hit[:, j]``: first iteration within ``deltas[j]`` (-1: never, within the cap);
    ``n``: iterations performed; ``status``: :data:`kernel.STATUS_NAMES`; ``nstick``: sticking
    episodes.  ``duration(delta)`` gives the transient durations with censored orbits set to
    ``cap`` and a mask of censored ones.
    """

    tau0: np.ndarray
    sdot0: np.ndarray
    hit: np.ndarray
    n: np.ndarray
    status: np.ndarray
    nstick: np.ndarray
    deltas: np.ndarray
    delta: float
    cap: int
    params: Params
    ic_mode: str
    s0: float | None
    target: PeriodicTarget
    elapsed: float
    meta: dict = field(default_factory=dict)

    def column(self, delta: float | None = None) -> int:
        d = self.delta if delta is None else float(delta)
        j = np.flatnonzero(np.isclose(self.deltas, d, rtol=1e-12, atol=0))
        if len(j) == 0:
            raise ValueError(f"delta={delta!r} is out of range: allowed one of the recorded deltas {list(self.deltas)}")
        return int(j[0])

    def duration(self, delta: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(durations, censored)``: iterations to come within ``delta`` (``cap`` when never)."""
        h = self.hit[:, self.column(delta)]
        censored = h < 0
        return np.where(censored, self.cap, h), censored

    @property
    def impacts(self) -> int:
        """Total map iterations performed (the engine's work)."""
        return int(np.sum(self.n))

    @property
    def n_stuck_orbits(self) -> int:
        """Orbits with at least one sticking episode."""
        return int(np.sum(self.nstick > 0))

    def summary(self) -> dict:
        d, c = self.duration()
        return {
            "n_ic": int(len(self.n)), "cap": self.cap, "delta": self.delta, "ic_mode": self.ic_mode, "s0": self.s0,
            "censored": int(c.sum()), "mean_duration_uncensored": float(d[~c].mean()) if (~c).any() else math.nan,
            "orbits_with_sticking": self.n_stuck_orbits, "sticking_episodes": int(self.nstick.sum()),
            "status_counts": {K.STATUS_NAMES[s]: int(np.sum(self.status == s)) for s in np.unique(self.status)},
            "impacts": self.impacts, "elapsed_s": self.elapsed,
            "impacts_per_s": self.impacts / self.elapsed if self.elapsed > 0 else math.nan,
        }


def _check_ic_arrays(tau0, sdot0, ic_mode, s0):
    tau0 = np.atleast_1d(np.asarray(tau0, dtype=np.float64)).ravel()
    sdot0 = np.atleast_1d(np.asarray(sdot0, dtype=np.float64)).ravel()
    if tau0.shape != sdot0.shape:
        raise ValueError(f"tau0 and sdot0 must have the same length (got {tau0.size} and {sdot0.size})")
    if tau0.size == 0:
        raise ValueError("tau0 is empty: allowed at least one initial condition")
    if not np.all(np.isfinite(tau0)) or np.any(np.abs(tau0) > 1e6):
        raise ValueError("tau0 is out of range: allowed finite values with |tau0| <= 1e6")
    if not np.all(np.isfinite(sdot0)):
        raise ValueError("sdot0 is out of range: allowed finite values")
    if ic_mode not in IC_MODES:
        raise ValueError(f"ic_mode={ic_mode!r} is out of range: allowed one of {', '.join(IC_MODES)}")
    if ic_mode == "pre-impact":
        if np.any(sdot0 == 0.0):
            raise ValueError("sdot0 is out of range: a pre-impact state needs sdot0 != 0 (> 0 hits s = 0, < 0 hits s = -1)")
    else:
        if s0 is None or not (math.isfinite(float(s0)) and -1.0 <= float(s0) <= 0.0):
            raise ValueError(f"s0={s0!r} is out of range: allowed -1 <= s0 <= 0 for ic_mode='free'")
    return tau0, sdot0


_free_start_v = jax.jit(jax.vmap(free_flight_start, in_axes=(0, None, 0, None)))


def initial_states(params: Params, tau0, sdot0, ic_mode="pre-impact", s0=None):
    """Pre-impact states ``(theta, sdot, wall, ok)`` of the initial conditions (numpy arrays)."""
    tau0, sdot0 = _check_ic_arrays(tau0, sdot0, ic_mode, s0)
    if ic_mode == "pre-impact":
        th = np.asarray(K._reduce(jnp.asarray(tau0)))
        return th, sdot0.copy(), np.where(sdot0 > 0, 0, -1).astype(np.int32), np.ones(tau0.size, bool)
    st = _free_start_v(jnp.asarray(tau0), jnp.asarray(float(s0)), jnp.asarray(sdot0), params.arrays())
    ok = np.asarray(st.status) == ACTIVE
    return (np.asarray(st.theta), np.asarray(st.sdot), np.asarray(st.wall, dtype=np.int32), ok)


def _validate_run(deltas, delta, cap, lanes, block, chunk):
    d = np.asarray(sorted(set(float(x) for x in deltas) | {float(delta)}, reverse=True), dtype=np.float64)
    if not (math.isfinite(float(delta)) and float(delta) > 0):
        raise ValueError(f"delta={delta!r} is out of range: allowed 0 < delta (finite)")
    if np.any(~np.isfinite(d)) or np.any(d <= 0) or np.any(d > 10):
        raise ValueError(f"deltas={list(deltas)!r} are out of range: allowed 0 < delta <= 10")
    if int(cap) != cap or not (1 <= int(cap) <= 10**8):
        raise ValueError(f"cap={cap!r} is out of range: allowed integer 1 <= cap <= 1e8")
    for name, v, hi in (("lanes", lanes, 1 << 22), ("block", block, 1 << 16), ("chunk", chunk, 1 << 26)):
        if int(v) != v or not (1 <= int(v) <= hi):
            raise ValueError(f"{name}={v!r} is out of range: allowed integer 1 <= {name} <= {hi}")
    return d


def engine_devices(devices=None) -> list:
    """Devices the engine spreads its queue over: ``devices`` (a count or a list of JAX devices),
    default all devices of JAX's default backend (one per core on the CPU, see :mod:`mapimpl._jax`;
    the accelerator(s) when there is one)."""
    avail = jax.devices()
    if devices is None:
        return list(avail)
    if isinstance(devices, (int, np.integer)) and not isinstance(devices, bool):
        if not 1 <= int(devices) <= len(avail):
            raise ValueError(f"devices={devices!r} is out of range: allowed 1 <= devices <= {len(avail)} "
                             f"(the {jax.default_backend()} devices JAX sees)")
        return list(avail[:int(devices)])
    out = list(devices)
    if not out:
        raise ValueError("devices is empty: allowed a positive count or a list of JAX devices")
    return out


def _default_lanes(n_per_device: int) -> int:
    # enough lanes to amortise per-operation overhead, few enough that each lane serves ~16 orbits
    # (short tail when the queue runs dry); on the CPU 512 lanes keep the working set in cache when
    # every core runs a device (Fig. 11 on 2 cores: 140 s engine time at 512 lanes, 164 s at 2048)
    top = 512 if jax.default_backend() == "cpu" else 65536
    return int(min(top, max(64, 2 ** int(math.log2(max(n_per_device // 16, 1))))))


def _drive(jb: dict, cap: int, block: int, report) -> None:
    """Run one device's queue to the end: blocks of micro-steps, progress, and the tail compaction."""
    # every orbit ends within cap map iterations of bounded finder work, so the loop is bounded; the
    # guard only turns an engine bug into an error instead of a hang
    size = jb["carry"][0]["mode"].shape[0]
    max_calls = 1 + (cap + 1) * 200 * (jb["m"] // size + 2) // (block * 64)
    for _call in range(max_calls):
        jb["carry"], _ = K.run_blocks(jb["carry"], *jb["q"], jb["k"], block=block, max_blocks=64)
        lanes_s, res_s, next_ic = jb["carry"]
        n_busy = int(jnp.sum(lanes_s["mode"] != K.MODE_IDLE))
        drained = int(next_ic) >= jb["m"]
        report(jb, int(next_ic) - n_busy)
        if drained and n_busy == 0:
            return
        # the tail: queue empty, few long orbits left -> fewer lanes (same results)
        size = lanes_s["mode"].shape[0]
        while drained and n_busy <= size // TAIL_SHRINK and size // TAIL_SHRINK >= TAIL_MIN_LANES:
            size //= TAIL_SHRINK
        if size < lanes_s["mode"].shape[0]:
            jb["carry"] = (K.compact(lanes_s, size=size), res_s, next_ic)
    raise RuntimeError("transient engine made no progress (bug): queue not drained")


def transient_times(tau0, sdot0, params: Params = PAPER_PARAMS, *, ic_mode: str = "pre-impact", s0=None,
                    delta: float = DELTA, deltas=DELTAS, cap: int = 20000, lanes: int | None = None,
                    block: int = 32, chunk: int = 1 << 18, progress: bool | None = None,
                    label: str = "transients", target: PeriodicTarget | None = None,
                    stick_time: float = STICK_TIME, devices=None) -> TransientResult:
    """Transient duration of every initial condition ``(tau0[i], sdot0[i])`` (see module docstring).

    ``cap``: most map iterations per orbit; ``lanes``: orbits advanced together per device (default: a power of
    two near N/16 per device, at most 512 on CPU, 65536 on an accelerator); ``block``: micro-steps between
    refills; ``chunk``: initial conditions per kernel launch (bounds memory); ``devices``: a count or list of
    JAX devices to spread the initial conditions over (default: all of the default backend, see
    :func:`engine_devices`).  ``progress``: progress bar on stderr (default: when stderr is a terminal).
    Deterministic: no randomness inside, and each orbit's arithmetic does not depend on its lane, device or
    neighbours, so results do not depend on ``lanes``, ``chunk`` or ``devices``.
    """
    d = _validate_run(deltas, delta, cap, 1 if lanes is None else lanes, block, chunk)
    devs = engine_devices(devices)
    if target is None:
        target = periodic_target(params)
    th, sd, wall, ok = initial_states(params, tau0, sdot0, ic_mode, s0)
    tau0a = np.atleast_1d(np.asarray(tau0, np.float64)).ravel()
    sdot0a = np.atleast_1d(np.asarray(sdot0, np.float64)).ravel()
    n_ic = th.size
    if progress is None:
        progress = sys.stderr.isatty()
    k = K.make_consts((params.alpha, params.beta, params.gamma, params.r), target.theta, target.sdot, target.wall,
                      d, int(cap), stick_time=stick_time, t_max=T_MAX, max_steps=MAX_STEPS)
    nd = d.size
    hit = np.full((n_ic, nd), -1, np.int32)
    nn = np.zeros(n_ic, np.int32)
    status = np.full(n_ic, K.NOT_RUN, np.int32)
    nstick = np.zeros(n_ic, np.int32)
    # orbits whose free flight never reaches a wall are not run
    status[~ok] = K.ESCAPED
    idx_ok = np.flatnonzero(ok)
    ndev = max(1, min(len(devs), idx_ok.size))
    devs = devs[:ndev]
    if lanes is None:
        lanes = _default_lanes(min(idx_ok.size, int(chunk)) // ndev)
    k_dev = [jax.device_put(k, dv) for dv in devs]
    bar = Progress(label, bool(progress), total=idx_ok.size)
    t0 = time.perf_counter()
    done_total = 0
    for c0 in range(0, idx_ok.size, int(chunk)):
        # each device gets every ndev-th initial condition of the chunk (similar mixes of short and
        # long transients, so the devices finish together)
        jobs = []
        for j, dv in enumerate(devs):
            sel = idx_ok[c0:c0 + int(chunk)][j::ndev]
            m = sel.size
            if m == 0:
                continue
            q = tuple(jax.device_put(jnp.asarray(a[sel]), dv) for a in (th, sd, wall))
            res = dict(n=jnp.zeros(m, jnp.int32), status=jnp.full(m, K.NOT_RUN, jnp.int32),
                       nstick=jnp.zeros(m, jnp.int32), hitn=jnp.full((m, nd), -1, jnp.int32))
            carry = jax.device_put((K.idle_lanes(int(min(lanes, m)), nd), res, jnp.asarray(0, jnp.int32)), dv)
            jobs.append({"sel": sel, "m": m, "q": q, "k": k_dev[j], "carry": carry, "done": 0})
        # one thread per device drives its queue (JAX releases the GIL while it compiles and runs), so
        # the devices neither wait for each other nor compile one after the other
        lock = threading.Lock()

        def report(jb, n_done, _base=done_total, _jobs=jobs):
            with lock:
                jb["done"] = n_done
                bar.update(_base + sum(x["done"] for x in _jobs))

        with ThreadPoolExecutor(max_workers=len(jobs)) as pool:
            for f in [pool.submit(_drive, jb, int(cap), int(block), report) for jb in jobs]:
                f.result()
        for jb in jobs:
            res, sel = jb["carry"][1], jb["sel"]
            done_total += jb["m"]
            hit[sel] = np.asarray(res["hitn"])
            nn[sel] = np.asarray(res["n"])
            status[sel] = np.asarray(res["status"])
            nstick[sel] = np.asarray(res["nstick"])
    elapsed = time.perf_counter() - t0
    bar.update(idx_ok.size)
    bar.close()
    return TransientResult(tau0a, sdot0a, hit, nn, status, nstick, d, float(delta), int(cap), params, ic_mode,
                           None if s0 is None else float(s0), target, elapsed,
                           meta={"lanes": int(lanes), "block": int(block), "chunk": int(chunk),
                                 "backend": jax.default_backend(), "devices": len(devs)})


def grid(box=PAPER_BOX, nx: int = 400, ny: int = 400):
    """Cell-centred ``nx`` x ``ny`` mesh over ``box = (tau_lo, tau_hi, sdot_lo, sdot_hi)``.

    Returns ``(TAU, SDOT)`` of shape ``(ny, nx)`` (cell centres: the open box's edges, e.g.
    ``sdot0 = 0``, are never sampled).
    """
    t_lo, t_hi, s_lo, s_hi = (float(x) for x in box)
    if not (t_lo < t_hi and s_lo < s_hi) or not all(math.isfinite(x) for x in box):
        raise ValueError(f"box={box!r} is out of range: allowed finite (tau_lo < tau_hi, sdot_lo < sdot_hi)")
    for name, v in (("nx", nx), ("ny", ny)):
        if int(v) != v or not (1 <= int(v) <= 20000):
            raise ValueError(f"{name}={v!r} is out of range: allowed integer 1 <= {name} <= 20000")
    tx = t_lo + (np.arange(nx) + 0.5) * (t_hi - t_lo) / nx
    sy = s_lo + (np.arange(ny) + 0.5) * (s_hi - s_lo) / ny
    return np.meshgrid(tx, sy)
