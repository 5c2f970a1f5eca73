"""Parameter-plane atlas (`gear-rattle atlas`, docs/atlas.md): the compute seam's contract, tiles on Dask
equal to a serial run, resume after an interruption, a killed worker, spec mismatch, and the paper's
Fig. 4 points on the atlas.

Every run here uses one spec and 4-point tiles, so one compiled kernel serves the whole module; worker
processes share a JAX compilation cache (JAX_COMPILATION_CACHE_DIR) so that a restarted worker does not
compile again."""

import functools
import json
import os
import signal
import sys

import numpy as np
import pytest

pytest.importorskip("zarr")
pytest.importorskip("distributed")

import cloudpickle  # a dependency of distributed

from gear_rattle.validation.atlas import FIELDS, AtlasSpec, compute_tile
from gear_rattle.validation.atlas.run import run_atlas
from gear_rattle.validation.atlas.store import load_store, open_store
from gear_rattle.validation.cli import main
from atlasgrid import CLI_SMALL, SMALL  # the grid shared by the atlas tests

# the killer task below runs on Dask workers, which cannot import this test module: ship it by value
cloudpickle.register_pickle_by_value(sys.modules[__name__])


@pytest.fixture(scope="module", autouse=True)
def jax_cache_for_workers(tmp_path_factory):
    """Worker processes inherit the environment: they share one on-disk cache of compiled kernels."""
    old = os.environ.get("JAX_COMPILATION_CACHE_DIR")
    os.environ["JAX_COMPILATION_CACHE_DIR"] = str(tmp_path_factory.mktemp("jax_cache"))
    yield
    if old is None:
        os.environ.pop("JAX_COMPILATION_CACHE_DIR", None)
    else:
        os.environ["JAX_COMPILATION_CACHE_DIR"] = old


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The reference: SMALL computed in this process, 2 x 2 tiles."""
    path = tmp_path_factory.mktemp("serial") / "a.zarr"
    run = run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial")
    assert run.computed == [(0, 0), (0, 1), (1, 0), (1, 1)] and run.skipped == 0
    return load_store(str(path)).read()


def same(a, b):
    """Every field of two atlases equal, bit for bit (NaN == NaN)."""
    return all(np.array_equal(a[k], b[k], equal_nan=True) for k in FIELDS)


def idx(data, alpha, r):
    return int(np.argmin(np.abs(data["r"] - r))), int(np.argmin(np.abs(data["alpha"] - alpha)))


# --- the compute seam ------------------------------------------------------------------------------


def test_compute_tile_contract():
    # an orbit that ends (alpha = 0: the tooth rests on a wall for ever), one that sticks (alpha = 0.15,
    # r = 0.3), a chaotic one (Fig. 3: alpha = 3, r = 0.9) and the 6-impact orbit of Fig. 4 (r = 0.8)
    a = np.array([[0.0, 0.15], [3.0, 3.0]])
    r = np.array([[0.5, 0.3], [0.9, 0.8]])
    out = compute_tile(a, r, SMALL)
    assert set(out) == set(FIELDS)
    for k, (dt, _) in FIELDS.items():
        assert out[k].shape == (2, 2) and out[k].dtype == dt, k
    ended, stuck, chaos, per = (0, 0), (0, 1), (1, 0), (1, 1)
    assert out["status"][ended] == 1  # STUCK_FOREVER: the orbit ended
    assert np.isnan(out["lambda1"][ended]) and np.isnan(out["lambda2"][ended])
    assert out["period_p"][ended] == 0 and out["period_m"][ended] == 0
    assert out["status"][stuck] == 0 and np.isneginf(out["lambda1"][stuck]) and np.isneginf(out["lambda2"][stuck])
    for pt in (chaos, per):
        assert out["status"][pt] == 0 and np.isfinite(out["lambda1"][pt]) and out["lambda1"][pt] >= out["lambda2"][pt]
    assert out["lambda1"][chaos] > 0.1 and out["period_p"][chaos] == 0
    assert out["lambda1"][per] < 0 and (out["period_p"][per], out["period_m"][per]) == (6, 1)
    # a point's numbers do not depend on the other points of the batch or its place in it
    back = compute_tile(a.ravel()[::-1], r.ravel()[::-1], SMALL)
    for k in FIELDS:
        assert np.array_equal(back[k][::-1], out[k].ravel(), equal_nan=True), k


def test_compute_tile_bad_input():
    with pytest.raises(ValueError, match="shapes"):
        compute_tile(np.zeros(3), np.full(2, 0.9), SMALL)
    with pytest.raises(ValueError, match="r=1.2"):
        compute_tile(np.array([3.0]), np.array([1.2]), SMALL)
    empty = compute_tile(np.zeros((0, 2)), np.zeros((0, 2)), SMALL)
    assert all(v.shape == (0, 2) and v.dtype == FIELDS[k][0] for k, v in empty.items())


@pytest.mark.parametrize(
    "kw, name",
    [
        (dict(n_alpha=0), "n_alpha"),
        (dict(r_hi=1.5), "r_hi"),
        (dict(alpha_lo=-1.0), "alpha_lo"),
        (dict(alpha_lo=3.0, alpha_hi=2.0), "alpha_lo"),
        (dict(sdot0=0.0), "sdot0"),
        (dict(period_tol=0.0), "period_tol"),
        (dict(impacts=0), "impacts"),
        (dict(beta=0.0), "beta"),
    ],
)
def test_spec_validation(kw, name):
    with pytest.raises(ValueError, match=name):
        AtlasSpec(**kw)


# --- the paper's scans on the atlas -------------------------------------------------------------------


def test_fig4_points_on_the_atlas(serial):
    # Fig. 4 (alpha = 3): chaotic at r = 0.9 (lambda1 > 0, Fig. 3), the stable 6-impact period-1 orbit at
    # r = 0.8 (lambda1 < 0; 6 impacts in one driving period), as the 1-D code says (docs/dynamics.md)
    i, j = idx(serial, 3.0, 0.9)
    assert serial["lambda1"][i, j] > 0.1 and serial["period_p"][i, j] == 0
    i, j = idx(serial, 3.0, 0.8)
    assert serial["lambda1"][i, j] < 0
    assert (serial["period_p"][i, j], serial["period_m"][i, j]) == (6, 1)
    assert np.all(serial["done"]) and np.all(serial["status"] == 0)


# --- tiles on Dask ------------------------------------------------------------------------------------


def test_local_cluster_equals_serial(serial, tmp_path):
    # another tiling (1 x 4 tiles instead of 2 x 2) on 2 worker processes: the same atlas, bit for bit
    run = run_atlas(SMALL, str(tmp_path / "a.zarr"), tile=(1, 4), scheduler="local", workers=2)
    assert run.workers == 2 and sorted(run.computed) == [(0, 0), (1, 0), (2, 0)]
    got = load_store(str(tmp_path / "a.zarr")).read()
    assert same(got, serial) and np.all(got["done"])
    assert np.all(got["tile_seconds"] > 0) and np.all(got["tile_cpu_seconds"] > 0)  # timed on the workers


def _kill_first(marker, alpha, r, spec):
    """Compute seam that kills its own worker process the first time any task runs it."""
    try:
        fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return compute_tile(alpha, r, spec)
    os.write(fd, str(os.getpid()).encode())
    os.close(fd)
    os.kill(os.getpid(), signal.SIGKILL)


def test_killed_worker_loses_nothing(serial, tmp_path):
    marker = tmp_path / "killed"
    run = run_atlas(
        SMALL,
        str(tmp_path / "a.zarr"),
        tile=(2, 2),
        scheduler="local",
        workers=2,
        compute=functools.partial(_kill_first, str(marker)),
    )
    assert marker.exists() and int(marker.read_text()) != os.getpid()  # a worker did die
    assert len(run.computed) == 4
    got = load_store(str(tmp_path / "a.zarr")).read()
    assert same(got, serial) and np.all(got["done"])


# --- resume -------------------------------------------------------------------------------------------


def test_resume_computes_only_missing_tiles(serial, tmp_path):
    path = str(tmp_path / "a.zarr")
    calls = []

    def interrupted(alpha, r, spec):
        if len(calls) == 2:
            raise KeyboardInterrupt  # Ctrl-C during the third tile
        calls.append((float(alpha.min()), float(r.min())))
        return compute_tile(alpha, r, spec)

    with pytest.raises(KeyboardInterrupt):
        run_atlas(SMALL, path, tile=(2, 2), scheduler="serial", compute=interrupted)
    assert int(load_store(path).read()["done"].sum()) == 2

    def counted(alpha, r, spec):
        calls.append((float(alpha.min()), float(r.min())))
        return compute_tile(alpha, r, spec)

    calls.clear()
    run = run_atlas(SMALL, path, tile=(2, 2), scheduler="serial", compute=counted)
    assert len(calls) == 2 and run.skipped == 2 and run.computed == [(1, 0), (1, 1)]
    assert same(load_store(path).read(), serial)
    again = run_atlas(SMALL, path, tile=(2, 2), scheduler="serial", compute=counted)
    assert again.computed == [] and again.skipped == 4 and len(calls) == 2


def test_spec_mismatch_refused(tmp_path):
    path = str(tmp_path / "a.zarr")
    st = open_store(path, SMALL, (2, 2))
    assert st.group["lambda1"].chunks == (2, 2) and st.group.attrs["spec"] == SMALL.to_dict()
    st.write_tile(0, 0, {k: np.full((2, 2), 1, dt) for k, (dt, _) in FIELDS.items()})
    other = AtlasSpec(**{**SMALL.to_dict(), "impacts": 600})
    with pytest.raises(ValueError, match=r"different spec .*impacts 500 \(store\) != 600"):
        open_store(path, other, (2, 2))
    with pytest.raises(ValueError, match="tile"):
        open_store(path, SMALL, (1, 4))
    assert open_store(path, SMALL, (2, 2)).done()[0, 0]  # the same spec resumes
    fresh = open_store(path, other, (2, 2), overwrite=True)
    assert not fresh.done().any() and load_store(path).spec == other
    (tmp_path / "junk").mkdir()
    (tmp_path / "junk" / "keep.txt").write_text("not an atlas")
    with pytest.raises(ValueError, match="not an atlas store"):
        open_store(str(tmp_path / "junk"), SMALL, (2, 2), overwrite=True)
    assert (tmp_path / "junk" / "keep.txt").exists()


def test_the_papers_scans_only_in_the_papers_plane():
    """Issue 32 item 5: an atlas at beta = 0.2 drew and profiled "the paper's Fig. 4 scan" although the
    paper's scans are at beta = gamma = 0.1.  Away from that plane the summary says that no comparison is
    made and the figure draws no paper line; in it, both stay."""
    from gear_rattle.validation.atlas.summary import summarise
    from gear_rattle.validation.plots.atlas import atlas_figure

    z = np.zeros((3, 3))
    ints = z.astype(np.int64)
    data = dict(alpha=np.linspace(2.9, 3.1, 3), r=np.linspace(0.85, 0.95, 3), lambda1=z + 0.1, status=ints)
    data.update(period_p=ints, period_m=ints, done=np.ones((1, 1), bool))
    for beta, paper in ((0.1, True), (0.2, False)):
        spec = AtlasSpec(alpha_lo=2.9, alpha_hi=3.1, n_alpha=3, r_lo=0.85, r_hi=0.95, n_r=3, beta=beta)
        lines = json.loads(json.dumps(summarise(data, spec).as_dict()))["paper lines"]
        drawn = [x.get_label() for ax in atlas_figure(data, spec).axes for x in ax.get_lines()]
        if paper:
            assert lines["Fig. 4 (alpha = 3)"]["points"] == 3 and "the paper's Fig. 4 (alpha = 3) scan" in drawn
        else:
            assert isinstance(lines, str) and lines.startswith("no comparison with the paper") and "beta=0.2" in lines
            assert not any("paper" in x for x in drawn)


# --- command line -------------------------------------------------------------------------------------


def test_cli_serial_run_resume_and_mismatch(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(CLI_SMALL + ["--scheduler", "serial", "--quiet", "--out", str(out)]) == 0
    printed = json.loads(capsys.readouterr().out)  # stdout, not a terminal: the summary as strict JSON
    assert printed["run"]["tiles_computed"] == 4 and printed["run"]["tiles_resumed"] == 0
    summary = json.loads((out / "atlas_summary.json").read_text())
    assert summary["points_computed"] == 12 and summary["run"]["tiles_computed"] == 4
    fig4 = summary["paper lines"]["Fig. 4 (alpha = 3)"]
    assert fig4["grid_line"] == {"alpha": 3.0} and fig4["points"] == 3
    assert (out / "atlas.png").stat().st_size > 10_000
    assert main(CLI_SMALL + ["--scheduler", "serial", "--quiet", "--out", str(out)]) == 0
    resumed = json.loads(capsys.readouterr().out)["run"]
    assert resumed["tiles_computed"] == 0 and resumed["tiles_resumed"] == 4
    from gear_rattle.validation import cliutil  # on a terminal: lines for a person, no 'nan' rate

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cliutil, "is_terminal", lambda stream: True)
        assert main(CLI_SMALL + ["--scheduler", "serial", "--quiet", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "nothing to compute, all 4 tiles found in the store" in text and "nan" not in text
    # another spec on the same store: refused in one line, before computing
    rc = main(CLI_SMALL + ["--impacts", "400", "--scheduler", "serial", "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "different spec" in err and "--overwrite" in err


@pytest.mark.parametrize(
    "args, what",
    [
        (["--alpha-lo", "-1"], "--alpha-lo=-1.0"),
        (["--r-hi", "1.5"], "--r-hi=1.5"),
        (["--r-lo", "0.9", "--r-hi", "0.8"], "r_lo"),
        (["--sdot0", "0"], "--sdot0"),
        (["--period-tol", "2"], "--period-tol"),
        (["--beta", "0"], "beta"),
        (["--scheduler", "serial", "--workers", "2"], "--workers"),
        (["--scheduler", " "], "--scheduler"),
        (["--scheduler", "lcoal"], "--scheduler='lcoal'"),
    ],
)
def test_cli_bad_input_one_line_exit_2(args, what, tmp_path, capsys):
    rc = main(["atlas", "--out", str(tmp_path / "o")] + args)
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and what in err and "Traceback" not in err
    assert not (tmp_path / "o" / "atlas.zarr").exists()


def test_cli_bad_integer_exit_2(capsys):
    with pytest.raises(SystemExit) as e:
        main(["atlas", "--tile", "0"])
    assert e.value.code == 2 and "--tile" in capsys.readouterr().err


# --- paper scale (opt-in) -----------------------------------------------------------------------------


@pytest.mark.slow
def test_paper_scans_agree_with_the_1d_lyapunov_code():
    """The atlas along Fig. 4 (alpha = 3, r-scan) and Fig. 8 (r = 0.9, alpha-scan) against
    ``mapimpl.lyapunov`` (the code of ``gear-rattle lyapunov``) from the same initial condition,
    transient and length, and against the paper's description of both figures."""
    from gear_rattle.core.params import Params
    from gear_rattle.mapimpl.lyapunov import lyapunov

    n, tr = 4000, 2000
    scans = {}
    for param, lo, hi in (("r", 0.70, 0.95), ("alpha", 1.10, 1.40)):
        values = np.linspace(lo, hi, 26)
        a = values if param == "alpha" else np.full(values.size, 3.0)
        r = values if param == "r" else np.full(values.size, 0.9)
        out = compute_tile(a, r, AtlasSpec(transient=tr, impacts=n, period_max=32))
        ref = lyapunov(
            Params(3.0, 0.1, 0.1, 0.9), param, values, n_impacts=n, transient=tr
        )  # the varied one is replaced
        lam, per = out["lambda1"], out["period_p"] > 0
        assert np.all(np.isfinite(lam)) and np.all(out["status"] == 0)
        # the same orbit and the same exponent where the orbit is periodic (no chaos to amplify rounding) ...
        assert np.allclose(lam[per], ref.lam[per, 0], atol=1e-8, rtol=0)
        # ... and the same sign everywhere it is resolved by a 4000-impact sample
        clear = np.abs(ref.lam[:, 0]) > 0.02
        assert np.all(np.sign(lam[clear]) == np.sign(ref.lam[clear, 0]))
        scans[param] = values, lam, out["period_p"], out["period_m"]

    # Fig. 4: chaos above r2 = 0.8214 (docs/dynamics.md); below it, down to the period doublings, the stable
    # 6-impact period-1 orbit (6 impacts in 1 driving period, lambda1 < 0)
    v, lam, p, m = scans["r"]
    win = (v >= 0.765) & (v <= 0.821)
    assert np.all((p[win] == 6) & (m[win] == 1) & (lam[win] < 0))
    assert np.all(lam[v >= 0.83] > 0.1) and np.all(p[v >= 0.83] == 0)
    # Fig. 8: chaotic below the crisis alpha1 = 1.2437; above it the stable period-1 orbit with four impacts
    # (well above alpha1, where the chaotic transients are far shorter than the 2000 impacts discarded)
    v, lam, p, m = scans["alpha"]
    chaos = (v > 1.165) & (v < 1.2437)
    assert np.all(lam[chaos] > 0.1) and np.all(p[chaos] == 0)
    above = v >= 1.265
    assert np.all((p[above] == 4) & (m[above] == 1) & (lam[above] < 0))


