"""``gear-rattle fuzz``: triage and ownership (issue 37 item 4, issue 38 item 3; docs/reference/golden_commands.md, "Fuzzing an
implementation").

Failures grouped by signature, one folder per group with its shrunk member, its count and the files the
implementation left (output, stdout, stderr, exit status); a crash, a timeout, a missing, malformed or
non-regular output of one input is a failure of that input, isolated from its batch and shrunk; the
implementation's process group killed on SIGTERM and SIGKILL, its work folder removed; Hypothesis's files
out of the current directory; nothing found lost on a full disk.  The implementations are the fast
``tests/copy_impl.py`` (the certified reference with one planted defect; no JAX) and, in the slow test, a
mutant of tests/golden_mutants.py with a planted crash.
"""

from __future__ import annotations

import contextlib
import json
import os
import shlex
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.oracle.inputs import case_input
from gear_rattle.validation.golden.oracle.ondemand import build_user_case, write_user_case
from gear_rattle.validation.golden.formats.cases import load_case, load_suite, read_sequence
from gear_rattle.validation.golden.scoring.cases import score_sequence

HERE = Path(__file__).resolve().parent
PY = shlex.quote(sys.executable)
#: The prefix of a fuzz run's work folder in the temporary directory (fuzz_process.WORK_PREFIX).
WORK_PREFIX = "gear-rattle-fuzz-"


def copy_impl(defect: str) -> str:
    return f"{PY} {shlex.quote(str(HERE / 'copy_impl.py'))} {defect}"


@pytest.fixture
def tmpdir_here(tmp_path, monkeypatch):
    """The temporary directory (where the fuzzer makes its work folder) inside the test's folder."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp))
    monkeypatch.setenv("TMPDIR", str(tmp))
    return tmp


class Late(BaseException):
    """A test's time is up (a BaseException: no handler of the command line turns it into an exit status)."""


@pytest.fixture(scope="module", autouse=True)
def warm(tmp_path_factory):
    """The first draw and the first case of a process take seconds (Hypothesis reads the package's sources,
    the certifier starts): done once here, so that each test's --budget is spent on its own search."""
    from gear_rattle.validation.golden.fuzzing.scenarios import construct, draw_recipes

    try:
        from gear_rattle.validation.golden.fuzzing.runner import hypothesis_home
    except ImportError:  # the code before the fuzzer's runner module (a test run on it fails its own way)
        hypothesis_home = lambda path: contextlib.nullcontext()  # noqa: E731
    with hypothesis_home(tmp_path_factory.mktemp("hypothesis")):
        recipe = draw_recipes(0, 1, ["generic"])[0]
    build_user_case(construct(recipe, "warm"))


@contextlib.contextmanager
def at_most(seconds: int):
    """Fail (rather than hang) when the block takes longer than ``seconds`` (SIGALRM: an open() of a named
    pipe is interrupted)."""

    def late(signum, frame):
        raise Late(f"still running after {seconds} s")

    old = signal.signal(signal.SIGALRM, late)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def run_fuzz(args: list[str], capsys) -> tuple[int, dict, str]:
    capsys.readouterr()
    rc = main(["fuzz", "--quiet", "--scenarios", "generic", *args])
    cap = capsys.readouterr()
    return rc, json.loads(cap.out), cap.err


def folders(out: Path) -> list[str]:
    return sorted(p.name for p in out.iterdir() if p.is_dir())


# ---------------------------------------------------------------------------------------------
# triage


