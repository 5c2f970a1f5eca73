"""Running an atlas: tiles of the (alpha, r) grid computed by :func:`.compute.compute_tile` on Dask
(or in-process) and written to the Zarr store as they finish (:mod:`.store`).

Schedulers (``scheduler=``):

* ``"local"`` (default): an embedded ``distributed.LocalCluster`` -- worker *processes*, one thread
  each, ``workers`` of them (default: one per available core);
* ``"tcp://HOST:PORT"`` (any other string): the scheduler of a running Dask cluster.  Workers need
  ``gear-rattle`` installed; they never touch the store (results come back to this process, which
  writes them), so the store only has to be reachable from here;
* ``"serial"``: in this process, tile after tile (no Dask needed; what the tests compare against).

Every tile is padded to the full tile shape (edge values repeated, then cropped), so that one compiled
kernel serves all tiles.  A point's numbers depend on nothing but the point and the spec, so the atlas
is the same for any tiling, worker count or scheduler (``tests/test_atlas.py``).  A worker process that
dies (killed, out of memory) costs only its running tile: Dask reruns it on another worker.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import signal
import socket
import time
import warnings
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .. import interrupt
from ...core.checks import InputTypeError, check_int
from .compute import compute_tile
from ..extras import require
from ..writelock import StoreLock, holder_text
from .spec import AtlasSpec
from .store import AtlasStore, StoreWriteError, fit_tile, open_store, tile_slices

ComputeFn = Callable[[np.ndarray, np.ndarray, AtlasSpec], dict]

#: How long to wait for a remote scheduler.
CONNECT_TIMEOUT_S = 20

#: Default of ``timeout``: seconds a run waits with no worker connected before it gives up.
WORKER_TIMEOUT_S = 300.0

#: Seconds between two looks at the cluster (finished tiles are taken as they come, between looks).
POLL_S = 0.1


class ClusterLost(RuntimeError):
    """The Dask cluster is gone: the scheduler does not answer or was lost, or no worker came back within
    ``timeout`` seconds (the command line: one line, exit status 3)."""


def import_distributed():
    """The ``distributed`` module, or :class:`~validation.extras.MissingExtra` naming the ``atlas`` extra."""
    return require("distributed", "atlas", "the atlas on Dask")


def default_workers() -> int:
    """One worker per available core on the CPU; one worker when JAX runs on an accelerator (every worker
    process would otherwise claim the same device and its memory)."""
    import jax

    if jax.default_backend() != "cpu":
        return 1
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - non-Linux
        return max(1, os.cpu_count() or 1)


def check_scheduler(scheduler: str, workers: int | None) -> None:
    """``ValueError`` for a bad scheduler string or worker count (before anything starts)."""
    if not isinstance(scheduler, str) or not (scheduler in ("local", "serial") or ":" in scheduler):
        raise ValueError(
            f"scheduler={scheduler!r} is out of range: allowed 'local', 'serial' or a scheduler "
            "address such as tcp://host:8786"
        )
    if workers is not None:
        if scheduler != "local":
            raise ValueError(f"workers={workers!r} applies only to scheduler='local' (the embedded LocalCluster)")
        check_int("workers", workers, 1, 4096, strict=True)


def tile_points(spec: AtlasSpec, tile: tuple[int, int], i: int, j: int) -> tuple[np.ndarray, np.ndarray]:
    """``(alpha, r)`` arrays of the full tile shape for tile ``(i, j)``: the tile's grid points, edge
    tiles padded by repeating their last row / column (cropped again by :func:`crop`)."""
    rows, cols = tile_slices(spec, tile, i, j)
    a = spec.alphas[cols]
    r = spec.rs[rows]
    a = np.concatenate([a, np.full(tile[1] - a.size, a[-1])])
    r = np.concatenate([r, np.full(tile[0] - r.size, r[-1])])
    aa, rr = np.meshgrid(a, r)
    return aa, rr


def crop(spec: AtlasSpec, tile: tuple[int, int], i: int, j: int, result: dict) -> dict:
    """The part of a padded tile's result that lies in the grid."""
    rows, cols = tile_slices(spec, tile, i, j)
    nr, na = rows.stop - rows.start, cols.stop - cols.start
    return {k: np.asarray(v)[:nr, :na] for k, v in result.items()}


