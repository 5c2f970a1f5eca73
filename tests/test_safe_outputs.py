"""Nothing is lost and nothing half-written is kept (issue 29, items 1 and 3; the atlas store aside).

* The kill matrix: ``simulate --output big.csv`` (7 MB) and ``check --self --out DIR`` (25 files) are
  sent SIGTERM and SIGKILL at several moments of the run -- fractions of its duration and the moment
  the first output appears -- and after each the target is the earlier content or the new one, whole
  (a folder: every file earlier or every file new, or a manifest that says otherwise).  Before, a kill
  while writing left the file empty or cut, and ``check --self --out`` a mix of new and old files.
* ``--out`` owns only the files a command writes (``report --out .`` deleted ``figures/`` and ``data/``).
* Debris of a killed run is removed by the next run writing the same target, and nothing else is.
* A full disk (a 64 KiB tmpfs) and a name too long for the file system are one line each, the earlier
  file intact.
* SIGTERM acts as Ctrl-C: one line, exit status 143, no temporary file left.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.io import atomic

ENV = dict(os.environ, MPLBACKEND="Agg")
EARLIER = b"earlier output of the same name\n"
#: (signal, moment, exit status, what the target held) of every kill of the matrices, for a tally.
OUTCOMES: list = []


def run_cli(args, capsys):
    try:
        rc = main(args)
    except SystemExit as e:
        rc = e.code
    out = capsys.readouterr()
    return rc, out.out, out.err


def _console(args, cwd) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "gear_rattle", *args],
        cwd=cwd,
        env=ENV,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )


def _partials(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.rglob("*") if ".partial-" in p.name)


def _kill(args, cwd: Path, sig, when, watch: Path, names: list[str]):
    """Start the console script, send ``sig`` after ``when`` seconds or, for ``when == 'write'``, the moment
    one of ``names`` in ``watch`` changes or a temporary file of the writer appears there; returns
    (exit status, stderr)."""

    def state():
        out = []
        for n in names:
            try:
                st = os.stat(watch / n)
                out.append((st.st_ino, st.st_size, st.st_mtime_ns))
            except FileNotFoundError:
                out.append(None)
        return out

    before = state()
    p = _console(args, cwd)
    try:
        if when == "write":
            while p.poll() is None:
                if state() != before or any(".partial-" in e for e in os.listdir(watch)):
                    break
                time.sleep(0.0005)
        else:
            time.sleep(when)
        if p.poll() is None:
            p.send_signal(sig)
        _, err = p.communicate(timeout=120)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    return p.returncode, err.decode()


def _moments(duration: float) -> list:
    """Half-way through a run as long as the reference run, and the moment the first output appears."""
    return [0.5 * duration, "write"]


def _check_signal_outcome(sig, rc, err, command):
    if sig == signal.SIGTERM:
        # -15 with nothing said: the signal came while the interpreter started, before any of our code ran
        assert rc in (0, 143) or (rc == -signal.SIGTERM and err == ""), err
        if rc == 143:
            assert err == f"gear-rattle {command}: terminated\n" or err == "gear-rattle: terminated\n", err
    else:
        assert rc in (0, -signal.SIGKILL), err
    assert "Traceback" not in err


def _both_signals(series) -> list:
    """``series(signal)`` for SIGTERM and SIGKILL at once, each in its own folder (two processes at a time:
    the matrix takes half the time); the outcomes of both."""
    with ThreadPoolExecutor(2) as pool:
        return [o for outcomes in pool.map(series, (signal.SIGTERM, signal.SIGKILL)) for o in outcomes]


def _reference(args, cwd):
    """Run the command to its end; returns its duration (s)."""
    t0 = time.perf_counter()
    ref = subprocess.run([sys.executable, "-m", "gear_rattle", *args], cwd=cwd, env=ENV, capture_output=True)
    assert ref.returncode in (0, 1), ref.stderr
    return time.perf_counter() - t0


def test_kill_matrix_simulate_output_is_earlier_or_new_whole(tmp_path):
    """simulate --output big.csv (100000 impacts, 7 MB): SIGTERM and SIGKILL half-way through the run and
    the moment the output starts to change; each time big.csv is the earlier file or the new one,
    byte for byte, and the next run removes what a SIGKILL left.  Fails on the old code: the file was
    truncated, then written (0 bytes after the SIGTERM at the write)."""
    args = ["simulate", "--impacts", "100000", "--quiet", "--output"]
    duration = _reference([*args, "ref.csv"], tmp_path)
    new = (tmp_path / "ref.csv").read_bytes()
    assert len(new) > 5_000_000

    def series(sig):
        home = tmp_path / sig.name
        home.mkdir()
        target = home / "big.csv"
        target.write_bytes(EARLIER)
        outcomes = []
        for when in _moments(duration):
            rc, err = _kill([*args, "big.csv"], home, sig, when, home, ["big.csv"])
            _check_signal_outcome(sig, rc, err, "simulate")
            got = target.read_bytes()
            assert got in (EARLIER, new), (sig, when, rc, len(got))
            outcomes.append((sig.name, when, rc, "new" if got == new else "earlier"))
            if sig == signal.SIGTERM:
                assert _partials(home) == [], (when, _partials(home))  # cleaned up
            target.write_bytes(EARLIER)
        _reference([*args, "big.csv"], home)  # the next run: debris removed, the new file
        assert target.read_bytes() == new and _partials(home) == []
        return outcomes

    outcomes = _both_signals(series)
    OUTCOMES.extend(("simulate", *o) for o in outcomes)
    assert any(rc != 0 for *_, rc, _ in outcomes), outcomes  # the kills did land in the run


def test_kill_matrix_check_out_folder_is_all_earlier_or_all_new(tmp_path):
    """check --self --out c (25 case files): after SIGTERM every file is the earlier one or every file the
    new one; after SIGKILL too, or else the manifest says the folder mixes two runs; a file of the
    user's in c survives; the next run removes the debris.  Fails on the old code: each file was
    written when its case was done (a SIGTERM at 10.8 s left 14 of 25 new, the others old)."""
    args = ["check", "--self", "--quiet", "--out"]
    duration = _reference([*args, "ref"], tmp_path)
    names = sorted(p.name for p in (tmp_path / "ref").glob("*.csv"))
    assert len(names) >= 20
    new = {n: (tmp_path / "ref" / n).read_bytes() for n in names}

    def series(sig):
        home = tmp_path / sig.name
        out = home / "c"
        out.mkdir(parents=True)
        (out / "mine.txt").write_text("the user's")

        def reset():
            for n in names:
                (out / n).write_bytes(EARLIER)
            (out / "check.manifest.json").unlink(missing_ok=True)

        outcomes = []
        for when in _moments(duration):
            reset()
            rc, err = _kill([*args, "c"], home, sig, when, out, names)
            _check_signal_outcome(sig, rc, err, "check")
            got = {n: (out / n).read_bytes() for n in names}
            assert all(got[n] in (EARLIER, new[n]) for n in names), (sig, when)  # each file whole
            fresh = sum(got[n] == new[n] for n in names)
            if 0 < fresh < len(names):  # a mix: only a SIGKILL between two renames, and the manifest says so
                assert sig == signal.SIGKILL, (when, fresh)
                with pytest.raises(ValueError, match="mix two runs"):
                    atomic.read_manifest(out, "check")
            if sig == signal.SIGTERM:
                assert _partials(out) == [], _partials(out)
            assert (out / "mine.txt").read_text() == "the user's"
            outcomes.append((sig.name, when, rc, fresh))
        _reference([*args, "c"], home)
        assert all((out / n).read_bytes() == new[n] for n in names) and _partials(out) == []
        manifest = atomic.read_manifest(out, "check")
        assert sorted(manifest["files"]) == names and manifest["complete"] is True
        assert (out / "mine.txt").read_text() == "the user's"
        return outcomes

    outcomes = _both_signals(series)
    OUTCOMES.extend(("check", *o) for o in outcomes)
    assert any(rc != 0 for *_, rc, _ in outcomes), outcomes


# ---------------------------------------------------------------------- --out owns only its files


def _fake_report_writing_data(monkeypatch):
    """The fake report section (tests/reportfake.py), which also writes a data file, as the transients
    section does."""
    import reportfake

    fake = reportfake.fake_section

    def with_data(ctx):
        sec = fake(ctx)
        (ctx.out_dir / "data").mkdir(exist_ok=True)
        (ctx.out_dir / "data" / "survival.csv").write_text("n,p\n1,0.5\n")
        return sec

    monkeypatch.setattr(reportfake, "fake_section", with_data)
    return reportfake


def test_report_out_keeps_the_users_files_in_figures_and_data(tmp_path, monkeypatch):
    """`report --out .` replaced DIR/figures and DIR/data wholesale: mine.png and data/important.csv were
    deleted.  Now each file the report writes replaces only that file."""
    reportfake = _fake_report_writing_data(monkeypatch)
    out = tmp_path / "d"
    (out / "figures").mkdir(parents=True)
    (out / "data").mkdir()
    (out / "figures" / "mine.png").write_bytes(b"the user's figure")
    (out / "data" / "important.csv").write_text("the user's data")
    (out / "figures" / "fake.png").write_bytes(b"an earlier report's figure")
    monkeypatch.chdir(out)
    reportfake.build_fake_report(Path("."), monkeypatch)
    assert (out / "figures" / "mine.png").read_bytes() == b"the user's figure"
    assert (out / "data" / "important.csv").read_text() == "the user's data"
    assert (out / "figures" / "fake.png").read_bytes().startswith(b"\x89PNG")  # ours: replaced
    assert (out / "data" / "survival.csv").read_text() == "n,p\n1,0.5\n"
    manifest = atomic.read_manifest(out, "report")
    assert "figures/fake.png" in manifest["files"] and "figures/mine.png" not in manifest["files"]
    assert _partials(tmp_path) == []


def test_rerender_refuses_a_folder_whose_move_was_cut_and_keeps_the_manifest(tmp_path, monkeypatch):
    from gear_rattle.validation.report import builder

    reportfake = _fake_report_writing_data(monkeypatch)
    out = reportfake.build_fake_report(tmp_path / "r", monkeypatch)
    builder.rerender(out)
    files = atomic.read_manifest(out, "report")["files"]
    assert {"figures/fake.png", "report.html", "document.json"} <= set(files)  # merged: the figure kept
    m = out / "report.manifest.json"
    m.write_text(m.read_text().replace('"complete": true', '"complete": false'))
    with pytest.raises(ValueError, match="report.manifest.json.*mix two runs"):
        builder.rerender(out)


# ------------------------------------------------------------------------------------------- debris


def test_debris_of_a_killed_run_is_removed_by_the_next_and_nothing_else(tmp_path, capsys, monkeypatch):
    """A SIGKILL leaves the writer's temporary file (or a report's staging folder); the next run writing
    the same target removes it -- only names of the writer's pattern for that target, older than the
    run, whose process is gone.  Fails on the old code (nothing was removed: 824 KB folders piled up)."""
    import reportfake

    old, later = time.time() - 3600, time.time() + 3600
    debris = [tmp_path / ".o.csv.partial-999999999-0123abcd", tmp_path / ".r.partial-ab_12cd3"]  # file, legacy folder
    debris[0].write_bytes(b"half a file")
    debris[1].mkdir()
    (debris[1] / "report.md").write_text("half a report")
    kept = {
        tmp_path / ".o.csv.partial-1-89abcdef": old,  # its process (pid 1) is alive: a concurrent run's
        tmp_path / ".o.csv.partial-999999998-fedcba98": later,  # newer than this run
        tmp_path / ".o.csv.partial-mine": old,
        tmp_path / ".other.csv.partial-999999999-0123abcd": old,
        tmp_path / "o.csv.partial-999999999-0123abcd": old,
    }  # not the writer's names for o.csv
    for f, t in kept.items():
        f.write_bytes(b"keep")
        os.utime(f, (t, t))
    for p in debris:
        os.utime(p, (old, old))
    rc, _, err = run_cli(["simulate", "--impacts", "3", "--output", str(tmp_path / "o.csv")], capsys)
    assert rc == 0, err
    assert not debris[0].exists() and all(f.read_bytes() == b"keep" for f in kept)
    reportfake.build_fake_report(tmp_path / "r", monkeypatch)  # the report's staging folder, beside --out
    assert not debris[1].exists() and (tmp_path / "r" / "report.html").exists()
    assert sorted(p.name for p in tmp_path.iterdir() if ".partial" in p.name) == sorted(f.name for f in kept)


# ---------------------------------------------------------------------------------------- full disk
# (the fixture full_disk, a 64 KiB tmpfs, is tests/conftest.py's)


def _one_line_error(rc, err, status):
    assert rc == status, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err


def test_disk_full_is_one_line_and_the_earlier_file_stays(full_disk, capsys):
    """simulate --output on a full 64 KiB file system: one line, exit status 1, the earlier file intact and
    no temporary file left.  Before, the earlier file was truncated (and a full disk in the report was
    a 33-line traceback)."""
    target = full_disk / "o.csv"
    target.write_bytes(EARLIER)
    rc, _, err = run_cli(["simulate", "--impacts", "3000", "--output", str(target)], capsys)
    _one_line_error(rc, err, 1)
    assert "No space left on device" in err and "o.csv" in err and ".partial" not in err, err
    assert target.read_bytes() == EARLIER and _partials(full_disk) == []
    plot = full_disk / "p.png"
    rc, _, err = run_cli(["simulate", "--impacts", "3000", "--plot", str(plot)], capsys)
    _one_line_error(rc, err, 1)
    assert not plot.exists() and _partials(full_disk) == []


def test_two_outputs_go_in_together_or_not_at_all(full_disk, tmp_path, capsys):
    """simulate --output (a disk with room) --plot (a full one): the plot fails, and the data file keeps
    its earlier content (before, it had been replaced already when the plot failed)."""
    data = tmp_path / "o.csv"
    data.write_bytes(EARLIER)
    (full_disk / "filler").write_bytes(b"x" * 60_000)
    rc, _, err = run_cli(
        ["simulate", "--impacts", "2000", "--output", str(data), "--plot", str(full_disk / "p.png")], capsys
    )
    _one_line_error(rc, err, 1)
    assert "--plot" in err and data.read_bytes() == EARLIER
    assert _partials(tmp_path) == [] and not (full_disk / "p.png").exists()


def test_report_on_a_full_disk_is_one_line_and_leaves_out_as_it_was(full_disk, monkeypatch, capsys):
    reportfake = _fake_report_writing_data(monkeypatch)
    from gear_rattle.validation.report import builder

    out = full_disk / "r"
    out.mkdir()
    (out / "report.html").write_bytes(EARLIER)
    (full_disk / "filler").write_bytes(b"x" * 40_000)
    mod = reportfake.types.ModuleType("gear_rattle_test_fake_section")
    mod.KEY, mod.TITLE, mod.build = "fake", "Fake section (test)", reportfake.fake_section
    monkeypatch.setattr(builder, "section_modules", lambda: [mod])
    monkeypatch.setattr(builder, "environment", lambda: {"python": "test"})
    rc, _, err = run_cli(["report", "--out", str(out), "--quiet"], capsys)
    _one_line_error(rc, err, 1)
    assert "No space left on device" in err, err
    assert sorted(p.name for p in out.iterdir()) == ["report.html"] and (out / "report.html").read_bytes() == EARLIER


# ------------------------------------------------------------------------------- names and targets

LONG = "x" * 300


@pytest.mark.parametrize(
    "args",
    [
        ["simulate", "--impacts", "3", "--output", f"{LONG}.csv"],
        ["simulate", "--impacts", "3", "--plot", f"{LONG}/p.png"],
        ["lyapunov", "--impacts", "3", "--output", f"{LONG}.json"],
        ["timeseries", "--output", f"{LONG}.csv"],
        ["bifurcation", "--plot", f"{LONG}.png"],
        ["orbit", "find", "--output", f"{LONG}.json"],
        ["basins", "--out", LONG],
        ["transients", "--out", f"d/{LONG}"],
        ["report", "--out", LONG],
        ["check", "--self", "--out", LONG],
    ],
)
def test_a_name_too_long_is_one_line_before_computing(args, tmp_path, monkeypatch, capsys):
    """A name of 300 bytes (the file system allows 255): one line naming the option, exit status 2, before
    anything is computed.  Before: a traceback (pathlib's exists() raises ENAMETOOLONG)."""
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(args, capsys)
    _one_line_error(rc, err, 2)
    option = next(a for a in args if a.startswith("--") and a not in ("--impacts", "--self"))
    assert option in err and "bytes long" in err and "255" in err, err
    assert out == "" and os.listdir(tmp_path) == []


def test_symlink_devnull_and_new_folders(tmp_path, capsys):
    """A symbolic link is followed (the file it names is replaced, the link stays); /dev/null is written in
    place (never renamed over); a target in folders that do not exist yet has them created."""
    real = tmp_path / "real.csv"
    real.write_bytes(EARLIER)
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    rc, _, err = run_cli(["simulate", "--impacts", "3", "--output", str(link)], capsys)
    assert rc == 0, err
    assert link.is_symlink() and real.read_text().startswith("n,tau,") and _partials(tmp_path) == []
    rc, _, err = run_cli(["simulate", "--impacts", "3", "--output", "/dev/null", "--format", "csv"], capsys)
    assert rc == 0, err
    assert Path("/dev/null").is_char_device()
    rc, _, err = run_cli(["simulate", "--impacts", "3", "--output", str(tmp_path / "a" / "b" / "o.json")], capsys)
    assert rc == 0 and json.loads((tmp_path / "a" / "b" / "o.json").read_text()), err


def test_a_file_in_the_way_of_a_report_folder_is_one_line_and_nothing_moves(tmp_path, monkeypatch, capsys):
    """DIR/figures is a file of the user's: the report stops in one line before moving any file in."""
    reportfake = _fake_report_writing_data(monkeypatch)
    out = tmp_path / "r"
    out.mkdir()
    (out / "figures").write_text("not a folder")
    with pytest.raises(NotADirectoryError):
        reportfake.build_fake_report(out, monkeypatch)
    assert sorted(p.name for p in out.iterdir()) == ["figures"] and (out / "figures").read_text() == "not a folder"


def test_sigterm_ignored_from_the_start_stays_ignored(tmp_path):
    """As for SIGINT (`nohup`-like launchers start a command with SIGTERM ignored): kept ignored."""
    started_ignoring = (
        "import os, signal, sys; signal.signal(signal.SIGTERM, signal.SIG_IGN); "
        "os.execv(sys.executable, [sys.executable, '-m', 'gear_rattle', 'simulate', "
        "'--impacts', '50000', '--quiet'])"
    )
    p = subprocess.Popen(
        [sys.executable, "-c", started_ignoring], stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path, env=ENV
    )
    try:
        time.sleep(1.5)
        p.send_signal(signal.SIGTERM)
        out, err = p.communicate(timeout=300)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 0, err.decode()
    assert out.count(b"\n") == 50_002


def test_a_name_of_250_bytes_is_written_atomically(tmp_path, capsys):
    """The temporary name cuts the target's name (a 250-byte name plus the writer's suffix would pass the
    255-byte limit): such a file is written, and no temporary file stays."""
    target = tmp_path / ("y" * 246 + ".csv")
    target.write_bytes(EARLIER)
    rc, _, err = run_cli(["simulate", "--impacts", "3", "--output", str(target)], capsys)
    assert rc == 0, err
    assert target.read_text().startswith("n,tau,") and _partials(tmp_path) == []


def test_a_read_only_file_system_is_one_line_before_computing(tmp_path, capsys):
    where = tmp_path / "ro"
    where.mkdir()
    if not shutil.which("mount") or os.geteuid() != 0:
        pytest.skip("a read-only file system needs mount(8) as root")
    r = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=64k,ro", "tmpfs", str(where)], capture_output=True, text=True
    )
    if r.returncode != 0:
        pytest.skip(f"mounting a read-only tmpfs was refused: {r.stderr.strip()}")
    try:
        for args in (
            ["simulate", "--impacts", "3", "--output", str(where / "o.csv")],
            ["check", "--self", "--cases", "0001-regular-fig2", "--out", str(where / "c")],
        ):
            rc, out, err = run_cli(args, capsys)
            _one_line_error(rc, err, 2)
            assert "Read-only file system" in err and out == "", err
    finally:
        subprocess.run(["umount", str(where)], capture_output=True)