def test_a_crash_on_one_input_is_isolated_shrunk_and_kept(tmp_path, tmpdir_here, capsys):
    """An implementation that panics (exit 101) on the first case with alpha > 2 of its batch: the crash is
    pinned on that input (its batch run again in halves), shrunk to the simplest input that crashes the same
    way (no impact after impact 0, alpha a one-digit number above 2) and written like any other failure, with
    the implementation's stderr, stdout and exit status of that input run alone; the messages name the kept
    files.  Before: exit status 2, "the implementation exited with status 101 on 6 cases", nothing kept."""
    out = tmp_path / "found"
    with at_most(240):
        rc, s, err = run_fuzz(
            ["--impl", copy_impl("crash-alpha-2"), "--budget", "10", "--batch", "6", "--out", str(out)], capsys
        )
    assert rc == 1 and s["status"] == "failures" and s["error"] is None, err
    [g] = s["groups"]
    assert g["signature"]["kind"] == "crash" and g["signature"]["detail"] == "exit 101"
    assert g["id"] == "fuzz-0-01-crash-exit-101" and folders(out) == [g["id"]]
    assert g["original_input"]["alpha"] > 2 and g["input"]["alpha"] > 2
    assert g["shrunk"] and g["impacts"] == 0 < g["original_input"]["impacts"], g
    assert g["run"] == {**g["run"], "exit_status": 101, "alone": True, "cases_in_run": 1}
    kept = out / g["id"] / "fuzz"
    assert "panicked at 'alpha" in (kept / "stderr.txt").read_text()
    assert g["kept"]["stderr"] == str(kept / "stderr.txt") and g["kept"]["output"] is None
    assert "exited with status 101 on this case alone" in g["message"] and str(kept / "stderr.txt") in g["message"]
    assert json.loads((kept / "group.json").read_text())["count"] == g["count"] >= 1
    case = load_case(out / g["id"])
    assert case.settings["notes"]["fuzz"]["signature"]["kind"] == "crash" and case.settings["n_impacts"] == 0
    assert [c.id for c in load_suite(out)] == [g["id"]]
    assert "gear-rattle-fuzz-" not in json.dumps(s) and "OUT_DIR" not in json.dumps(s)
    assert list(tmpdir_here.iterdir()) == []


def test_progress_says_when_a_group_is_being_shrunk(tmp_path, tmpdir_here):
    """Shrinking a group takes up to a minute and a half with no new case counted: the progress callback
    hears it before it starts (``shrinking <signature>``), with the cases counted so far, and a later
    report drops the note.  Before: the bar stood at "0 cases" for the whole shrink of the first batch's
    crash (89 s, seen on a terminal)."""
    from gear_rattle.validation.golden.fuzzing.runner import fuzz

    calls = []
    with at_most(240):
        res = fuzz(
            shlex.split(copy_impl("crash-alpha-2")),
            budget=6,
            batch=6,
            scenarios=["generic"],
            progress=lambda *a: calls.append(a),
        )
    assert res.groups, calls
    shrinking = [c for c in calls if len(c) == 3 and c[2]]
    assert shrinking and shrinking[0] == (shrinking[0][0], 1, "shrinking crash (exit 101)"), calls
    assert shrinking[0][0] >= 1  # the batch that found it is counted before its shrink
    assert len(calls[-1]) == 2 or not calls[-1][2], calls


def test_one_defect_failing_many_inputs_is_one_group_with_json_and_junit(tmp_path, tmpdir_here, capsys):
    """--keep-going with an implementation whose every impact's sdot is off by 1e-6 relative: every input
    with an impact after impact 0 fails, all with the same signature, from three scenarios -- one group (one
    folder), its count the number of failing inputs, counted per scenario; its kept output fails the kept
    case under `check`; --json FILE holds the summary printed on stdout, --junit-xml FILE one failing
    testcase for the group.  Before: one folder per failing input (7 in the issue's run), no --json FILE or
    --junit-xml."""
    out, js, junit = tmp_path / "found", tmp_path / "s.json", tmp_path / "j.xml"
    args = ["--impl", copy_impl("sdot-off"), "--budget", "8", "--batch", "6", "--keep-going", "--out", str(out)]
    args += ["--scenarios", "generic", "paper", "free-flight"]
    rc, s, _ = run_fuzz([*args, "--json", str(js), "--junit-xml", str(junit)], capsys)
    assert rc == 1 and s["failed_inputs"] >= 3, s
    [g] = s["groups"]
    assert g["signature"] == {**g["signature"], "kind": "value", "column": "sdot", "row": "impact"}
    assert g["count"] == s["failed_inputs"] == sum(g["scenarios"].values()) and len(g["scenarios"]) >= 2
    assert len(g["members"]) == min(g["count"], 50) and g["id"] == "fuzz-0-01-value-sdot-impact"
    assert folders(out) == [g["id"]] and g["impacts"] <= g["original_input"]["impacts"]
    assert json.loads(js.read_text()) == s
    manifest = json.loads((out / "fuzz.manifest.json").read_text())
    assert manifest["complete"] and {"index.json", f"{g['id']}/settings.json", f"{g['id']}/fuzz/group.json"} <= set(
        manifest["files"]
    )
    root = ET.parse(junit).getroot()
    [case] = root.iter("testcase")
    failure = case.find("failure")
    assert case.get("name") == g["id"] and failure is not None and failure.get("type") == "fuzz.value"
    assert f"{g['count']} input(s) failed" in failure.get("message") and root.get("failures") == "1"
    # the kept output, as the implementation wrote it for the shrunk case, fails that case
    kept = Path(g["kept"]["output"])
    assert g["message"].endswith(f"of {kept}") and kept.is_file()
    (tmp_path / "impl").mkdir()
    (tmp_path / "impl" / f"{g['id']}.csv").write_bytes(kept.read_bytes())
    assert main(["check", str(tmp_path / "impl"), "--suite", str(out), "--summary"]) == 1


