"""A suite is input too (issue 38 items 1, 2, 4; issue 37 item 5): everything read from a suite, a ``--from``
file or an implementation's output folder is checked at the boundary, a suite has one writer at a time and
``case`` commits its cases with the index or nothing, and one rule holds for an output name that is a link.

* **The hostile-suite table** (:data:`HOSTILE`): a copy of shipped case 0001 (or orbit record) with one
  thing changed -- ids that are paths, escape codes, reserved names or too long; tolerances negative,
  1e308, huge, of the wrong type; counts beyond their bounds; a named pipe, a device, a link out of the
  folder, a folder where a file is -- in the suite or in the implementation's output folder.  Each is
  refused in one line naming the file (exit status 2, no escape code on the terminal, nothing written
  outside ``--out``), or handled (an ``index.json`` that is a pipe: the suite is unversioned), never
  waited on (every run under an alarm).  On the old code ``"../x"`` wrote outside ``--out`` and an empty
  folder passed, 1e308 passed anything and every pipe hung ``check``.
* ``case``: reserved ids refused before anything is written; two ``case --id X`` started together, one
  succeeds and the other exits non-zero in one line (before: both 0, one case silently replaced); a full
  disk during ``case --from`` leaves the suite as it was and the same command then succeeds (before: empty
  case folders, then "case 'c000' exists", and the message named the file ``'None'``).
* ``case --from``: the reader limits ``check`` has (a 400-digit integer, JSON nested 100 000 deep, a
  field over 128 KiB, a pipe, a device: one line, never a traceback), every bad line named with its field
  and reason, nothing written without ``--skip-bad``; a time limit for an extreme input in range.
* Links: ``report`` follows a link at an output name as every other command does (before: replaced it by
  a file), and the manifest lists a file written through a link with where it went (before: missing).
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.paths import DEFAULT_ORBITS

CASE = "0001-regular-fig2"
RECORD = "orbit-3-impact-fig2-alpha0.5-r0.9"
#: The input of a quick case (3 impacts of the Fig. 2 orbit).
ONE = ["--alpha", "0.5", "--beta", "0.1", "--gamma", "0.1", "--r", "0.9", "--tau0", "0", "--sdot0", "0.5"]
HEADER = "id,alpha,beta,gamma,r,tau0,sdot0,impacts\n"


def run_cli(args, capsys, seconds: float = 120.0):
    """``main(args)`` under an alarm (a run that waits on a pipe fails instead of hanging the tests)."""

    def ring(signum, frame):
        raise AssertionError(f"gear-rattle {' '.join(map(str, args))}: still running after {seconds} s")

    old = signal.signal(signal.SIGALRM, ring)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        rc = main([str(a) for a in args])
    except SystemExit as e:
        rc = e.code
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    out = capsys.readouterr()
    return rc, out.out, out.err


def one_line(rc, err, status) -> str:
    assert rc == status, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert "\x1b" not in err, "an escape code reached the terminal raw"
    return err


def _tree(folder: Path) -> dict:
    """``{relative path: bytes (None for a folder or a special file)}`` of everything under ``folder``."""
    out = {}
    for p in sorted(folder.rglob("*")):
        rel = p.relative_to(folder).as_posix()
        out[rel] = p.read_bytes() if p.is_file() and not p.is_symlink() else None
    return out


# ------------------------------------------------------------------------------------- the hostile suite


def _settings(case: Path, **changes) -> None:
    s = json.loads((case / "settings.json").read_text())
    for key, value in changes.items():
        d = s
        *path, last = key.split(".")
        for k in path:
            d = d[k]
        d[last] = value
    (case / "settings.json").write_text(json.dumps(s))


def _replace(path: Path, make) -> None:
    """Put something else at ``path`` (``make(path)``)."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    elif os.path.lexists(path):
        path.unlink()
    make(path)


def _id(value):
    return lambda s, o, w: _settings(s / CASE, id=value)


def _tol(value, column="tau", which="abs"):
    return lambda s, o, w: _settings(s / CASE, **{f"tolerances.{column}.{which}": value})


def _text(rel: str, text: str):
    return lambda s, o, w: (s / rel).write_text(text)


