"""The atlas store under faults (issue 29 items 2, 3, 5; docs/atlas.md "Integrity, one writer, faults"):
damaged tiles found by their checksums and computed again, damaged metadata refused and kept, one
writer at a time (a held lock, --overwrite, a stale lock from a killed writer), a full disk, a lost
scheduler and no workers.

Most runs use a cheap stand-in for the compute seam (:func:`fake`: no JAX, no compilation), since what
is tested is the store and the cluster handling, not the numbers; the command-line runs here are all
refused or given up before anything is computed."""

import hashlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("zarr")
pytest.importorskip("distributed")

import cloudpickle  # a dependency of distributed

from gear_rattle.validation.atlas import FIELDS, AtlasSpec
from gear_rattle.validation.writelock import StoreBusy, StoreLock, lock_path
from gear_rattle.validation.atlas.run import ClusterLost, run_atlas
from gear_rattle.validation.atlas.store import StoreWriteError, load_store
from gear_rattle.validation.cli import main
from atlasgrid import CLI_SMALL, SMALL  # the grid shared by the atlas tests

cloudpickle.register_pickle_by_value(sys.modules[__name__])  # fake() runs on Dask workers

TILES = [(0, 0), (0, 1), (1, 0), (1, 1)]  # SMALL in 2 x 2 tiles; tile (0, 1) is alpha 2.67, 3 at r 0.8, 0.85


def fake(alpha, r, spec):
    """A stand-in for the compute seam: every field a distinct function of the point."""
    return {
        "lambda1": np.sin(alpha * 7.0 + r),
        "lambda2": -alpha * r,
        "period_p": np.round(alpha * 10 + r * 100).astype(np.int32),
        "period_m": np.ones(alpha.shape, np.int32),
        "status": np.zeros(alpha.shape, np.int8),
    }


def counting(calls, compute=fake):
    def seam(alpha, r, spec):
        calls.append((float(alpha.min()), float(r.min())))
        return compute(alpha, r, spec)

    return seam


def fields(path):
    data = load_store(str(path)).read()
    return {k: data[k] for k in FIELDS}


def same(a, b):
    return all(np.array_equal(a[k], b[k], equal_nan=True) for k in FIELDS)


@pytest.fixture
def made(tmp_path):
    """A finished store of SMALL (fake numbers) and its fields."""
    path = tmp_path / "a.zarr"
    run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=fake)
    return path, fields(path)


def snapshot(path: Path) -> dict:
    """Every file of a folder with a digest of its bytes."""
    return {
        str(f.relative_to(path)): hashlib.sha256(f.read_bytes()).hexdigest()
        for f in sorted(path.rglob("*"))
        if f.is_file()
    }


# --- damaged tiles: found on resume, named, computed again --------------------------------------------


def _flip_value(p):  # a flipped bit in a value, written through Zarr (a valid chunk, its old checksum)
    import zarr

    a = zarr.open_group(str(p), mode="r+")["lambda1"]
    v = a[0:2, 2:4]
    v.view(np.uint64)[0, 0] ^= np.uint64(1)
    a[0:2, 2:4] = v