def test_two_defects_are_two_groups(tmp_path, tmpdir_here, capsys):
    """An implementation with two defects -- a panic where alpha > 2 and sdot off everywhere else: two
    groups, a crash and a value of sdot, each with its own count, folder and kept files."""
    out = tmp_path / "found"
    args = ["--impl", copy_impl("crash-alpha-2+sdot-off"), "--budget", "6", "--batch", "6", "--keep-going"]
    rc, s, _ = run_fuzz([*args, "--out", str(out)], capsys)
    assert rc == 1 and sorted(g["signature"]["kind"] for g in s["groups"]) == ["crash", "value"], s["groups"]
    assert sum(g["count"] for g in s["groups"]) == s["failed_inputs"] and folders(out) == sorted(
        g["id"] for g in s["groups"]
    )
    crash = next(g for g in s["groups"] if g["signature"]["kind"] == "crash")
    assert crash["input"]["alpha"] > 2 and "panicked" in Path(crash["kept"]["stderr"]).read_text()


def test_a_clean_run_and_an_implementation_that_cannot_start(tmp_path, tmpdir_here, capsys, monkeypatch):
    """A correct implementation: exit 0, no group, one passing JUnit testcase, nothing of Hypothesis's in the
    current directory (--hypothesis-dir names where it goes).  A command that does not exist: exit 2 and
    one line (the only implementation fault that stops the run)."""
    junit = tmp_path / "j.xml"
    monkeypatch.chdir(tmp_path)
    rc, s, _ = run_fuzz(
        [
            "--impl",
            copy_impl("right"),
            "--budget",
            "5",
            "--batch",
            "2",
            "--out",
            str(tmp_path / "f"),
            "--junit-xml",
            str(junit),
            "--hypothesis-dir",
            str(tmp_path / "hyp"),
        ],
        capsys,
    )
    assert rc == 0 and s["status"] == "clean" and s["groups"] == [] and s["cases"] > 0
    assert not (tmp_path / ".hypothesis").exists()
    [case] = ET.parse(junit).getroot().iter("testcase")
    assert case.get("name") == "search" and case.find("failure") is None and not (tmp_path / "f").exists()
    rc, s, err = run_fuzz(
        ["--impl", str(tmp_path / "no-such-program"), "--budget", "3", "--batch", "2", "--out", str(tmp_path / "f")],
        capsys,
    )
    assert rc == 2 and s["status"] == "error" and "cannot start the implementation" in err
    assert len(err.strip().splitlines()) == 1
    assert list(tmpdir_here.iterdir()) == []


@pytest.mark.parametrize(
    "script, kind",
    [
        ("exit 3", "crash"),
        ('sleep 30 & echo $! >> "$FUZZ_TEST_PIDS"; wait', "timeout"),  # a grandchild that outlives the timeout
        (":", "missing output"),  # writes nothing
    ],
)
def test_a_broken_implementation_is_a_triaged_failure(script, kind, tmp_path, tmpdir_here, capsys, monkeypatch):
    """A crash, a timeout or a missing file on every input: a group of that kind (exit status 1, the run went
    on), no longer an error that ends the run (exit 2 before; a malformed file: the named-pipe test).  The
    timeout kills the implementation's grandchildren too."""
    pids = tmp_path / "pids"
    monkeypatch.setenv("FUZZ_TEST_PIDS", str(pids))
    impl = f"sh -c {shlex.quote(script)} sh"
    args = ["--impl", impl, "--budget", "4", "--timeout", "1", "--batch", "2", "--out", str(tmp_path / "f")]
    with at_most(120):
        rc, s, err = run_fuzz(args, capsys)
    assert rc == 1 and s["status"] == "failures" and err.strip() == "", err
    assert [g["signature"]["kind"] for g in s["groups"]] == [kind]
    assert list(tmpdir_here.iterdir()) == []
    started = [int(p) for p in pids.read_text().split()] if pids.exists() else []
    assert (kind != "timeout" or started) and not any(_alive(p) for p in started)


