"""Parameter-plane atlas over (alpha, r) at fixed beta, gamma (default 0.1, 0.1, the paper's plane): the
largest Lyapunov exponent (per impact, QR method) and the period (p impacts in m driving periods) of the
attractor reached from one initial condition, computed in tiles on Dask (an embedded LocalCluster by
default, --scheduler ADDRESS for a running cluster, --scheduler serial in this process) and written to a
Zarr store tile by tile: rerunning the same command resumes an interrupted run.  Writes the figure
(atlas.png: lambda1 and period maps with the paper's Fig. 4 and Fig. 8 scans as lines) and a summary
(atlas_summary.json) to --out.  Needs the optional dependencies: pip install "gear-rattle[atlas]".
See docs/atlas.md."""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..cliutil import CliError, CommandFailed, add_output_options, add_start_args, nonneg_int, positive_int, real

#: Exit status of a lost Dask cluster: the scheduler does not answer or was lost, or no worker for --timeout.
EXIT_CLUSTER_LOST = 3

if TYPE_CHECKING:
    from ..atlas.spec import AtlasSpec

NAME = "atlas"

_FIELD = re.compile(
    r"^(alpha_lo|alpha_hi|n_alpha|r_lo|r_hi|n_r|tau0|sdot0|transient|impacts|period_max|"
    r"period_tol|tile_r|tile_alpha|tile|workers|scheduler|store)="
)


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..atlas.run import WORKER_TIMEOUT_S
    from ..atlas.spec import MAX_GRID, MAX_IMPACTS, MAX_PERIOD, AtlasSpec

    d = AtlasSpec()
    g = p.add_argument_group("grid (alpha = linspace(lo, hi, n) by r = linspace(lo, hi, n))")
    g.add_argument(
        "--alpha-lo",
        type=float,
        default=d.alpha_lo,
        help=f"lowest alpha, 0 <= alpha-lo <= alpha-hi (default {d.alpha_lo})",
    )
    g.add_argument(
        "--alpha-hi", type=float, default=d.alpha_hi, help=f"highest alpha, alpha-hi <= 1e10 (default {d.alpha_hi})"
    )
    g.add_argument(
        "--n-alpha",
        type=positive_int("--n-alpha", MAX_GRID),
        default=d.n_alpha,
        help=f"alpha values, 1 to {MAX_GRID} (default {d.n_alpha})",
    )
    g.add_argument("--r-lo", type=float, default=d.r_lo, help=f"lowest r, 0 < r-lo <= r-hi (default {d.r_lo})")
    g.add_argument("--r-hi", type=float, default=d.r_hi, help=f"highest r, r-hi <= 1 (default {d.r_hi})")
    g.add_argument(
        "--n-r",
        type=positive_int("--n-r", MAX_GRID),
        default=d.n_r,
        help=f"r values, 1 to {MAX_GRID} (default {d.n_r})",
    )
    g.add_argument("--beta", type=float, default=d.beta, help=f"damping, 0 < beta <= 1e10 (default {d.beta})")
    g.add_argument(
        "--gamma", type=float, default=d.gamma, help=f"constant torque term, |gamma| <= 1e10 (default {d.gamma})"
    )
    m = p.add_argument_group("orbits")
    add_start_args(m, (d.tau0, d.sdot0))
    m.add_argument(
        "--transient",
        type=nonneg_int("--transient", MAX_IMPACTS),
        default=d.transient,
        help=f"impacts discarded first, 0 to {MAX_IMPACTS} (default {d.transient})",
    )
    m.add_argument(
        "--impacts",
        type=positive_int("--impacts", MAX_IMPACTS),
        default=d.impacts,
        help=f"impacts averaged for lambda1 after --transient, 1 to {MAX_IMPACTS} (default {d.impacts})",
    )
    m.add_argument(
        "--period-max",
        type=positive_int("--period-max", MAX_PERIOD),
        default=d.period_max,
        help=f"longest period looked for, in impacts, 1 to {MAX_PERIOD}; 2x this many impacts are recorded (default "
        f"{d.period_max})",
    )
    m.add_argument(
        "--period-tol",
        type=float,
        default=d.period_tol,
        help=f"state distance below which a period is recognised, 0 < period-tol < 1 (default {d.period_tol:g})",
    )
    r = p.add_argument_group("run")
    r.add_argument(
        "--tile",
        type=positive_int("--tile", 100_000),
        default=16,
        help="tile side in grid points, 1 to 100000, "
        "fitted to the grid: one task and one Zarr chunk per tile (default 16)",
    )
    r.add_argument("--store", default=None, help="Zarr store (default: OUT/atlas.zarr); rerun to resume")
    r.add_argument("--overwrite", action="store_true", help="replace a store made with other options")
    r.add_argument(
        "--scheduler",
        default="local",
        metavar="local|serial|ADDRESS",
        help="local: embedded LocalCluster; serial: in this process; ADDRESS: a Dask "
        "scheduler such as tcp://host:8786 (default local)",
    )
    r.add_argument(
        "--workers",
        type=positive_int("--workers", 1024),
        default=None,
        help="worker processes of the local cluster, 1 to 1024 (default: one per core)",
    )
    r.add_argument(
        "--timeout",
        type=real("--timeout", lo=0.0, hi=1e7, lo_open=True),
        default=WORKER_TIMEOUT_S,
        metavar="SECONDS",
        help="give up (exit status 3) after this many seconds with no Dask worker "
        "connected, 0 < SECONDS <= 1e7 (default %(default)s)",
    )
    add_output_options(r, out=("atlas", "directory for atlas.png and atlas_summary.json (default atlas)"))