def _timed(compute: ComputeFn, alpha, r, spec):
    """``(result, wall seconds, CPU seconds of this process)`` of one tile."""
    t0, c0 = time.perf_counter(), time.process_time()
    out = compute(alpha, r, spec)
    return out, time.perf_counter() - t0, time.process_time() - c0


def _worker_task(compute: ComputeFn, alpha, r, spec):
    """Runs on a Dask worker: float64 JAX on one XLA CPU device per worker process, then the tile."""
    from ...core.jax_config import use_cpu_devices  # importing gear_rattle enables float64

    use_cpu_devices(1)  # a no-op once JAX has started in this worker
    return _timed(compute, alpha, r, spec)


@dataclass
class AtlasRun:
    """What one call of :func:`run_atlas` did."""

    store: AtlasStore
    scheduler: str
    workers: int
    tiles_total: int
    skipped: int
    computed: list[tuple[int, int]] = field(default_factory=list)
    remaining: list[tuple[int, int]] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def points_computed(self) -> int:
        sp, t = self.store.spec, self.store.tile
        n = 0
        for i, j in self.computed:
            rows, cols = tile_slices(sp, t, i, j)
            n += (rows.stop - rows.start) * (cols.stop - cols.start)
        return n

    @property
    def throughput(self) -> float:
        """Grid points x map steps per second of wall time, over this call (start-up and compile included)."""
        return self.points_computed * self.store.spec.impacts_per_point / self.seconds if self.seconds > 0 else 0.0