def test_a_named_pipe_as_output_is_malformed_not_waited_on(tmp_path, tmpdir_here, capsys):
    """An implementation that makes <id>.csv a named pipe (for alpha > 2) and writes nothing into it: a
    malformed output of that input (not a regular file), found within the budget.  Before: fuzz waited for a
    writer for ever."""
    t0 = time.monotonic()
    with at_most(120):
        rc, s, _ = run_fuzz(
            ["--impl", copy_impl("fifo-alpha-2"), "--budget", "8", "--batch", "6", "--out", str(tmp_path / "f")], capsys
        )
    assert rc == 1 and time.monotonic() - t0 < 60
    [g] = s["groups"]
    assert g["signature"]["kind"] == "malformed" and "a named pipe, not a regular file" in g["message"]
    assert g["input"]["alpha"] > 2 and g["kept"]["output"] is None


def test_the_shrinker_aims_at_the_scores_row_with_blank_lines(tmp_path):
    """An output with blank lines between its rows, one row short, whose row 3 has the wrong wall: the first
    failing impact is that of the expected row at the score's ``first_row`` (impact 3).  Before, it was read
    from the message's line number minus 2: line 8 (blank lines count), so impact 6."""
    from gear_rattle.validation.golden.fuzzing.shrinker import first_failing_impact

    case = build_user_case(case_input("c", 0.5, 0.1, 0.1, 0.9, 0.0, 0.5, 6))
    folder = write_user_case(tmp_path / "s", case)
    header, *rows = case.expected.splitlines()
    f = rows[3].split(",")
    f[3] = "0" if f[3] == "-1" else "-1"
    rows[3] = ",".join(f)
    (tmp_path / "c.csv").write_text("\n".join([header, *[x for r in rows[:-1] for x in (r, "")]]) + "\n")
    score = score_sequence(load_case(folder), read_sequence(tmp_path / "c.csv"))
    assert not score.passed and score.first_row == 3
    assert first_failing_impact(case, score) == 3


def test_signatures_come_from_the_scores_fields(tmp_path):
    """The signature of a failing output: a value beyond its tolerance, a wrong wall with as many events, a
    missing last event, a wrong wall with an event missing further on -- each with the kind of the golden
    row at the first difference."""
    from gear_rattle.validation.golden.fuzzing.triage import Signature, score_signature

    case = build_user_case(case_input("c", 0.5, 0.1, 0.1, 0.9, 0.0, 0.5, 6))
    ref = load_case(write_user_case(tmp_path / "s", case))
    header, *rows = case.expected.splitlines()

    def edited(row: int | None, field: int, value, drop_last: bool) -> Signature:
        out = list(rows[:-1] if drop_last else rows)
        if row is not None:
            f = out[row].split(",")
            f[field] = value(f[field])
            out[row] = ",".join(f)
        (tmp_path / "c.csv").write_text("\n".join([header, *out]) + "\n")
        got = read_sequence(tmp_path / "c.csv")
        return score_signature(score_sequence(ref, got), got, ref.expected)

    flip = lambda w: "0" if w == "-1" else "-1"  # noqa: E731
    assert edited(2, 4, lambda v: repr(float(v) * (1 + 1e-6)), False) == Signature("value", "sdot", row="impact")
    assert edited(3, 3, flip, False) == Signature("wall", row="impact")
    assert edited(None, 0, str, True) == Signature("row count", "missing rows", row="impact")
    assert edited(3, 3, flip, True) == Signature("row count", "wall", row="impact")


# ---------------------------------------------------------------------------------------------
# what is written, and when