def _flip_byte(p):  # a flipped bit in the file (compressed bytes)
    f = p / "lambda1" / "c" / "0" / "1"
    b = bytearray(f.read_bytes())
    b[len(b) // 2] ^= 0x10
    f.write_bytes(bytes(b))


def _truncate(rel):
    def damage(p):
        f = p / rel
        f.write_bytes(f.read_bytes()[: len(f.read_bytes()) // 2])

    return damage


DAMAGE = {
    "flipped bit in a lambda1 value": (_flip_value, "lambda1 chunk lambda1/c/0/1 does not match its checksum"),
    "flipped bit in a lambda1 chunk file": (_flip_byte, "lambda1 chunk lambda1/c/0/1"),
    "deleted lambda1 chunk": (lambda p: (p / "lambda1/c/0/1").unlink(), "lambda1 chunk lambda1/c/0/1 is missing"),
    "lambda1 chunk copied from tile (0, 0)": (
        lambda p: (p / "lambda1/c/0/1").write_bytes((p / "lambda1/c/0/0").read_bytes()),
        "lambda1 chunk lambda1/c/0/1 does not match its checksum",
    ),
    "truncated lambda1 chunk": (_truncate("lambda1/c/0/1"), "lambda1 chunk lambda1/c/0/1 is unreadable"),
    "truncated period_p chunk": (_truncate("period_p/c/0/1"), "period_p chunk period_p/c/0/1 is unreadable"),
    "truncated done chunk": (_truncate("done/c/0/1"), "its done flag done/c/0/1 is unreadable"),
    "deleted checksum chunk": (lambda p: (p / "checksum/c/0/1/0/0").unlink(), "has no checksum recorded"),
    "tile_seconds chunk copied": (
        lambda p: (p / "tile_seconds/c/0/1").write_bytes((p / "tile_seconds/c/1/1").read_bytes()),
        "tile_seconds chunk tile_seconds/c/0/1 does not match its checksum",
    ),
}


@pytest.mark.parametrize("kind", list(DAMAGE))
def test_damaged_tile_is_named_and_computed_again(kind, made):
    """Issue 29: a flipped bit, a deleted chunk (16 values NaN) or a chunk copied from another tile were
    kept on resume (exit 0, unchanged counts); a truncated chunk made every resume end in a 90-line Zstd
    traceback, a truncated done chunk in an error that did not name the file.  Now each is found by the
    tile's checksums, named in a note (tile and chunk), and only that tile is computed again."""
    path, before = made
    damage, what = DAMAGE[kind]
    damage(path)
    calls, notes = [], []
    run = run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=counting(calls), note=notes.append)
    assert run.computed == [(0, 1)] and len(calls) == 1 and run.skipped == 3
    assert [d.tile for d in run.store.damaged] == [(0, 1)]
    assert len(notes) == 1 and "tile (0, 1)" in notes[0] and what in notes[0] and "computing it again" in notes[0], (
        notes
    )
    assert same(fields(path), before) and load_store(str(path)).done().all()
    assert load_store(str(path)).verify() == []
    again = run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=counting(calls), note=notes.append)
    assert again.computed == [] and len(notes) == 1  # repaired: nothing more to say


def test_undamaged_resume_says_nothing(made):
    path, before = made
    notes = []
    run = run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=fake, note=notes.append)
    assert run.computed == [] and notes == [] and same(fields(path), before)


# --- damaged metadata: refused in one line, nothing deleted --------------------------------------------


def _edit_json(rel, old, new):
    def damage(p):
        f = p / rel
        text = f.read_text()
        assert old in text
        f.write_text(text.replace(old, new, 1))

    return damage


def _empty_attrs(p):
    import zarr

    zarr.open_group(str(p), mode="r+").attrs.put({})


META_DAMAGE = {
    "emptied attributes": (_empty_attrs, "zarr.json) are not an atlas's (empty)"),
    "truncated group zarr.json": (_truncate("zarr.json"), "zarr.json is unreadable"),
    "a spec value changed": (
        _edit_json("zarr.json", '"impacts": 500', '"impacts": 501'),
        "zarr.json) do not match their checksum",
    ),
    "truncated lambda1/zarr.json": (_truncate("lambda1/zarr.json"), "array 'lambda1'"),
    "deleted done/zarr.json": (lambda p: (p / "done/zarr.json").unlink(), "array 'done'"),
    "a grid value changed": (lambda p: _set_first(p, "alpha", 2.5), "its grid (alpha, r) differs from its spec"),
}


def _set_first(p, name, value):
    import zarr

    zarr.open_group(str(p), mode="r+")[name][0] = value


@pytest.mark.parametrize("kind", list(META_DAMAGE))
@pytest.mark.parametrize("overwrite", [False, True])
def test_damaged_metadata_is_refused_and_kept(kind, overwrite, made):
    """Issue 29: a store whose group attributes were emptied was deleted and recomputed without a word.
    Now damaged metadata is refused in one line naming the store and the file, even with --overwrite,
    and the store is left as it is."""
    path, _ = made
    damage, what = META_DAMAGE[kind]
    damage(path)
    kept = snapshot(path)
    with pytest.raises(ValueError) as e:
        run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=fake, overwrite=overwrite)
    msg = str(e.value)
    assert "\n" not in msg and f"store {str(path)!r} is damaged" in msg and what in msg, msg
    assert snapshot(path) == kept and not lock_path(str(path)).exists()