def _fifo(where: str, rel: str):
    return lambda s, o, w: _replace({"suite": s, "out": o}[where] / rel, os.mkfifo)


def _link(where: str, rel: str, target):
    """A link at ``rel`` to ``target`` (a path, or a callable of the test's folder giving one)."""

    def make(s, o, w):
        t = target(w) if callable(target) else target
        _replace({"suite": s, "out": o}[where] / rel, lambda p: p.symlink_to(t))

    return make


def _dir(where: str, rel: str):
    return lambda s, o, w: _replace({"suite": s, "out": o}[where] / rel, lambda p: p.mkdir())


def _outside(w: Path) -> Path:
    f = w / "outside.csv"
    f.write_bytes((DEFAULT_SUITE / CASE / "expected.csv").read_bytes())
    return f


def _rename_case(name: str):
    def make(s, o, w):
        (s / CASE).rename(s / name)
        _settings(s / name, id=name)

    return make


def _record(**changes):
    def make(s, o, w):
        f = s / f"{RECORD}.json"
        d = json.loads(f.read_text())
        for k, v in changes.items():
            if k.startswith("tolerances."):
                d["tolerances"][k.split(".")[1]] = v
            else:
                d[k] = v
        f.write_text(json.dumps(d))

    return make


REFUSED, HANDLED = "refused", "handled"
#: ``(label, what is read: cases or orbits, the change, expected outcome, a word of the message)``.
HOSTILE = [
    # ids (settings.json's id; the folder keeps its name unless said)
    ("id absolute", "cases", _id("/tmp/x"), REFUSED, "id="),
    ("id dot-dot", "cases", _id("../x"), REFUSED, "id='../x'"),
    ("id with a separator", "cases", _id("a/b"), REFUSED, "id="),
    ("id with a backslash", "cases", _id("a\\b"), REFUSED, "id="),
    ("id with an escape code", "cases", _id("\x1b[31mRED"), REFUSED, "\\x1b"),
    ("id index.json", "cases", _id("index.json"), REFUSED, "reserved"),
    ("id of a manifest", "cases", _id("case.manifest.json"), REFUSED, "reserved"),
    ("id of a lock", "cases", _id("suite.lock"), REFUSED, "reserved"),
    ("id CON", "cases", _id("CON"), REFUSED, "reserved"),
    ("id too long", "cases", _id("x" * 101), REFUSED, "1-100"),
    ("id empty", "cases", _id(""), REFUSED, "id="),
    ("id a number", "cases", _id(7), REFUSED, "id=7"),
    ("id not its folder's", "cases", _id("0002-chaotic-fig3"), REFUSED, "its folder"),
    ("folder with an escape code", "cases", _rename_case("\x1b[2Jx"), REFUSED, "\\x1b"),
    ("folder named index.json", "cases", _rename_case("index.json"), REFUSED, "reserved"),
    ("folder named x.lock", "cases", _rename_case("x.lock"), REFUSED, "reserved"),
    # tolerances
    ("tolerance negative", "cases", _tol(-1e-9), REFUSED, "tolerances.tau.abs"),
    ("tolerance 1e308", "cases", _tol(1e308), REFUSED, "0.0001"),
    ("tolerance 1e-3", "cases", _tol(1e-3, "sdot"), REFUSED, "tolerances.sdot.abs"),
    ("tolerance relative 1", "cases", _tol(1.0, "tau_mod_2pi", "rel"), REFUSED, "tolerances.tau_mod_2pi.rel"),
    ("tolerance a string", "cases", _tol("1e-9"), REFUSED, "tolerances.tau.abs"),
    ("tolerance true", "cases", _tol(True), REFUSED, "tolerances.tau.abs"),
    ("tolerance huge integer", "cases", _tol(10**50), REFUSED, "tolerances.tau.abs"),
    (
        "tolerance NaN",
        "cases",
        lambda s, o, w: _settings(s / CASE, **{"tolerances.tau.abs": float("nan")}),
        REFUSED,
        "NaN",
    ),
    ("tolerance 400 digits", "cases", _text(f"{CASE}/settings.json", '{"id": ' + "9" * 400 + "}"), REFUSED, "100"),
    # counts and the run of --self
    ("expected_rows 1e9", "cases", lambda s, o, w: _settings(s / CASE, expected_rows=10**9), REFUSED, "expected_rows"),
    ("n_impacts 1e12", "cases", lambda s, o, w: _settings(s / CASE, n_impacts=10**12), REFUSED, "n_impacts"),
    ("beta negative", "cases", lambda s, o, w: _settings(s / CASE, **{"params.beta": -1}), REFUSED, "beta"),
    (
        "an unknown status",
        "cases",
        lambda s, o, w: _settings(s / CASE, expected_status="x"),
        REFUSED,
        "expected_status",
    ),
    ("params a list", "cases", lambda s, o, w: _settings(s / CASE, params=[1, 2]), REFUSED, "params"),
    # file kinds in the suite
    ("expected.csv a pipe", "cases", _fifo("suite", f"{CASE}/expected.csv"), REFUSED, "named pipe"),
    ("settings.json a pipe", "cases", _fifo("suite", f"{CASE}/settings.json"), REFUSED, "named pipe"),
    ("settings.json /dev/zero", "cases", _link("suite", f"{CASE}/settings.json", "/dev/zero"), REFUSED, "outside"),
    ("expected.csv a link out", "cases", _link("suite", f"{CASE}/expected.csv", _outside), REFUSED, "outside"),
    ("expected.csv a folder", "cases", _dir("suite", f"{CASE}/expected.csv"), REFUSED, "a directory"),
    ("case folder a link out", "cases", None, REFUSED, "outside"),  # made in the test (needs the copy)
    ("index.json a pipe", "cases", _fifo("suite", "index.json"), HANDLED, "golden suite unversioned"),
    ("index.json a folder", "cases", _dir("suite", "index.json"), HANDLED, "golden suite unversioned"),
    (
        "index.json naming the suite with an escape code",
        "cases",
        _text("index.json", '{"suite": {"name": "\\u001b[2J"}}'),
        HANDLED,
        "\\x1b[2J",
    ),
    ("provenance.json a link out", "cases", _link("suite", f"{CASE}/provenance.json", _outside), REFUSED, "outside"),
    # file kinds in the implementation's output folder
    ("output a pipe", "out", _fifo("out", f"{CASE}.csv"), REFUSED, "named pipe"),
    ("output /dev/zero", "out", _link("out", f"{CASE}.csv", "/dev/zero"), REFUSED, "outside"),
    ("output a link out", "out", _link("out", f"{CASE}.csv", _outside), REFUSED, "outside"),
    ("output a folder", "out", _dir("out", f"{CASE}.csv"), REFUSED, "a directory"),
    ("output a link inside", "out", None, HANDLED, "1/1 cases pass"),  # made in the test
    # orbit records
    ("record id dot-dot", "orbits", _record(id="../x"), REFUSED, "id='../x'"),
    ("record id not its file's", "orbits", _record(id="other"), REFUSED, "its file"),
    (
        "record tolerance 1e308",
        "orbits",
        _record(**{"tolerances.multipliers": 1e308}),
        REFUSED,
        "tolerances.multipliers",
    ),
    ("record a pipe", "orbits", _fifo("suite", f"{RECORD}.json"), REFUSED, "named pipe"),
    ("record file name with a space", "orbits", lambda s, o, w: (s / "a b.json").write_text("{}"), REFUSED, "'a b'"),
]