def test_a_group_is_written_before_it_is_shrunk(tmp_path, tmpdir_here, capsys, monkeypatch):
    """The first failing input of a group is in --out, with its kept files, before the shrinker runs: a
    Ctrl-C while shrinking leaves it whole (a golden-format case and its group.json), and the work folder
    (there while it ran) is removed."""
    from gear_rattle.validation.golden.fuzzing import runner

    def interrupted(*a, **k):
        work.extend(p.name for p in tmpdir_here.iterdir())
        raise KeyboardInterrupt

    work: list[str] = []

    monkeypatch.setattr(runner, "shrink", interrupted)
    out = tmp_path / "found"
    capsys.readouterr()
    rc = main(
        [
            "fuzz",
            "--quiet",
            "--scenarios",
            "generic",
            "--impl",
            copy_impl("sdot-off"),
            "--budget",
            "5",
            "--batch",
            "4",
            "--out",
            str(out),
        ]
    )
    assert rc == 130
    [name] = folders(out)
    g = json.loads((out / name / "fuzz" / "group.json").read_text())
    assert g["shrunk"] is False and g["count"] == 1 and g["kept"]["output"].endswith("output.csv")
    assert load_case(out / name).settings["notes"]["fuzz"]["original_input"] == g["original_input"]
    assert (out / name / "fuzz" / "output.csv").is_file()
    assert len(work) == 1 and work[0].startswith(WORK_PREFIX) and list(tmpdir_here.iterdir()) == []


def test_disk_full_keeps_what_was_found_and_says_what_was_not_written(full_disk, tmp_path, tmpdir_here, capsys):
    """--out on a full file system: exit status 1, one line naming the file that could not be written, the
    JSON summary on stdout with the failure's input (nothing found is lost), no empty or partial folder.
    Before: an empty fuzz-0-000001/, no JSON summary."""
    (full_disk / "filler").write_bytes(b"x" * 60_000)
    out = full_disk / "found"
    rc, s, err = run_fuzz(["--impl", copy_impl("sdot-off"), "--budget", "5", "--batch", "4", "--out", str(out)], capsys)
    assert rc == 1 and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert "No space left on device" in err and str(out) in err and ".partial" not in err
    [g] = s["groups"]
    assert g["unwritten"] and s["unwritten"] and g["input"]["impacts"] >= 0 and g["original_input"]
    assert not out.exists()
    assert [p for p in full_disk.rglob("*") if ".partial-" in p.name] == []


# ---------------------------------------------------------------------------------------------
# what fuzz starts, it ends