def test_damaged_metadata_on_the_command_line(made, capsys):
    path, _ = made
    _empty_attrs(path)
    kept = snapshot(path)
    rc = main(CLI_SMALL + ["--scheduler", "serial", "--store", str(path), "--out", str(path.parent / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "is damaged" in err and "Traceback" not in err, err
    assert snapshot(path) == kept


def test_interrupted_creation_is_made_again(tmp_path):
    """A store whose creation was cut short (attributes marked 'creating') is made again, not refused."""
    import zarr

    path = tmp_path / "a.zarr"
    zarr.open_group(str(path), mode="w", attributes={"format": "gear-rattle-atlas/2", "creating": True})
    run = run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=fake)
    assert len(run.computed) == 4 and load_store(str(path)).done().all()


# --- one writer at a time ------------------------------------------------------------------------------

HOLDER = """
import sys, time
from gear_rattle.validation.writelock import StoreLock
locks = [StoreLock(store, command="holder-of-the-test").acquire() for store in sys.argv[2:]]
print("held", flush=True)
if sys.argv[1] == "die":
    import os, signal
    os.kill(os.getpid(), signal.SIGKILL)
sys.stdin.read()
for lock in locks:
    lock.release()
"""


def _holder(*stores, how="hold"):
    """A process that holds the locks of ``stores`` until its stdin closes (or is killed at once)."""
    p = subprocess.Popen(
        [sys.executable, "-c", HOLDER, how, *map(str, stores)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    line = p.stdout.readline()
    if how == "hold":
        assert line.strip() == "held", p.stderr.read()
    else:
        p.wait(timeout=60)
        assert p.returncode == -signal.SIGKILL
    return p


def test_second_writer_is_refused_in_one_line(made, capsys):
    """Issue 29: `atlas --overwrite` started while another atlas wrote the same store: both exited 0 and
    the store mixed two specs; two identical commands on a new store: Zarr's "An array exists in store".
    Now the second command is refused in one line naming the store and the holder, and the store is as
    the first left it."""
    path, before = made
    new = path.parent / "new.zarr"
    kept = snapshot(path)
    holder = _holder(path, new)
    try:
        for overwrite in ([], ["--overwrite"]):
            rc = main(
                CLI_SMALL
                + [
                    "--impacts",
                    "400",
                    "--scheduler",
                    "serial",
                    "--store",
                    str(path),
                    "--quiet",
                    "--out",
                    str(path.parent / "o"),
                ]
                + overwrite
            )
            err = capsys.readouterr().err
            assert rc == 1 and err.count("\n") == 1 and "Traceback" not in err, err
            assert f"store {str(path)!r} is in use by another writer: pid {holder.pid} on host" in err
            assert "holder-of-the-test" in err
            assert snapshot(path) == kept
        # a new store: nothing is created
        with pytest.raises(StoreBusy, match=f"pid {holder.pid}"):
            run_atlas(SMALL, str(new), tile=(2, 2), scheduler="serial", compute=fake)
        assert not new.exists()
    finally:
        holder.communicate("")
    assert not lock_path(str(path)).exists() and not lock_path(str(new)).exists()
    # the holder gone, the store resumes (and this run leaves no lock behind)
    run = run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=fake)
    assert run.computed == [] and same(fields(path), before) and not lock_path(str(path)).exists()


def test_lock_in_this_process_and_released_on_error(made):
    path, _ = made
    with StoreLock(str(path)):
        with pytest.raises(StoreBusy, match="in use by another writer"):
            run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=fake, overwrite=True)
    other = AtlasSpec(**{**SMALL.to_dict(), "impacts": 600})
    with pytest.raises(ValueError, match="different spec"):
        run_atlas(other, str(path), tile=(2, 2), scheduler="serial", compute=fake)
    assert not lock_path(str(path)).exists()


def test_stale_lock_of_a_killed_writer_is_taken_over(made):
    """A writer killed with SIGKILL leaves its lock file (with its record) but not its flock: the next
    run takes it over with a note naming the dead writer, checks the tiles, and removes the file."""
    path, before = made
    dead = _holder(path, how="die")
    assert lock_path(str(path)).exists()
    notes = []
    run = run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=fake, note=notes.append)
    assert run.computed == [] and same(fields(path), before)
    assert len(notes) == 1 and "took over the lock" in notes[0] and f"pid {dead.pid} on host" in notes[0], notes
    assert not lock_path(str(path)).exists()


@pytest.mark.slow
def test_two_identical_commands_on_a_new_store(tmp_path):
    """Two identical commands started together on a new store: one computes, the other is refused in one
    line (it was Zarr's "An array exists in store"); the store is whole.  (Two JAX processes: slow.)"""
    args = [
        sys.executable,
        "-m",
        "gear_rattle",
        *CLI_SMALL,
        "--scheduler",
        "serial",
        "--quiet",
        "--store",
        str(tmp_path / "a.zarr"),
    ]
    ps = [
        subprocess.Popen(
            args + ["--out", str(tmp_path / f"o{k}")], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
        )
        for k in range(2)
    ]
    res = sorted((p.wait(timeout=300), p.stderr.read()) for p in ps)
    assert [rc for rc, _ in res] == [0, 1], res
    assert res[1][1].count("\n") == 1 and "is in use by another writer" in res[1][1]
    assert load_store(str(tmp_path / "a.zarr")).done().all() and load_store(str(tmp_path / "a.zarr")).verify() == []


# --- a full disk ---------------------------------------------------------------------------------------


@pytest.fixture
def tiny_disk(tmp_path):
    """A 256 KiB tmpfs (we must be allowed to mount one: root in the test container; else skipped)."""
    mnt = tmp_path / "tiny"
    mnt.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(mnt)], capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(
            f"cannot mount a tmpfs here ({(r.stderr or r.stdout).strip() or r.returncode}): no full disk to test"
        )
    yield mnt
    subprocess.run(["umount", "-l", str(mnt)], capture_output=True)


