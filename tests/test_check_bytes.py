"""What ``gear-rattle check`` writes, byte for byte: its stdout, stderr, ``--json`` and ``--junit-xml`` on
a corpus of outputs that covers every verdict and kind of failure (passing cases; a value beyond its
tolerance in tau, tau_mod_2pi (a phase of 1e300) and sdot; a wrong n, wall and kind; missing, extra and
truncated rows; an empty output; two malformed files; a missing file; skipped cases by --exclude, --level
and --cases; expected failures (xfail, one of them malformed) and an unexpected pass (xpass); the orbit
records with a value beyond its tolerance, a malformed file, a missing key, another number of points and
a missing file; a missing output folder), compared with the files in tests/data/check_bytes/.

Those files were written by the code before the scoring moved below the command layer with typed
results (issue 39 item 2), so this test pins the reports across that redesign: the results are typed up
to every report and serialised only at the edge, the bytes are the same.  Normalised: the temporary
folder (``<TMP>``), the shipped suite's folders (``<SUITE>``, ``<ORBITS>``) and the JUnit ``time``
attributes (seconds spent scoring).  ``GEAR_RATTLE_WRITE_EXPECTED=1`` rewrites the files (only where a
report is meant to change).  No track runs."""

from __future__ import annotations

import csv
import importlib.util
import io
import json
import os
import re
from pathlib import Path

import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.paths import DEFAULT_ORBITS, DEFAULT_SUITE

EXPECTED = Path(__file__).resolve().parent / "data" / "check_bytes"
#: .ci/golden_sample.py, the light install's sample implementation: the interval midpoints of a record.
_spec = importlib.util.spec_from_file_location("golden_sample", EXPECTED.parents[2] / ".ci" / "golden_sample.py")
golden_sample = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(golden_sample)  # type: ignore[union-attr]
WRITE = os.environ.get("GEAR_RATTLE_WRITE_EXPECTED") == "1"


def _rows(case: str) -> list[list[str]]:
    return list(csv.reader((DEFAULT_SUITE / case / "expected.csv").read_text().splitlines()))


def _write(out: Path, case: str, rows: list[list[str]], end: str = "\n") -> None:
    buf = io.StringIO()
    csv.writer(buf, lineterminator=end).writerows(rows)
    (out / f"{case}.csv").write_text(buf.getvalue(), newline="")


def _shift(rows: list[list[str]], row: int, column: str, delta: float) -> None:
    j = rows[0].index(column)
    rows[row + 1][j] = repr(float(rows[row + 1][j]) + delta)


def _set(rows: list[list[str]], row: int, column: str, value: str) -> None:
    rows[row + 1][rows[0].index(column)] = value


def _first(rows: list[list[str]], kind: str) -> int:
    return next(k for k, r in enumerate(rows[1:]) if r[5] == kind)


def _case_outputs(out: Path) -> None:
    """One output file per case of the shipped suite, each with its fault (module docstring)."""
    out.mkdir()
    cases = sorted(p.name for p in DEFAULT_SUITE.iterdir() if (p / "settings.json").is_file())
    for case in cases:
        rows = _rows(case)
        key = case[:4]
        if key == "0002":
            _shift(rows, 5, "tau", 1e-6)
        elif key == "0003":
            _set(rows, 4, "n", str(int(rows[5][0]) + 1))
        elif key == "0004":
            _set(rows, 3, "wall", "0" if rows[4][3] == "-1" else "-1")
        elif key == "0005":
            del rows[6]
        elif key == "0006":
            rows.insert(8, list(rows[8]))
        elif key == "0007":
            _set(rows, _first(rows, "stick"), "kind", "release")
        elif key == "0008":
            rows = rows[:11]
        elif key == "0009":  # a second tau column
            j = rows[0].index("tau")
            rows = [rows[0] + ["tau"]] + [r + [r[j]] for r in rows[1:]]
        elif key == "0010":
            continue  # no output
        elif key == "0011":  # a first failure, then the worst one
            _shift(rows, 2, "tau", 1e-10)
            _set(rows, 3, "tau_mod_2pi", "1e300")
            _shift(rows, 6, "sdot", 1e-3)
        elif key == "0012":
            _shift(rows, 2, "tau", 1e-9)
        elif key == "0018":  # a value, then the event sequences part
            _shift(rows, 2, "tau", 1e-9)
            del rows[9]
        elif key == "0015":
            _set(rows, 2, "tau", "abc")
        elif key == "0016":
            last = rows[-1]
            rows += [[str(int(last[0]) + k), *last[1:]] for k in (1, 2, 3)]
        elif key == "0017":
            rows = [r[:6] for r in rows]
        elif key == "0019":
            rows = rows[:1]
        elif key == "0024":
            _set(rows, 1, "wall", "2")
        _write(out, case, rows, "\r\n" if key == "0020" else "\n")