def _alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie waiting for its parent counts as ended)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _start_fuzz(tmp_path: Path, extra: list[str] = ()) -> tuple[subprocess.Popen, list[int], Path]:
    """`python -m gear_rattle fuzz` (the console script's signal handling) with the implementation that
    starts a grandchild and sleeps, in ``tmp_path/cwd`` with TMPDIR ``tmp_path/tmp``; returns the process and
    the pids of the implementation and its grandchild once both run."""
    tmp, cwd, pids = tmp_path / "tmp", tmp_path / "cwd", tmp_path / "pids"
    for d in (tmp, cwd):
        d.mkdir(exist_ok=True)
    env = {**os.environ, "TMPDIR": str(tmp), "COPY_IMPL_PIDS": str(pids)}
    cmd = [sys.executable, "-m", "gear_rattle", "fuzz", "--quiet", "--scenarios", "generic", "--batch", "1"]
    proc = subprocess.Popen(
        [*cmd, "--impl", copy_impl("grandchild"), "--budget", "300", "--out", str(tmp_path / "f"), *extra],
        cwd=cwd,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    end = time.monotonic() + 120
    while not (pids.is_file() and len(pids.read_text().split()) == 2):
        assert proc.poll() is None and time.monotonic() < end, proc.communicate()
        time.sleep(0.05)
    started = [int(p) for p in pids.read_text().split()]
    assert all(_alive(p) for p in started) and [p.name for p in tmp.iterdir()][0].startswith(WORK_PREFIX)
    return proc, started, tmp


def _gone(pids: list[int], tmp: Path, within: float) -> bool:
    end = time.monotonic() + within
    while time.monotonic() < end:
        if not any(_alive(p) for p in pids) and not list(tmp.iterdir()):
            return True
        time.sleep(0.05)
    return False


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")
def test_sigterm_ends_the_implementation_and_its_grandchild_and_removes_the_work_folder(tmp_path):
    """SIGTERM of `fuzz` while its implementation runs, with a grandchild: exit status 143 and one line; the
    implementation and the grandchild are gone, the work folder too; no .hypothesis/ in the current
    directory.  Before: both kept running (a `sleep 300` left), the work folder stayed, and .hypothesis/
    was written into the current directory."""
    proc, pids, tmp = _start_fuzz(tmp_path)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143 and err.decode().strip() == "gear-rattle fuzz: terminated"
    assert _gone(pids, tmp, 5.0), ([_alive(p) for p in pids], list(tmp.iterdir()))
    assert not (tmp_path / "cwd" / ".hypothesis").exists()


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")
def test_sigkill_leaves_nothing_running_and_no_work_folder(tmp_path):
    """SIGKILL of `fuzz` (it runs no code): its watchdog kills the implementation's group and the grandchild
    and removes the work folder.  Before: both kept running, the work folder stayed."""
    proc, pids, tmp = _start_fuzz(tmp_path)
    proc.kill()
    proc.communicate(timeout=60)
    assert _gone(pids, tmp, 10.0), ([_alive(p) for p in pids], list(tmp.iterdir()))
    assert not (tmp_path / "cwd" / ".hypothesis").exists()


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")
def test_the_next_run_removes_a_dead_runs_work_folder_and_its_processes(tmp_path, tmpdir_here, capsys):
    """A work folder whose lock nobody holds (its run and its watchdog were killed) and a process of that run
    still alive, in a session of its own: the next run kills the process and removes the folder; a folder
    whose lock is held (a live run) and another user's file of the same prefix stay."""
    import fcntl

    from gear_rattle.validation.golden.fuzzing import reaper
    from gear_rattle.validation.golden.fuzzing.process import LOCK_NAME

    dead, live = tmpdir_here / f"{WORK_PREFIX}dead", tmpdir_here / f"{WORK_PREFIX}live"
    for d in (dead, live):
        d.mkdir()
        (d / LOCK_NAME).write_text("{}\n")
    fd = os.open(live / LOCK_NAME, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)
    orphan = subprocess.Popen(["sleep", "300"], start_new_session=True, env={**os.environ, reaper.MARKER: str(dead)})
    try:
        assert _alive(orphan.pid)
        rc, _, _ = run_fuzz(
            ["--impl", copy_impl("right"), "--budget", "1", "--batch", "1", "--out", str(tmp_path / "f")], capsys
        )
        assert rc == 0
        orphan.wait(10)
        assert sorted(p.name for p in tmpdir_here.iterdir()) == [live.name]
    finally:
        orphan.kill()
        os.close(fd)


def test_the_watchdog_kills_what_it_was_told_of_when_its_input_ends(tmp_path):
    """The reaper (fuzzing/reaper.py) as the fuzzer starts it: given a process group on its input, it kills the group (a
    shell and its child) and removes the work folder as soon as its input ends."""
    from gear_rattle.validation.golden.fuzzing import reaper

    work = tmp_path / "work"
    work.mkdir()
    group = subprocess.Popen(["sh", "-c", "sleep 300 & sleep 300"], start_new_session=True)
    dog = subprocess.Popen(
        [sys.executable, "-I", "-S", reaper.__file__, str(work)], stdin=subprocess.PIPE, start_new_session=True
    )
    try:
        dog.stdin.write(f"+{group.pid}\n".encode())
        dog.stdin.close()
        assert dog.wait(30) == 0 and group.wait(10) == -signal.SIGKILL
        assert reaper.group_members(group.pid) == [] and not work.exists()
    finally:
        group.kill()
        dog.kill()


# ---------------------------------------------------------------------------------------------
# slow: a real mutant with a planted crash


@pytest.mark.slow
def test_a_mutant_with_a_planted_crash_gives_two_groups(tmp_path, capsys):
    """The mutant without sticking on s = -1, crashing (exit 101) where alpha > 2, fuzzed on lower-wall
    chatter with --keep-going: the crash is one group and the mutant's own defect another, each shrunk and
    kept; the kept crash case crashes the mutant and our map track passes both."""
    impl = f"{PY} {shlex.quote(str(HERE / 'mutant_impl.py'))} no-lower-wall-sticking+crash-alpha-2"
    out = tmp_path / "found"
    args = ["--impl", impl, "--budget", "120", "--batch", "8", "--keep-going", "--scenarios", "chatter-lower"]
    rc, s, _ = run_fuzz([*args, "--out", str(out)], capsys)
    kinds = {g["signature"]["kind"] for g in s["groups"]}
    assert rc == 1 and "crash" in kinds and len(kinds) >= 2, s
    assert folders(out) == sorted(g["id"] for g in s["groups"])
    assert main(["check", "--self", "--suite", str(out), "--summary"]) == 0