def _fill(folder: Path) -> None:
    fd = os.open(folder / "filler", os.O_WRONLY | os.O_CREAT)
    try:
        while True:
            os.write(fd, b"\0" * 4096)
    except OSError:
        pass
    finally:
        os.close(fd)


def test_disk_full_during_the_run_is_one_line(tiny_disk):
    """Issue 29: disk full in the atlas was an 81-line traceback.  Now one line naming the store and the
    tile; the tiles written before are stored and verified, and a rerun with space again completes it."""
    path = tiny_disk / "a.zarr"
    calls = []

    def filling(alpha, r, spec):
        if len(calls) == 2:
            _fill(tiny_disk)  # the disk fills up while the third tile is computed
        return counting(calls)(alpha, r, spec)

    with pytest.raises(StoreWriteError) as e:
        run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=filling)
    msg = str(e.value)
    assert "\n" not in msg and f"store {str(path)!r}: cannot write tile (1, 0): No space left on device" in msg, msg
    assert not lock_path(str(path)).exists()
    (tiny_disk / "filler").unlink()
    notes = []
    run = run_atlas(SMALL, str(path), tile=(2, 2), scheduler="serial", compute=fake, note=notes.append)
    assert run.computed == [(1, 0), (1, 1)] and notes == []
    assert load_store(str(path)).verify() == [] and load_store(str(path)).done().all()