def run_atlas(
    spec: AtlasSpec,
    store: str,
    tile=(16, 16),
    scheduler: str = "local",
    workers: int | None = None,
    overwrite: bool = False,
    compute: ComputeFn = compute_tile,
    progress=None,
    timeout: float = WORKER_TIMEOUT_S,
    lock: StoreLock | None = None,
    note=None,
) -> AtlasRun:
    """Compute the tiles of ``spec`` missing from the Zarr ``store`` and write each as it finishes.

    An interrupted call keeps every stored tile; calling again resumes.  Nothing is created before the
    input is validated and a remote scheduler has answered.

    Parameters
    ----------
    spec : AtlasSpec
        The grid and the measurement (:class:`.spec.AtlasSpec`).
    store : str
        Path of the Zarr store (created if absent; layout in :mod:`.store`).
    tile : tuple of int, optional
        Points per tile ``(r, alpha)``, fitted to the grid (:func:`.store.fit_tile`).
    scheduler : str, optional
        ``"local"`` (embedded LocalCluster, ``workers`` processes, default one per core), ``"serial"``
        (in this process) or a Dask scheduler address.
    workers : int, optional
        Worker processes of the local cluster.
    overwrite : bool, optional
        Replace a store made with another spec or tile size (refused otherwise).
    compute : callable, optional
        The compute seam (default :func:`.compute.compute_tile`).
    progress : callable, optional
        ``progress(done, total)``, called after every stored tile.
    timeout : float, optional
        Seconds to wait while no worker is connected to the scheduler (a note says that it waits), then
        give up with :class:`ClusterLost` (default :data:`WORKER_TIMEOUT_S`, 300 s).
    lock : StoreLock, optional
        The store's lock, held by the caller until it is done with the store (acquired here if it is
        not held yet; the caller releases it).  Without it, this call takes the lock for its duration.
        A store whose lock another process holds is refused (:class:`..writelock.StoreBusy`).
    note : callable, optional
        ``note(text)`` for what the caller should know: a stale lock taken over, a damaged tile computed
        again, waiting for workers (default: :func:`warnings.warn`).

    Returns
    -------
    AtlasRun
        The store, the tiles computed and skipped, and the wall time.

    Raises
    ------
    ValueError
        For a bad argument, a store made otherwise (without ``overwrite``) or a damaged store's metadata.
    StoreBusy
        Another process writes the store (one line naming the holder).
    StoreWriteError
        The store cannot be written (disk full, ...): the tiles finished are stored.
    ClusterLost
        A scheduler that does not answer or was lost (naming ``scheduler``), or no worker for ``timeout``
        seconds.

    Examples
    --------
    A 3 x 4 atlas through Fig. 4's scan in four tiles, in this process; a second call finds every tile
    done and computes nothing:

    >>> from gear_rattle.validation.atlas.run import run_atlas
    >>> from gear_rattle.validation.atlas.spec import AtlasSpec
    >>> from gear_rattle.validation.atlas.store import load_store
    >>> spec = AtlasSpec(
    ...     alpha_lo=2.0, alpha_hi=3.0, n_alpha=4, r_lo=0.8, r_hi=0.9, n_r=3, transient=300, impacts=500, period_max=16
    ... )
    >>> run = run_atlas(spec, "atlas.zarr", tile=(2, 2), scheduler="serial")
    >>> run.tiles_total, len(run.computed), run.points_computed
    (4, 4, 12)
    >>> again = run_atlas(spec, "atlas.zarr", tile=(2, 2), scheduler="serial")
    >>> again.skipped, again.computed
    (4, [])
    >>> bool(load_store("atlas.zarr").done().all())
    True
    """
    if not isinstance(spec, AtlasSpec):
        raise InputTypeError(f"spec is a {type(spec).__name__}: allowed a validation.atlas.spec.AtlasSpec")
    check_scheduler(scheduler, workers)
    fit_tile(spec, tile)
    if (
        isinstance(timeout, bool)
        or not isinstance(timeout, (int, float, np.integer, np.floating))
        or not 0 < timeout <= 1e7
    ):
        raise ValueError(f"timeout={timeout!r} is out of range: allowed 0 < timeout <= 1e7 seconds")
    note = note if note is not None else _warn
    client = cluster = None
    own_lock = lock is None
    lock = StoreLock(store) if lock is None else lock

    def shut():
        _shutdown(client, cluster)
        if own_lock:
            lock.release()

    if scheduler not in ("serial", "local"):
        client = _connect(scheduler)  # before the store is created
    try:
        _take(lock, note)
        st = open_store(store, spec, tile, overwrite=overwrite)
        for d in st.damaged:
            note(f"store {store!r}: {d}: computing it again")
        tile = st.tile
        todo = st.missing()
        nt = st.n_tiles
        run = AtlasRun(st, scheduler, 1, nt[0] * nt[1], nt[0] * nt[1] - len(todo), remaining=list(todo))
        t0 = time.perf_counter()

        def store_one(ij: tuple[int, int], out: dict, secs: float, cpu: float) -> None:
            st.write_tile(*ij, crop(spec, tile, *ij, out), secs, cpu)
            run.computed.append(ij)
            run.remaining.remove(ij)
            run.seconds = time.perf_counter() - t0
            if progress is not None:
                progress(len(run.computed), len(todo))

        if not todo:
            return run
        if scheduler == "serial":
            for ij in todo:
                store_one(ij, *_timed(compute, *tile_points(spec, tile, *ij), spec))
            return run
        if client is None:
            run.workers = workers or default_workers()
            cluster, client = local_cluster(run.workers)
        else:
            run.workers = len(client.scheduler_info().get("workers", {}))
        _run_dask(spec, tile, todo, client, compute, run, store_one, timeout, note)
        return run
    finally:
        shut()


def _warn(text: str) -> None:
    warnings.warn(text, UserWarning, stacklevel=3)