# --- issue 23: tiles fitted to the grid, nothing left behind, Ctrl-C -----------------------------------


def test_tile_is_fitted_to_the_grid_and_bounded(tmp_path):
    """--tile 256 on a 2 x 2 grid computed 65536 padded orbits; --tile 100000 allocated 74.5 GiB."""
    from gear_rattle.validation.atlas.store import MAX_TILE_POINTS, fit_tile

    assert fit_tile(SMALL, 256) == (3, 4) and fit_tile(SMALL, (2, 100000)) == (2, 4)
    st = open_store(str(tmp_path / "a.zarr"), SMALL, 256)
    assert st.tile == (3, 4) and st.n_tiles == (1, 1) and st.group["lambda1"].chunks == (3, 4)
    assert open_store(str(tmp_path / "a.zarr"), SMALL, 10**5).tile == (3, 4)  # the same fitted tile resumes
    big = AtlasSpec(n_alpha=2000, n_r=2000)
    assert fit_tile(big, 1024) == (1024, 1024) and 1024 * 1024 == MAX_TILE_POINTS
    with pytest.raises(ValueError, match=r"tile=100000 is out of range on a 2000 x 2000 grid"):
        fit_tile(big, 100000)
    # a store of the format before checksums (issue 29; also the one before tiles were fitted) is not
    # resumed -- its tiles cannot be verified -- but recognised: --overwrite replaces it
    old = open_store(str(tmp_path / "old.zarr"), SMALL, (3, 4))
    old.group.attrs.put(
        {
            "format": "gear-rattle-atlas/1",
            "spec": SMALL.to_dict(),
            "tile": [16, 16],
            "engine": old.group.attrs["engine"],
        }
    )
    with pytest.raises(ValueError, match=r"format 'gear-rattle-atlas/1' of an older version, without checksums"):
        open_store(str(tmp_path / "old.zarr"), SMALL, (16, 16))
    assert open_store(str(tmp_path / "old.zarr"), SMALL, (16, 16), overwrite=True).tile == (3, 4)