def _hostile_setup(tmp_path: Path, label: str, part: str, change):
    suite, out = tmp_path / "suite", tmp_path / "out"
    out.mkdir()
    if part == "orbits":
        suite.mkdir()
        shutil.copy(DEFAULT_ORBITS / f"{RECORD}.json", suite)
    else:
        shutil.copytree(DEFAULT_SUITE / CASE, suite / CASE)
        shutil.copy(DEFAULT_SUITE / CASE / "expected.csv", out / f"{CASE}.csv")  # a correct implementation
    if label == "case folder a link out":
        shutil.move(str(suite / CASE), tmp_path / "elsewhere")
        (suite / CASE).symlink_to(tmp_path / "elsewhere")
    elif label == "output a link inside":
        (out / f"{CASE}.csv").rename(out / "real.csv")
        (out / f"{CASE}.csv").symlink_to("real.csv")
    elif change is not None:
        change(suite, out, tmp_path)
    return suite, out


@pytest.mark.parametrize("label, part, change, expected, word", HOSTILE, ids=[h[0] for h in HOSTILE])
def test_a_hostile_suite_is_refused_in_one_line(label, part, change, expected, word, tmp_path, capsys):
    suite, out = _hostile_setup(tmp_path, label, part, change)
    before = sorted(p.name for p in tmp_path.iterdir())
    args = ["check", str(out), "--suite", str(suite), "--quiet"]
    if part == "orbits":
        args = ["check", "--orbits", "--self", "--suite", str(suite), "--out", str(out / "self"), "--quiet"]
    rc, stdout, err = run_cli(args, capsys)
    if expected == REFUSED:
        # a bad suite is a usage error (2); a bad output file an error of its case alone (1, the others scored)
        one_line(rc, err, 1 if part == "out" else 2)
        assert word in err, err
    else:
        assert rc == 0 and "Traceback" not in err, err
        assert word in stdout or word in err, (stdout, err)
        assert "\x1b" not in stdout + err, "an escape code reached the terminal raw"
    assert sorted(p.name for p in tmp_path.iterdir()) == before, "something was written beside the folders"