def _take(lock: StoreLock, note) -> None:
    """Acquire ``lock`` if not held; note a stale lock taken over, or a file system without locks."""
    if lock.held:
        return
    try:
        lock.acquire()
    except OSError as e:
        raise StoreWriteError(
            f"store {lock.store!r}: cannot create its lock {str(lock.path)!r}: {e.strerror or e}"
        ) from None
    if lock.stale is not None:
        note(
            f"store {lock.store!r}: took over the lock of a writer that ended without releasing it (killed?): "
            f"{holder_text(lock.stale)}; its stored tiles are checked"
        )
    if lock.unsupported is not None:
        note(
            f"store {lock.store!r}: its file system does not lock files ({lock.unsupported}): a second writer "
            "would not be noticed"
        )


def _shutdown(client, cluster) -> None:
    """Close a client and its local cluster (once; quietly)."""
    with _quiet_dask():
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()


def _connect(scheduler: str):
    """A client of the Dask scheduler at ``scheduler`` (``ValueError`` naming it when it does not answer)."""
    distributed = import_distributed()
    _probe(scheduler)
    try:
        with _quiet_dask():
            return distributed.Client(scheduler, timeout=CONNECT_TIMEOUT_S)
    except (OSError, TimeoutError, ValueError) as e:
        raise ClusterLost(f"scheduler={scheduler!r}: cannot connect ({e})") from None


def _probe(scheduler: str) -> None:
    """A TCP address that refuses connections fails at once (Dask's client retries until its timeout)."""
    if not scheduler.startswith("tcp://"):
        return
    host, _, port = scheduler[len("tcp://") :].rpartition(":")
    try:
        with socket.create_connection((host.strip("[]") or "127.0.0.1", int(port)), timeout=CONNECT_TIMEOUT_S):
            pass
    except ValueError:
        raise ValueError(
            f"scheduler={scheduler!r} is out of range: allowed an address such as tcp://host:8786"
        ) from None
    except OSError as e:
        raise ClusterLost(f"scheduler={scheduler!r}: cannot connect ({e.strerror or e})") from None


_QUIET = ("distributed", "tornado", "bokeh", "asyncio")


@contextlib.contextmanager
def _quiet_dask():
    """Dask's own log records of this process (the client, the cluster's scheduler and nannies) are
    dropped while a run starts, computes and shuts down, CRITICAL included ("Failed to reconnect to
    scheduler", a lost scheduler's tracebacks): a failure reaches the caller as an exception (one line on
    the command line), an interruption as KeyboardInterrupt.  Every logger of those libraries is set,
    not only their roots: Dask's configuration gives some of them (``distributed.client``) levels of
    their own."""
    names = [n for n in list(logging.root.manager.loggerDict) if n.split(".")[0] in _QUIET] + list(_QUIET)
    loggers = [logging.getLogger(name) for name in dict.fromkeys(names)]
    levels = [lg.level for lg in loggers]
    for lg in loggers:
        lg.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for lg, lv in zip(loggers, levels):
            lg.setLevel(lv)


def local_cluster(n_workers: int):
    """An embedded LocalCluster of ``n_workers`` processes (one thread each) and its client.  Its threads
    and worker processes start with SIGINT blocked (the mask is inherited): a Ctrl-C at the terminal,
    which reaches the whole process group, interrupts this process only, which closes the cluster (or,
    on the command line, ends; the workers exit with it) -- no traceback from every worker."""
    distributed = import_distributed()
    # the tracker first: launching it unblocks SIGINT in the launching thread (CPython's resource_tracker).
    # On the command line its stderr is /dev/null: a Ctrl-C ends the process at once (the workers exit with
    # it), and the tracker then frees the cluster's semaphores -- with a "leaked semaphore" warning each time
    _start_resource_tracker(quiet=interrupt.command_line_process())
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        with _quiet_dask():
            # no dashboard; the scheduler's HTTP server (health routes) on a free port: its default 8787 taken
            # by another cluster on the machine gave a 'Port 8787 is already in use' note (and a ResourceWarning)
            cluster = distributed.LocalCluster(
                n_workers=n_workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                scheduler_kwargs={"dashboard_address": ":0"},
                silence_logs=logging.CRITICAL,
            )
            client = distributed.Client(cluster)
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)
    return cluster, client