MID_COMMIT = r"""
import os, signal, sys, threading, time
from pathlib import Path
from gear_rattle.validation import interrupt
from gear_rattle.validation.io import atomic

out = Path(sys.argv[1])
slow = atomic._replace
def replace(tmp, target):  # 0.2 s per rename: the signal lands between two of them
    time.sleep(0.2)
    slow(tmp, target)
atomic._replace = replace
signal.signal(signal.SIGTERM, interrupt.exit_interrupted)
def work():
    with atomic.outputs("check", out, argv=["test"]):
        for i in range(5):
            atomic.write_text_atomic(out / f"f{i}.csv", f"new {i}\n")
        print("renaming", flush=True)
threading.Thread(target=work, daemon=True).start()
while True:
    time.sleep(0.05)
"""


def test_sigterm_between_two_renames_waits_for_the_last(tmp_path):
    """The handler takes the writer's lock: a SIGTERM sent while a command's files are being renamed in
    (each rename slowed to 0.2 s here) ends the process only after the last one, with the manifest
    complete -- never a folder that mixes two runs."""
    out = tmp_path / "c"
    out.mkdir()
    for i in range(5):
        (out / f"f{i}.csv").write_text("earlier\n")
    p = subprocess.Popen(
        [sys.executable, "-c", MID_COMMIT, str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV
    )
    try:
        assert p.stdout.readline() == b"renaming\n"
        time.sleep(0.5)  # two or three files renamed
        p.send_signal(signal.SIGTERM)
        _, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 143 and err == b"gear-rattle: terminated\n", err
    assert [(out / f"f{i}.csv").read_text() for i in range(5)] == [f"new {i}\n" for i in range(5)]
    assert atomic.read_manifest(out, "check")["complete"] is True and _partials(out) == []


def test_basins_stopped_while_plotting_leaves_every_earlier_file(tmp_path, monkeypatch, capsys):
    """basins killed mid-run left a new basins.json beside the old figure: its data files were written
    before the figure was drawn.  Now all three go in together at the end, or none (here a Ctrl-C while
    the figure is drawn; the computation is stubbed)."""
    import numpy as np

    import gear_rattle.validation.plots.transients as plots
    import gear_rattle.validation.transient.experiments as E

    class Stub:
        notes = ()

        def arrays(self):
            return {"durations": np.arange(4.0)}

        def summary(self):
            return {"stub": True}

    def interrupted(res):
        raise KeyboardInterrupt

    monkeypatch.setattr(E, "basins", lambda **kw: Stub())
    monkeypatch.setattr(plots, "basins_figure", interrupted)
    out = tmp_path / "b"
    out.mkdir()
    for name in ("basins.npz", "basins.json", "fig9_basins.png"):
        (out / name).write_bytes(EARLIER)
    rc, _, err = run_cli(["basins", "--nx", "2", "--ny", "2", "--quiet", "--out", str(out)], capsys)
    assert rc == 130 and err.strip() == "gear-rattle basins: interrupted", err
    assert {p.name: p.read_bytes() for p in out.iterdir()} == dict.fromkeys(
        ("basins.npz", "basins.json", "fig9_basins.png"), EARLIER
    )


REPORT_DRIVER = r"""
import os, sys, time, types
sys.path.insert(0, os.environ["TESTS_DIR"])
import reportfake
from gear_rattle.validation.report import builder

def section(ctx):
    sec = reportfake.fake_section(ctx)
    if os.environ.get("SLOW"):
        print("staged", flush=True)
        time.sleep(60)
    return sec

mod = types.ModuleType("fake_section_module")
mod.KEY, mod.TITLE, mod.build = "fake", "Fake section (test)", section
builder.section_modules = lambda: [mod]
builder.environment = lambda: {"python": "test"}
sys.argv = ["gear-rattle", "report", "--quiet", "--out", sys.argv[1]]
from gear_rattle.validation.cli import main
sys.exit(main())
"""


def test_report_killed_while_staged_leaves_out_as_it_was_and_no_debris(tmp_path):
    """The console script's report (a fake section that waits once its figure is staged): SIGTERM ends it
    with one line and 143, the staging folder removed, --out untouched; SIGKILL leaves the staging
    folder, which the next report into the same --out removes.  Before: SIGTERM and SIGKILL both left a
    .OUT.partial-* folder (up to 824 KB) that nothing removed."""
    out = tmp_path / "r"
    (out / "figures").mkdir(parents=True)
    (out / "figures" / "mine.png").write_bytes(b"the user's")
    (out / "report.html").write_bytes(EARLIER)
    env = dict(ENV, TESTS_DIR=str(Path(__file__).parent))

    def state():
        return sorted(
            (str(p.relative_to(tmp_path)), p.read_bytes() if p.is_file() else None) for p in tmp_path.rglob("*")
        )

    before = state()
    for sig in (signal.SIGTERM, signal.SIGKILL):
        p = subprocess.Popen(
            [sys.executable, "-c", REPORT_DRIVER, str(out)],
            env=dict(env, SLOW="1"),
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        try:
            assert p.stdout.readline() == b"staged\n"
            assert _partials(tmp_path)  # the staging folder, inside --out
            p.send_signal(sig)
            _, err = p.communicate(timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
        if sig == signal.SIGTERM:
            assert p.returncode == 143 and err == b"gear-rattle report: terminated\n", err
            assert state() == before
        else:
            assert p.returncode == -signal.SIGKILL
            assert _partials(tmp_path) and [x for x in state() if ".partial-" not in x[0]] == before
    done = subprocess.run([sys.executable, "-c", REPORT_DRIVER, str(out)], env=env, capture_output=True)
    assert done.returncode == 0, done.stderr
    assert _partials(tmp_path) == [] and (out / "figures" / "mine.png").read_bytes() == b"the user's"
    assert (out / "report.html").read_bytes() != EARLIER and (out / "figures" / "fake.png").exists()