def _option_names(e: ValueError) -> ValueError:
    """Name the command-line option (``--alpha-lo``) rather than the spec field (``alpha_lo``)."""
    msg = str(e)
    return ValueError(_FIELD.sub(lambda mt: "--" + mt.group(1).replace("_", "-") + "=", msg))


def _spec(args: argparse.Namespace) -> AtlasSpec:
    """The :class:`AtlasSpec` of the command line; a bad value is a
    ValueError naming the option (``--alpha-lo``)."""
    from ..atlas.spec import AtlasSpec

    try:
        spec = AtlasSpec(
            args.alpha_lo,
            args.alpha_hi,
            args.n_alpha,
            args.r_lo,
            args.r_hi,
            args.n_r,
            args.beta,
            args.gamma,
            args.tau0,
            args.sdot0,
            args.transient,
            args.impacts,
            args.period_max,
            args.period_tol,
        )
    except ValueError as e:
        raise _option_names(e) from None
    return spec


def run(args: argparse.Namespace) -> int:
    spec = _spec(args)
    from ..writelock import StoreBusy, StoreLock
    from ..atlas.run import ClusterLost, check_scheduler, import_distributed, run_atlas
    from ..atlas.store import StoreWriteError
    from ..atlas.store import fit_tile, import_zarr, load_store
    from ..cliutil import check_output_dir, check_outputs

    import_zarr()  # a missing extra: one line naming it, exit 2 (cli.main), before anything is written
    if args.scheduler != "serial":
        import_distributed()
    try:
        check_scheduler(args.scheduler, args.workers)
        fit_tile(spec, args.tile)
    except ValueError as e:
        raise _option_names(e) from None
    # every path is checked before anything is created (a store, the --out folder): run_atlas creates the
    # store only after a remote scheduler has answered
    out = Path(args.out)
    check_outputs(args)
    store = args.store if args.store is not None else str(out / "atlas.zarr")
    check_output_dir(store, "--store" if args.store is not None else "--out")
    from ...core.progress import Bar

    from ..cliutil import COMMAND, note

    lock = StoreLock(store)  # taken by run_atlas once the scheduler answers; held until the store is read
    try:
        with Bar(
            "atlas",
            unit="tiles",
            enabled=not args.quiet,
            phase="starting workers" if args.scheduler == "local" else "starting",
        ) as bar:
            try:
                res = run_atlas(
                    spec,
                    store,
                    (args.tile, args.tile),
                    args.scheduler,
                    args.workers,
                    args.overwrite,
                    progress=bar,
                    timeout=args.timeout,
                    lock=lock,
                    note=note,
                )
            except ClusterLost as e:  # not a usage error: its own status, one line (cliutil's format)
                print(f"{COMMAND[0]}: error: {_option_names(ValueError(str(e)))}", file=sys.stderr)
                return EXIT_CLUSTER_LOST
            except ValueError as e:
                raise _option_names(e) from None
            except (StoreBusy, StoreWriteError) as e:
                raise CommandFailed(str(e)) from None
            except RuntimeError as e:
                raise CliError(str(e)) from None
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise CliError(f"--out: cannot create directory {str(out)!r}: {e.strerror}") from None
        st = load_store(store)
        data = st.read()
    finally:
        lock.release()
    _write_results(args, spec, store, out, res, data)
    return 0


def _write_results(args: argparse.Namespace, spec: AtlasSpec, store: str, out: Path, res, data) -> None:
    """Summarise the store's ``data`` and this run's record ``res``: write atlas_summary.json and
    atlas.png to ``out`` and print the summary lines."""
    from ..atlas.summary import summarise
    from ..cliutil import print_result
    from ..io import save_figure, write_json
    from ..plots.atlas import atlas_figure

    summary = summarise(data, spec, res)
    summary.store = store
    assert summary.run is not None, "summarised with this run's record"
    write_json(out / "atlas_summary.json", summary.as_dict())
    save_figure(atlas_figure(data, spec), out / "atlas.png")
    print_result(
        summary.as_dict(),
        [
            _run_line(spec, summary.run, args.scheduler),
            f"chaotic (lambda1 > 0): {summary.chaotic}, periodic: {summary.periodic}, sticking: {summary.sticking}, "
            f"ended: {summary.ended} of {summary.points_computed} points",
            f"wrote {store}, {out / 'atlas.png'}, {out / 'atlas_summary.json'}",
        ],
        [out / "atlas_summary.json"],
    )


def _run_line(spec, ru: dict, scheduler: str) -> str:
    """What this run did: tiles computed and resumed, and its speed -- only when it computed something
    (a resumed atlas with nothing left printed "0 points x impacts/s ... nan")."""
    head = (
        f"atlas {spec.n_alpha} x {spec.n_r} (alpha {spec.alpha_lo:g}..{spec.alpha_hi:g}, r {spec.r_lo:g}.."
        f"{spec.r_hi:g}): "
    )
    if ru["tiles_computed"] == 0:
        n = ru["tiles_resumed"]
        return head + (
            "nothing to compute, the one tile found in the store"
            if n == 1
            else f"nothing to compute, all {n} tiles found in the store"
        )
    tile_rate = ru["median tile throughput per worker (points x impacts / s, wall)"]
    return head + (
        f"{ru['tiles_computed']} tiles computed, {ru['tiles_resumed']} found in the store; "
        f"{ru['wall_seconds']:.1f} s on {ru['workers']} worker(s) ({scheduler}), "
        f"{ru['throughput (points x impacts / s, wall, start-up and compile included)']:.3g} "
        f"points x impacts/s (start-up and compile included; median tile: {tile_rate:.3g} per worker)"
    )


__all__ = [
    "EXIT_CLUSTER_LOST",
    "NAME",
    "add_arguments",
    "run",
]