def test_disk_full_on_the_command_line_is_one_line(tiny_disk, tmp_path, capsys):
    _fill(tiny_disk)
    rc = main(CLI_SMALL + ["--scheduler", "serial", "--store", str(tiny_disk / "a.zarr"), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 1 and err.count("\n") == 1 and "No space left on device" in err and "Traceback" not in err, err
    assert not lock_path(str(tiny_disk / "a.zarr")).exists()


# --- a lost scheduler, no workers ----------------------------------------------------------------------

# Dask pickles a function of an importable module by reference: the scheduler and worker processes
# import this module (fake, _slow) from the tests folder
ENV = {
    **os.environ,
    "PYTHONPATH": os.pathsep.join(filter(None, [str(Path(__file__).parent), os.environ.get("PYTHONPATH")])),
}


@pytest.fixture
def scheduler(tmp_path):
    """A real `dask scheduler` process (no workers) and its address."""
    info = tmp_path / "scheduler.json"
    p = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "distributed.cli.dask_scheduler",
            "--host",
            "127.0.0.1",
            "--port",
            "0",
            "--no-dashboard",
            "--scheduler-file",
            str(info),
        ],
        env=ENV,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    t0 = time.monotonic()
    while not info.exists() or not info.read_text().strip():
        assert p.poll() is None and time.monotonic() - t0 < 60, "the scheduler did not start"
        time.sleep(0.1)
    import json

    yield p, json.loads(info.read_text())["address"]
    if p.poll() is None:
        p.kill()
        p.wait()


def test_no_workers_waits_with_a_note_then_gives_up(scheduler, tmp_path, capsys):
    """Issue 29: with every worker dead the atlas waited silently for ever.  Now a note says that it
    waits, and after --timeout seconds it gives up in one line with exit status 3 (the tiles finished
    are stored)."""
    _, addr = scheduler
    t0 = time.monotonic()
    rc = main(CLI_SMALL + ["--scheduler", addr, "--timeout", "2", "--quiet", "--out", str(tmp_path / "o")])
    took = time.monotonic() - t0
    err = capsys.readouterr().err.splitlines()
    assert rc == 3 and len(err) == 2, err
    assert err[0] == (
        "gear-rattle atlas: note: no worker is connected to the scheduler: waiting for one (at most 2 s, --timeout)"
    )
    assert err[1].startswith(
        "gear-rattle atlas: error: no worker connected to the scheduler for 2 s (--timeout): "
        "gave up; the 0 tiles finished are stored"
    )
    assert 2 < took < 30
    assert load_store(str(tmp_path / "o" / "atlas.zarr")).done().sum() == 0


def _slow(alpha, r, spec):
    time.sleep(0.5)
    return fake(alpha, r, spec)


def test_scheduler_killed_mid_run_is_one_line(scheduler, tmp_path, capfd):
    """Issue 29: a dead scheduler printed ~36 lines of Dask traceback before the one-line error, and
    exited 2.  Now: ClusterLost (the command line's exit status 3), one line, nothing else on stderr, the
    tiles finished are stored and verified."""
    proc, addr = scheduler
    worker = subprocess.Popen(
        [sys.executable, "-m", "distributed.cli.dask_worker", addr, "--nthreads", "1", "--no-nanny", "--no-dashboard"],
        env=ENV,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:

        def kill_after_first(done, total):
            if done == 1:
                proc.kill()

        capfd.readouterr()
        t0 = time.monotonic()
        with pytest.raises(ClusterLost) as e:
            run_atlas(
                SMALL,
                str(tmp_path / "a.zarr"),
                tile=(2, 2),
                scheduler=addr,
                compute=_slow,
                progress=kill_after_first,
                timeout=60,
                note=lambda text: None,
            )  # (waiting for the worker)
        assert time.monotonic() - t0 < 60
    finally:
        worker.kill()
        worker.wait()
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith(f"lost the Dask scheduler {addr}") and "tiles finished are stored" in msg
    out, err = capfd.readouterr()
    assert err == "" and out == "", err
    st = load_store(str(tmp_path / "a.zarr"))
    assert st.done().sum() >= 1 and st.verify() == []


def test_timeout_option_is_checked(capsys):
    for bad in ("0", "-1", "nan", "1e8"):
        with pytest.raises(SystemExit) as e:
            main(CLI_SMALL + ["--timeout", bad])
        assert e.value.code == 2 and "--timeout" in capsys.readouterr().err