def _orbit_outputs(out: Path) -> list[str]:
    """One values file per orbit record (the interval midpoints), six of them faulty; returns the ids."""
    out.mkdir()
    ids = sorted(p.stem for p in DEFAULT_ORBITS.glob("*.json"))
    for k, rid in enumerate(ids):
        d = golden_sample.record_values(DEFAULT_ORBITS / f"{rid}.json", broken=False)
        text = None
        if k == 0:
            d["points"][0]["sdot"] += 1e-3
        elif k == 1:
            text = json.dumps(d) + "}"
        elif k == 2:
            del d["multipliers"]
        elif k == 3:
            d["points"] = d["points"][:-1]
        elif k == 4:
            continue
        elif k == 6:
            d["multipliers"][0]["re"] += 0.5
        (out / f"{rid}.json").write_text(text if text is not None else json.dumps(d))
    return ids


def _normalise(text: str, tmp: Path) -> str:
    for path, name in ((tmp, "<TMP>"), (DEFAULT_SUITE, "<SUITE>"), (DEFAULT_ORBITS, "<ORBITS>")):
        text = text.replace(str(path), name)
    return re.sub(r'time="[0-9.]+"', 'time="T"', text)


def _compare(name: str, text: str, tmp: Path) -> None:
    got = _normalise(text, tmp)
    path = EXPECTED / name
    if WRITE:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(got)
    assert got == path.read_text(), f"{name} differs from {path}"


def _run(tmp: Path, capsys, name: str, argv: list[str], reports: bool = True) -> None:
    js, xml = tmp / f"{name}.json", tmp / f"{name}.xml"
    extra = ["--json", str(js), "--junit-xml", str(xml)] if reports else []
    capsys.readouterr()
    rc = main(["check", *argv, *extra])
    out = capsys.readouterr()
    _compare(f"{name}.out", f"exit status {rc}\n--- stdout\n{out.out}--- stderr\n{out.err}", tmp)
    if reports:
        _compare(f"{name}.json", js.read_text(), tmp)
        _compare(f"{name}.xml", xml.read_text(), tmp)


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("check-bytes")
    _case_outputs(tmp / "out")
    ids = _orbit_outputs(tmp / "orbits")
    (tmp / "known.txt").write_text(
        "# known failures\n0012-release-orbit-fig11  a planted tau error\n"
        "0013-lower-wall-sticking  listed, but it passes\n0024-near-miss-1e-9  a wall of 2 (malformed)\n"
    )
    (tmp / "known-orbits.txt").write_text(f"{ids[0]}  a planted sdot error\n{ids[5]}  listed, but it passes\n")
    return tmp


def test_cases_with_every_verdict(corpus, capsys):
    argv = [str(corpus / "out"), "--known-failures", str(corpus / "known.txt")]
    _run(corpus, capsys, "cases", [*argv, "--exclude", "0014-lower-wall-stuck-forever"])


def test_cases_summary_and_selections(corpus, capsys):
    _run(corpus, capsys, "summary", [str(corpus / "out"), "--summary"], reports=False)
    cases = ["0001-regular-fig2", "0002-chaotic-fig3", "0003-free-flight-start", "0004-grazing-impact"]
    _run(corpus, capsys, "selection", [str(corpus / "out"), "--level", "1", "--cases", *cases])
    _run(corpus, capsys, "json-stdout", [str(corpus / "out"), "--level", "2", "--json", "-"], reports=False)
    _run(corpus, capsys, "junit-stdout", [str(corpus / "out"), "--level", "3", "--junit-xml", "-"], reports=False)


def test_orbit_records_with_every_verdict(corpus, capsys):
    argv = ["--orbits", str(corpus / "orbits"), "--known-failures", str(corpus / "known-orbits.txt")]
    _run(corpus, capsys, "orbits", argv)
    _run(corpus, capsys, "orbits-summary", ["--orbits", str(corpus / "orbits"), "--summary"], reports=False)


def test_a_missing_output_folder(corpus, capsys):
    _run(corpus, capsys, "missing", [str(corpus / "no-such-folder")])