def test_an_id_that_is_a_path_writes_nothing_outside_out(tmp_path, capsys):
    """The issue's case: ``"id": "../x"`` made ``check --self --out D`` write ``x.csv`` beside D (no
    manifest entry), and made ``check`` of an empty folder pass with exit status 0."""
    suite, out = tmp_path / "s", tmp_path / "w" / "D"
    (tmp_path / "w").mkdir()
    shutil.copytree(DEFAULT_SUITE / CASE, suite / CASE)
    _settings(suite / CASE, id="../x")
    rc, _, err = run_cli(["check", "--self", "--suite", suite, "--out", out, "--quiet"], capsys)
    one_line(rc, err, 2)
    assert not (tmp_path / "w" / "x.csv").exists() and not out.exists()
    (tmp_path / "w" / "x.csv").write_bytes((DEFAULT_SUITE / CASE / "expected.csv").read_bytes())
    (tmp_path / "w" / "empty").mkdir()
    rc, _, err = run_cli(["check", tmp_path / "w" / "empty", "--suite", suite, "--quiet"], capsys)
    one_line(rc, err, 2)


# ----------------------------------------------------------------------------------- case: the writer


@pytest.mark.parametrize("cid", ["index.json", "case.manifest.json", "suite.lock", "index", "NUL.csv", ".x", "a/b"])
def test_case_refuses_a_reserved_id_and_leaves_the_suite_as_it_was(cid, tmp_path, capsys):
    """``case --id index.json`` wrote the case, failed with exit status 2 and broke every later ``case``;
    ``--id case.manifest.json`` broke a suite through an empty folder.  Now refused before anything."""
    suite = tmp_path / "s"
    suite.mkdir()
    (suite / "index.json").write_text('{"suite": {"name": "mine", "version": "7"}, "cases": []}\n')
    before = _tree(suite)
    rc, _, err = run_cli(["case", *ONE, "--impacts", "3", "--id", cid, "--out", suite, "--quiet"], capsys)
    one_line(rc, err, 2)
    assert "id=" in err and _tree(suite) == before


def test_case_refuses_a_suite_whose_index_is_a_folder_or_a_link(tmp_path, capsys):
    suite = tmp_path / "s"
    (suite / "index.json").mkdir(parents=True)
    rc, _, err = run_cli(["case", *ONE, "--impacts", "3", "--id", "a", "--out", suite, "--quiet"], capsys)
    one_line(rc, err, 2)
    assert "index.json" in err and sorted(p.name for p in suite.iterdir()) == ["index.json"]
    (suite / "index.json").rmdir()
    (tmp_path / "elsewhere.json").write_text("{}")
    (suite / "index.json").symlink_to(tmp_path / "elsewhere.json")
    rc, _, err = run_cli(["case", *ONE, "--impacts", "3", "--id", "a", "--out", suite, "--quiet"], capsys)
    one_line(rc, err, 2)
    assert "link" in err and (tmp_path / "elsewhere.json").read_text() == "{}"