@pytest.mark.parametrize(
    "args, what, status",
    [
        (["--scheduler", "tcp://127.0.0.1:1"], "--scheduler='tcp://127.0.0.1:1': cannot connect", 3),
        (
            ["--alpha-lo", "1e308", "--alpha-hi", "1e308"],
            "--alpha-lo=1e+308 is out of range: allowed 0 <= alpha <= 1e10",
            2,
        ),
        (["--alpha-hi", "1e11"], "--alpha-hi=100000000000.0 is out of range", 2),
        (
            ["--store", "/proc/s.zarr"],
            "--store: cannot create '/proc/s.zarr': directory '/proc': it does not accept new files",
            2,
        ),
        (
            ["--n-alpha", "2000", "--n-r", "2000", "--tile", "100000"],
            "--tile=100000 is out of range on a 2000 x 2000 grid",
            2,
        ),
    ],
)
def test_cli_failures_leave_nothing_behind(args, what, status, tmp_path, capsys):
    """Issue 23 item 12: each of these left a store or the --out folder behind and printed internal
    messages ("arange: cannot compute length"); now: one line naming the option, nothing created.  A
    scheduler that does not answer is a lost cluster, exit status 3, not a usage error (issue 29)."""
    out = tmp_path / "o"
    rc = main(CLI_SMALL[:-2] + ["--scheduler", "serial", "--out", str(out)] + args)
    err = capsys.readouterr().err
    assert rc == status and err.count("\n") == 1 and what in err, err
    assert list(tmp_path.iterdir()) == []