def _start_resource_tracker(quiet: bool) -> None:
    """Start multiprocessing's resource tracker (if it is not running); with ``quiet``, with /dev/null as
    its stderr (file descriptor 2 is swapped while it starts: the tracker writes there)."""
    from multiprocessing import resource_tracker

    if not quiet:
        resource_tracker.ensure_running()
        return
    saved, null = os.dup(2), os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 2)
        resource_tracker.ensure_running()
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(null)


def _n_workers(client) -> int | None:
    """Workers connected to the scheduler; None when the client has lost the scheduler."""
    if client.status != "running":
        return None
    try:
        return len(client.scheduler_info(n_workers=-1).get("workers", {}))
    except (OSError, TimeoutError):
        return None


def _lost(client, run: AtlasRun, why: str = "") -> ClusterLost:
    addr = getattr(client, "scheduler", None)
    addr = getattr(addr, "address", None) or run.scheduler
    return ClusterLost(
        f"lost the Dask scheduler {addr}{' (' + why + ')' if why else ''}; the "
        f"{len(run.computed)} tiles finished are stored: rerun to resume"
    )


def _run_dask(spec, tile, todo, client, compute, run: AtlasRun, store_one, timeout: float, note) -> None:
    """Submit every tile of ``todo`` and store each as it finishes; meanwhile watch the cluster: a lost
    scheduler, or no worker for ``timeout`` seconds (after a note that it waits), ends the run with
    :class:`ClusterLost`."""
    distributed = import_distributed()
    futures = {}
    with _quiet_dask():
        try:
            for ij in todo:
                a, r = tile_points(spec, tile, *ij)
                fut = client.submit(
                    _worker_task,
                    compute,
                    a,
                    r,
                    spec,
                    pure=False,
                    key=f"atlas-tile-{ij[0]}-{ij[1]}-{os.getpid()}-{time.monotonic_ns()}",
                )
                futures[fut] = ij
            pending = distributed.as_completed(list(futures))
            alone_since, next_look = None, 0.0
            while not pending.is_empty():
                batch = pending.next_batch(block=False)
                for fut in batch:
                    ij = futures[fut]
                    try:
                        out, secs, cpu = fut.result()
                    except (Exception, asyncio.CancelledError) as e:  # a tile that failed on every try
                        if fut.cancelled() or client.status != "running":
                            raise _lost(client, run) from None
                        raise RuntimeError(
                            f"tile {ij} failed ({type(e).__name__}: {e}); the {len(run.computed)} "
                            "tiles finished are stored: rerun to resume"
                        ) from e
                    store_one(ij, out, secs, cpu)
                now = time.monotonic()
                if batch or now < next_look:
                    if not batch:
                        time.sleep(POLL_S)
                    continue
                next_look = now + 1.0
                n = _n_workers(client)
                if n is None:
                    raise _lost(client, run)
                if n > 0:
                    if alone_since is not None:
                        note(f"{n} worker(s) connected: computing")
                    alone_since = None
                elif alone_since is None:
                    alone_since = now
                    note(f"no worker is connected to the scheduler: waiting for one (at most {timeout:g} s, --timeout)")
                elif now - alone_since > timeout:
                    raise ClusterLost(
                        f"no worker connected to the scheduler for {timeout:g} s (--timeout): gave "
                        f"up; the {len(run.computed)} tiles finished are stored: rerun to resume"
                    )
        finally:
            for fut in futures:
                fut.cancel()


__all__ = [
    "ComputeFn",
    "CONNECT_TIMEOUT_S",
    "WORKER_TIMEOUT_S",
    "POLL_S",
    "ClusterLost",
    "import_distributed",
    "default_workers",
    "check_scheduler",
    "tile_points",
    "crop",
    "AtlasRun",
    "run_atlas",
    "local_cluster",
]