def test_a_second_writer_is_refused_while_the_suite_is_locked(tmp_path, capsys):
    """The atlas's lock, reused: a suite being written is refused in one line (exit status 1), never
    waited for; the lock is the suite's own file ``suite.lock``, gone after the run."""
    from gear_rattle.validation.writelock import suite_lock

    suite = tmp_path / "s"
    with suite_lock(suite, command="the other writer"):
        rc, _, err = run_cli(["case", *ONE, "--impacts", "3", "--id", "a", "--out", suite, "--quiet"], capsys)
        one_line(rc, err, 1)
        assert "in use by another writer" in err and "the other writer" in err
    assert not (suite / "a").exists()
    rc, _, err = run_cli(["case", *ONE, "--impacts", "3", "--id", "a", "--out", suite, "--quiet"], capsys)
    assert rc == 0, err
    assert sorted(p.name for p in suite.iterdir()) == ["a", "case.manifest.json", "index.json"]


def _console_case(suite: Path, alpha: str, cid: str) -> subprocess.Popen:
    args = ["case", *ONE, "--impacts", "3", "--id", cid, "--out", str(suite), "--quiet"]
    args[args.index("--alpha") + 1] = alpha
    return subprocess.Popen(
        [sys.executable, "-m", "gear_rattle", *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )


def test_two_case_runs_of_one_id_started_together_one_wins(tmp_path):
    """Two ``case --id X`` without ``--replace`` started together: exactly one exits 0, the other non-zero
    with one line, and the suite holds the winner's case.  Before: both exited 0 in 9 of 10 trials and
    one case silently replaced the other."""
    for trial in range(2):
        suite = tmp_path / f"s{trial}"
        runs = {alpha: _console_case(suite, alpha, "X") for alpha in ("0.5", "0.6")}
        done = {alpha: (p.wait(timeout=300), p.stderr.read()) for alpha, p in runs.items()}
        codes = sorted(rc for rc, _ in done.values())
        assert codes[0] == 0 and codes[1] != 0, done
        (winner,) = [a for a, (rc, _) in done.items() if rc == 0]
        (loser_err,) = [err for rc, err in done.values() if rc != 0]
        assert len(loser_err.strip().splitlines()) == 1 and "Traceback" not in loser_err, loser_err
        settings = json.loads((suite / "X" / "settings.json").read_text())
        assert settings["params"]["alpha"] == float(winner)
        assert not (suite / "suite.lock").exists()


def test_a_full_disk_during_case_from_leaves_the_suite_as_it_was(full_disk, capsys):
    """``case --from`` with 40 inputs on a full 64 KiB disk: exit status 1, one line naming a file of the
    suite (before: ``'None'``), the suite byte for byte as it was (before: empty case folders), and the
    same command on the same disk with room then succeeds (before: "case 'c000' exists")."""
    suite = full_disk / "s"
    suite.mkdir()
    (suite / "index.json").write_text('{"suite": {"name": "mine", "version": "7"}, "cases": []}\n')
    src = full_disk.parent / "in.json"
    rows = [{"id": f"c{k:03d}", "alpha": 0.5 + 0.01 * k, "beta": 0.1, "gamma": 0.1, "r": 0.9} for k in range(40)]
    src.write_text(json.dumps([{**r, "tau0": 0, "sdot0": 0.5, "impacts": 3} for r in rows]))
    before = _tree(suite)
    rc, _, err = run_cli(["case", "--from", src, "--out", suite, "--quiet"], capsys, 600)
    one_line(rc, err, 1)
    assert "No space left on device" in err and f"{suite}/" in err and "'None'" not in err and ".partial" not in err
    assert _tree(suite) == before
    subprocess.run(["mount", "-o", "remount,size=16m", str(full_disk)], check=True)
    rc, _, err = run_cli(["case", "--from", src, "--out", suite, "--quiet"], capsys, 600)
    assert rc == 0, err
    index = json.loads((suite / "index.json").read_text())
    assert [c["id"] for c in index["cases"]] == [r["id"] for r in rows] and index["suite"]["version"] == "7"


def test_a_disk_full_message_names_the_file():
    """An OSError without a file name (a write or an fsync on a full disk) named the file ``'None'``."""
    import errno

    from gear_rattle.validation.cliutil import output_fault
    from gear_rattle.validation.io.atomic import target_of

    assert "'None'" not in str(output_fault(OSError(errno.ENOSPC, "No space left on device")))
    assert target_of("S/.S.partial-12-0123abcd/c1/.settings.json.partial-12-89abcdef") == Path("S/c1/settings.json")
    assert target_of("d/.r.partial-12-0123abcd/figures/a.png") == Path("d/r/figures/a.png")


# ------------------------------------------------------------------------------------------ case --from


def _from(tmp_path: Path, name: str, text: str | bytes) -> Path:
    f = tmp_path / name
    f.write_bytes(text.encode() if isinstance(text, str) else text)
    return f


FROM_LIMITS = [
    ("a 400-digit integer", "in.json", '[{"id": "a", "impacts": ' + "9" * 400 + "}]", "longer than 100"),
    ("JSON nested 100000 deep", "in.json", "[" * 100_000 + "]" * 100_000, "nested deeper than 32"),
    ("a CSV field of 140000 characters", "in.csv", HEADER + "a," + "1" * 140_000 + ",0.1,0.1,0.9,0,0.5,3\n", "1000"),
    ("a file of 3 MiB", "in.csv", HEADER + "a,0.5,0.1,0.1,0.9,0,0.5,3\n" * 120_000, "larger than"),
    ("not UTF-8", "in.csv", b"id,alpha\n\xff\xfe\n", "not UTF-8"),
    ("an object, not a list", "in.json", '{"id": "a"}', "expected a JSON array"),
    ("an unknown column", "in.csv", HEADER.replace("\n", ",x\n") + "a,0.5,0.1,0.1,0.9,0,0.5,3,1\n", "unknown field"),
    ("a missing column", "in.csv", "id,alpha\na,0.5\n", "missing field(s) beta"),
    ("an empty file", "in.csv", "", "empty file"),
    ("2001 inputs", "in.csv", HEADER + "".join(f"c{k},0.5,0.1,0.1,0.9,0,0.5,3\n" for k in range(2001)), "at most 2000"),
]


@pytest.mark.parametrize("label, name, text, word", FROM_LIMITS, ids=[f[0] for f in FROM_LIMITS])
def test_case_from_has_the_reader_limits_of_check(label, name, text, word, tmp_path, capsys):
    """Before: a 400-digit integer, JSON nested 100 000 deep and a CSV field over 128 KiB were tracebacks."""
    src = _from(tmp_path, name, text)
    rc, _, err = run_cli(["case", "--from", src, "--out", tmp_path / "s"], capsys)
    one_line(rc, err, 2)
    assert word in err and not (tmp_path / "s").exists(), err


@pytest.mark.parametrize("kind", ["fifo", "/dev/zero", "folder"])
def test_case_from_a_pipe_a_device_or_a_folder_is_refused_at_once(kind, tmp_path, capsys):
    src = tmp_path / "in.csv"
    if kind == "fifo":
        os.mkfifo(src)
    elif kind == "folder":
        src.mkdir()
    else:
        src = Path(kind)
    t = time.monotonic()
    rc, _, err = run_cli(["case", "--from", src, "--out", tmp_path / "s"], capsys, 30)
    one_line(rc, err, 2)
    assert "not a regular file" in err and time.monotonic() - t < 20


BAD_LINES = (
    HEADER
    + "ok1,0.5,0.1,0.1,0.9,0,0.5,3\n"
    + "b2,0.5,-1,0.1,0.9,0,0.5,3\n"  # beta out of range
    + '"b3,0.5,0.1,0.1,0.9,0,0.5,3\n'  # an unclosed quote
    + "b4,0.5,0.1,0.1,0.9,0,0.5\n"  # a field missing
    + "b5,0.5,0.1,0.1,7,0,0,2.5\n"  # r, sdot0 and impacts: three fields
    + "ok1,0.6,0.1,0.1,0.9,0,0.5,3\n"  # a duplicate id
    + "OK1,0.6,0.1,0.1,0.9,0,0.5,3\n"  # one folder on a case-insensitive file system
    + "ok2,0.55,0.1,0.1,0.9,0,0.5,3\n"
)


def test_case_from_names_every_bad_line_and_writes_nothing(tmp_path, capsys):
    """Before, ``case --from`` stopped at the first bad line (an unclosed quote read "1 fields, expected 8").
    Now every bad line is named with its field and reason, and nothing is written."""
    src = _from(tmp_path, "in.csv", BAD_LINES)
    rc, _, err = run_cli(["case", "--from", src, "--out", tmp_path / "s"], capsys)
    assert rc == 2 and "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 7, err  # six bad lines, then the summary
    for line, words in zip(
        lines,
        [
            ("line 3", "field beta"),
            ("line 4", "quoted field without its closing quote"),
            ("line 5", "7 fields, expected 8"),
            ("line 6", "field r", "field sdot0", "field impacts"),
            ("line 7", "field id", "duplicate id 'ok1' (also line 2)"),
            ("line 8", "field id", "only in case"),
        ],
    ):
        assert all(w in line for w in words), (line, words)
    assert "6 bad inputs of 8" in lines[-1] and "--skip-bad" in lines[-1] and "nothing written" in lines[-1]
    assert not (tmp_path / "s").exists()


def test_case_from_skip_bad_builds_the_good_inputs(tmp_path, capsys):
    src = _from(tmp_path, "in.csv", BAD_LINES)
    rc, _, err = run_cli(["case", "--from", src, "--out", tmp_path / "s", "--skip-bad", "--quiet"], capsys)
    assert rc == 1, err
    assert sum("skipped: line" in line for line in err.splitlines()) == 6
    assert sorted(p.name for p in (tmp_path / "s").iterdir() if p.is_dir()) == ["ok1", "ok2"]


def test_case_from_names_the_first_20_bad_lines_and_counts_the_others(tmp_path, capsys):
    src = _from(tmp_path, "in.csv", HEADER + "".join(f"c{k},0.5,0.1,0.1,1.5,0,0.5,3\n" for k in range(30)))
    rc, _, err = run_cli(["case", "--from", src, "--out", tmp_path / "s"], capsys)
    assert rc == 2
    lines = err.strip().splitlines()
    assert len(lines) == 21 and "10 more not shown" in lines[-1] and "30 bad inputs of 30" in lines[-1], err


def test_a_single_bad_line_is_one_line(tmp_path, capsys):
    src = _from(tmp_path, "in.json", '[{"id": "a", "alpha": 0.5, "beta": 0.1, "gamma": 0.1, "r": 0.9, "tau0": 0}]')
    rc, _, err = run_cli(["case", "--from", src, "--out", tmp_path / "s"], capsys)
    one_line(rc, err, 2)
    assert "entry 0 (line 1)" in err and "field sdot0: missing" in err and "field impacts: missing" in err


def test_an_extreme_input_in_range_is_bounded_in_time(tmp_path, capsys):
    """100 000 impacts of a regular orbit (in range) took about an hour; ``--time-limit`` bounds a case:
    it stops at the last impact certified in time and says so."""
    t = time.monotonic()
    args = ["case", *ONE, "--impacts", "100000", "--id", "long", "--out", tmp_path / "s", "--time-limit", "2"]
    rc, _, err = run_cli([*args, "--quiet"], capsys, 300)
    assert rc == 0 and "time limit of 2 s" in err, err
    assert time.monotonic() - t < 120
    s = json.loads((tmp_path / "s" / "long" / "settings.json").read_text())
    assert 0 < s["n_impacts"] < 100_000 and "time limit" in s["notes"]["truncation"]["reason"]


def test_a_case_stops_within_the_rows_check_reads(monkeypatch):
    """A case has at most MAX_CASE_ROWS rows (check reads at most 20000 lines and 2 MiB: a case of 100 000
    impacts would have been unreadable)."""
    from gear_rattle.validation.golden.oracle import ondemand
    from gear_rattle.validation.golden.oracle.inputs import case_input

    monkeypatch.setattr(ondemand, "MAX_CASE_ROWS", 10)
    inp = case_input("rows", 0.5, 0.1, 0.1, 0.9, 0.0, 0.5, 30)
    case = ondemand.build_user_case(inp)
    assert len(case.expected.strip().splitlines()) - 1 <= 10
    assert "more than 10 rows" in case.truncation["reason"]


# ------------------------------------------------------------------------------------------------ links


def test_report_follows_a_link_and_its_manifest_says_where_the_file_went(tmp_path, monkeypatch):
    """The one rule: an output name that is a link is followed (the file it names is replaced, the link
    stays) by every command.  ``report`` replaced the link by a file; the manifest lists the name and
    ``written_to``."""
    import reportfake

    from gear_rattle.validation.io import atomic

    out, elsewhere = tmp_path / "r", tmp_path / "kept" / "fake.png"
    (out / "figures").mkdir(parents=True)
    elsewhere.parent.mkdir()
    elsewhere.write_bytes(b"an earlier figure")
    (out / "figures" / "fake.png").symlink_to(elsewhere)
    reportfake.build_fake_report(out, monkeypatch)
    assert (out / "figures" / "fake.png").is_symlink() and elsewhere.read_bytes().startswith(b"\x89PNG")
    entry = atomic.read_manifest(out, "report")["files"]["figures/fake.png"]
    assert entry["written_to"] == os.path.realpath(elsewhere) and entry["bytes"] == elsewhere.stat().st_size
    assert "written_to" not in atomic.read_manifest(out, "report")["files"]["report.html"]


def test_a_file_written_through_a_link_in_out_is_in_the_manifest(tmp_path, capsys):
    out = tmp_path / "D"
    out.mkdir()
    (tmp_path / "outside.csv").write_text("earlier\n")
    (out / f"{CASE}.csv").symlink_to(tmp_path / "outside.csv")
    rc, _, err = run_cli(["check", "--self", "--cases", CASE, "--out", out, "--quiet", "--summary"], capsys)
    assert rc == 0, err
    assert (out / f"{CASE}.csv").is_symlink() and (tmp_path / "outside.csv").read_text().startswith("n,tau,")
    files = json.loads((out / "check.manifest.json").read_text())["files"]
    assert files[f"{CASE}.csv"]["written_to"] == os.path.realpath(tmp_path / "outside.csv")


# ------------------------------------------------------------------------------------ result types


def test_result_types_refuse_what_no_computation_returns():
    """Result types accepted anything and said ``ok=True``; a status no computation gives, or arrays of
    disagreeing shapes, are a ValueError naming the argument."""
    import numpy as np

    from gear_rattle.core.params import Params
    from gear_rattle.mapimpl.lyapunov import LyapunovResult
    from gear_rattle.mapimpl.periodic import PeriodicOrbit

    P = Params(0.5, 0.1, 0.1, 0.9)
    good = dict(
        params=P,
        period=2,
        turns=1,
        theta=np.zeros(2),
        sdot=np.ones(2),
        walls=np.zeros(2, int),
        multipliers=np.zeros(2),
        monodromy=np.eye(2),
        residual=0.0,
        status="converged",
        iterations=3,
    )
    assert PeriodicOrbit(**good).ok
    for change, word in [(dict(status="active"), "status"), (dict(period=3), "theta"), (dict(period=0), "period")]:
        with pytest.raises(ValueError, match=word):
            PeriodicOrbit(**{**good, **change})
    lyap = dict(
        param="r",
        values=np.ones(2),
        lam=np.zeros((2, 2)),
        lam_free=np.zeros((2, 2)),
        det_mean=np.zeros(2),
        n_stuck=np.zeros(2, int),
        n_steps=10,
        status=np.zeros(2, np.int32),
    )
    assert LyapunovResult(**lyap).ok
    for change, word in [(dict(status=np.full(2, 99)), "status"), (dict(lam=np.zeros((3, 2))), "lam")]:
        with pytest.raises(ValueError, match=word):
            LyapunovResult(**{**lyap, **change})
    with pytest.raises(ValueError, match="status"):
        LyapunovResult(**{**lyap, "status": np.zeros(2)})  # codes are integers