def _wait_until_workers_busy(pid: int, workers: int, cpu_s: float, at_most_s: float) -> None:
    """Return once ``workers`` worker processes under ``pid`` (the resource tracker aside) have each used
    ``cpu_s`` CPU seconds -- past the cluster's start (~1 CPU second each), in their tasks -- or after
    ``at_most_s`` seconds (the fixed wait this replaces) whatever they did."""
    import time

    import psutil

    root, t_end = psutil.Process(pid), time.monotonic() + at_most_s
    while time.monotonic() < t_end:
        busy = 0
        for c in root.children(recursive=True):
            try:
                if "resource_tracker" not in " ".join(c.cmdline()) and sum(c.cpu_times()[:2]) >= cpu_s:
                    busy += 1
            except psutil.Error:  # a process that ended meanwhile
                continue
        if busy >= workers:
            return
        time.sleep(0.1)


def test_ctrl_c_on_the_local_cluster_is_one_line(tmp_path):
    """Issue 23 item 4: Ctrl-C (SIGINT to the whole process group, as a terminal sends it) on an atlas on
    the default LocalCluster printed ~64 lines of worker tracebacks.  Now the workers start with SIGINT
    blocked, the command line ends at once with one line and status 130, and the workers exit with it."""
    import subprocess
    import time

    # 12 points x 1e7 transient impacts: minutes of work on 2 cores, so the run is still computing when
    # the signal comes however warm the compilation cache and however idle the machine
    p = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "gear_rattle",
            *CLI_SMALL[:-2],
            "--tile",
            "1",
            "--transient",
            "10000000",
            "--workers",
            "2",
            "--quiet",
            "--out",
            str(tmp_path / "o"),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        start_new_session=True,
        cwd=tmp_path,
    )
    _wait_until_workers_busy(p.pid, workers=2, cpu_s=3.0, at_most_s=12.0)  # the cluster is up and computing
    os.killpg(p.pid, signal.SIGINT)
    t0 = time.perf_counter()
    try:
        rc = p.wait(timeout=30)
        latency = time.perf_counter() - t0
        err = p.stderr.read().decode()  # after the workers are gone (they hold the pipe until they exit)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
    assert rc == 130 and err.strip() == "gear-rattle atlas: interrupted", err
    assert latency < 2.0, f"Ctrl-C acted after {latency:.2f} s"  # measured 0.05-0.07 s (see test_interrupt)
    # the store's lock goes with it (issue 29): the next run finds no stale lock to take over
    assert (tmp_path / "o" / "atlas.zarr").is_dir() and not (tmp_path / "o" / "atlas.zarr.lock").exists()


def test_local_cluster_with_port_8787_taken_says_nothing():
    """The scheduler's HTTP server took the default port 8787; with another cluster on the machine there
    ('Port 8787 is already in use', and a ResourceWarning) the command line showed both as notes, also
    on Ctrl-C.  It now listens on a free port: no warning whoever holds 8787."""
    import socket
    import warnings

    from gear_rattle.validation.atlas.run import local_cluster

    holder = socket.socket()
    try:
        holder.bind(("0.0.0.0", 8787))
        holder.listen()
    except OSError:  # another cluster holds it already: the case itself
        pass
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            cluster, client = local_cluster(1)
            try:
                assert cluster.scheduler.http_server.port != 8787
            finally:
                client.close()
                cluster.close()
    finally:
        holder.close()
    assert not [str(w.message) for w in caught if "8787" in str(w.message) or "unclosed" in str(w.message)]
