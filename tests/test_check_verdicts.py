"""An honest per-case verdict (issue 37 item 2) and the suite within reach (item 3): cases not selected
are <skipped> with the reason, known failures are expected failures (one that passes fails the run),
XML booleans are true/false, a missing output folder still gives the reports, --require-suite takes
ranges; --suite-version --json and --export-suite give the suite's folders and a copy of it.

No version is hard-coded: the ranges are built from the shipped suite's own version.  No track runs."""

from __future__ import annotations

import importlib.util
import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.formats import version as V
from gear_rattle.validation.golden.paths import GOLDEN

REPO = Path(__file__).resolve().parents[1]
CASES = sorted(p.name for p in (GOLDEN / "cases").iterdir() if (p / "settings.json").is_file())
RECORDS = sorted(p.stem for p in (GOLDEN / "orbits").glob("*.json"))
LEVEL = {c: json.loads((GOLDEN / "cases" / c / "settings.json").read_text())["level"] for c in CASES}

_spec = importlib.util.spec_from_file_location("golden_sample", REPO / ".ci" / "golden_sample.py")
golden_sample = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(golden_sample)


def _reports(tmp_path, argv, rc, capsys=None):
    js, xml = tmp_path / "r.json", tmp_path / "r.xml"
    assert main([*argv, "--json", str(js), "--junit-xml", str(xml)]) == rc
    doc = json.loads(js.read_text())
    root = ET.parse(xml).getroot()
    return doc, root, {t.get("name"): t for t in root.iter("testcase")}


def _one_error(capsys, *needles) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in err[0], err
    for n in needles:
        assert n in err[0], (n, err[0])
    return err[0]


def test_cases_not_selected_are_skipped_with_the_reason(tmp_path, capsys):
    """Before: cases left out by --level vanished from the reports (8 testcases for --level 1)."""
    out, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out", levels=[1])
    one = next(c for c in CASES if LEVEL[c] == 1)
    doc, root, tc = _reports(tmp_path, ["check", str(out), "--level", "1", "--exclude", one], 0)
    assert doc["tests"] == len(CASES) == len(tc)
    n1 = sum(v == 1 for v in LEVEL.values())
    assert (doc["passed"], doc["skipped"], doc["failed"]) == (n1 - 1, len(CASES) - n1 + 1, 0)
    ts = root.find("testsuite")
    assert ts.get("skipped") == str(len(CASES) - n1 + 1) and ts.get("failures") == "0"
    for c in CASES:
        sk = tc[c].find("skipped")
        if c == one:
            assert sk.get("message") == "skipped: excluded by --exclude"
        elif LEVEL[c] != 1:
            assert sk.get("message") == f"skipped: level {LEVEL[c]}, not selected by --level 1"
        else:
            assert len(tc[c]) == 0
    res = {r["id"]: r for r in doc["results"]}
    assert res[one]["verdict"] == "skipped" and res[one]["passed"] is None and res[one]["reason"]
    assert doc["selection"] == {"cases": None, "levels": [1], "exclude": [one], "known_failures": None}
    props = {p.get("name"): p.get("value") for p in root.iter("property")}
    assert props["selection.levels"] == "1" and props["selection.exclude"] == one
    assert main(["check", str(out), "--level", "1", "--summary"]) == 0
    assert f"{n1}/{n1} cases pass, {len(CASES) - n1} skipped" in capsys.readouterr().out
    assert main(["check", str(out), "--exclude", "9999-nope"]) == 2
    _one_error(capsys, "unknown case id(s): '9999-nope'")


def test_known_failures_are_expected_and_one_that_passes_fails_the_run(tmp_path, capsys):
    broken = next(c for c in CASES if LEVEL[c] == 1)
    good = next(c for c in CASES if c != broken)
    out, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out", broken)
    known = tmp_path / "known.txt"
    known.write_text(f"# our known failures\n\n{broken}   our finder is sloppy (issue 12)\n")
    doc, root, tc = _reports(tmp_path, ["check", str(out), "--known-failures", str(known)], 0)
    assert (doc["xfailed"], doc["failed"], doc["passed"]) == (1, 0, len(CASES) - 1)
    sk = tc[broken].find("skipped")
    assert sk.get("type") == "golden.xfail" and "our finder is sloppy (issue 12)" in sk.get("message")
    assert tc[broken].get("line") == "2" and "<- tau" in sk.text  # still says what differs
    res = {r["id"]: r for r in doc["results"]}
    assert res[broken]["verdict"] == "xfail" and res[broken]["reason"] == "our finder is sloppy (issue 12)"
    assert main(["check", str(out), "--known-failures", str(known), "--summary"]) == 0
    assert "1 known failure (xfail)" in capsys.readouterr().out
    # strict: a known failure that passes fails the run, and says so
    known.write_text(f"{broken} sloppy\n{good}\tfixed since, but still listed\n")
    doc, root, tc = _reports(tmp_path, ["check", str(out), "--known-failures", str(known)], 1)
    assert (doc["xpassed"], doc["xfailed"]) == (1, 1)
    f = tc[good].find("failure")
    assert f.get("type") == "golden.xpass" and f"remove it from {known}" in f.get("message")
    assert root.find("testsuite").get("failures") == "1"
    assert main(["check", str(out), "--known-failures", str(known), "--summary"]) == 1
    assert capsys.readouterr().out.strip().endswith(f"; known failures that now pass: {good}")


@pytest.mark.parametrize(
    "text, needles",
    [
        ("9999-nope some reason\n", ["line 1, column 1", "unknown case id '9999-nope'"]),
        ("{0} a\n# c\n{0} b\n", ["line 3", "listed twice (also line 1)"]),
        ("  {0}\n", ["line 1, column 20", "has no reason"]),  # just after the id
        ("{0} r\u2028\n", ["line 1", "U+2028"]),
    ],
)
def test_a_malformed_known_failures_file_is_one_line_exit_2(tmp_path, capsys, text, needles):
    out, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out")
    known = tmp_path / "known.txt"
    known.write_text(text.format(CASES[0]))
    assert main(["check", str(out), "--known-failures", str(known)]) == 2
    _one_error(capsys, "--known-failures", str(known), *needles)
    assert main(["check", str(out), "--known-failures", str(tmp_path / "nope.txt")]) == 2
    _one_error(capsys, "--known-failures", "not found")


def test_a_missing_output_folder_still_writes_the_reports(tmp_path, capsys):
    """Before: exit 2 and no report at all, so the CI step that uploads it failed too."""
    doc, root, tc = _reports(tmp_path, ["check", str(tmp_path / "nope")], 1)
    _one_error(capsys, "PATH=", "not found", '"no output"')
    assert (doc["tests"], doc["failed"]) == (len(CASES), len(CASES))
    assert {t.find("failure").get("type") for t in tc.values()} == {"golden.no-output"}
    assert all(r["note"].startswith("no output (") for r in doc["results"])
    doc, _, _ = _reports(tmp_path, ["check", "--orbits", str(tmp_path / "nope")], 1)
    _one_error(capsys, 'every record scored "no output"')
    assert doc["failed"] == len(RECORDS)


def test_xml_booleans_are_true_and_false(tmp_path, capsys):
    """Before: suite.digest_matches was written "True" (and a missing digest "None")."""
    copy = tmp_path / "cases"
    shutil.copytree(GOLDEN / "cases", copy)
    (copy / CASES[0] / "provenance.json").write_text((copy / CASES[0] / "provenance.json").read_text() + " ")
    out, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out")
    _, root, _ = _reports(tmp_path, ["check", str(out), "--suite", str(copy)], 0)
    props = {p.get("name"): p.get("value") for p in root.iter("property")}
    assert props["suite.digest_matches"] == "false"
    assert not {"True", "False", "None"} & set(props.values())
    _, root, _ = _reports(tmp_path, ["check", str(out)], 0)
    assert {p.get("name"): p.get("value") for p in root.iter("property")}["suite.digest_matches"] == "true"


def test_require_suite_takes_compatible_ranges(tmp_path, capsys):
    """Before: only the exact version was accepted (--require-suite 1 refused the suite 1.0.0)."""
    major, minor, patch = (int(x) for x in V.SUITE_VERSION.split("."))
    out, _ = golden_sample.write_sample(GOLDEN, tmp_path / "out")
    ok = [f"{major}", f"{major}.{minor}", f"~={major}.{minor}", f"~={major}.{minor}.{patch}", V.SUITE_VERSION]
    ok += [f"~={major}.0"] if minor else []
    for spec in ok:
        assert main(["check", str(out), "--require-suite", spec, "--summary"]) == 0, spec
    capsys.readouterr()
    for spec in (f"{major + 1}", f"{major}.{minor + 1}", f"~={major}.{minor + 1}", f"{major}.{minor}.{patch + 1}"):
        assert main(["check", str(out), "--require-suite", spec, "--summary"]) == 2, spec
        _one_error(capsys, f"--require-suite {spec}: the suite is {V.SUITE_VERSION}, not {spec}")
    for spec in ("~=1", "v1", "1.0.0.0", "latest"):
        with pytest.raises(SystemExit) as ex:
            main(["check", str(out), "--require-suite", spec])
        assert ex.value.code == 2
        _one_error(capsys, "--require-suite", "allowed MAJOR (1), MAJOR.MINOR (1.0), ~=MAJOR.MINOR")
    copy = tmp_path / "cases"
    shutil.copytree(GOLDEN / "cases", copy)
    (copy / CASES[0] / "settings.json").write_text((copy / CASES[0] / "settings.json").read_text() + " ")
    assert main(["check", str(out), "--suite", str(copy), "--require-suite", f"{major}"]) == 2
    _one_error(capsys, f"the suite is {V.SUITE_VERSION}+modified")


def test_the_orbit_records_have_the_same_verdicts(tmp_path, capsys):
    _, orbits = golden_sample.write_sample(GOLDEN, tmp_path / "out", RECORDS[0])
    (orbits / f"{RECORDS[1]}.json").write_text("{")
    (orbits / f"{RECORDS[2]}.json").unlink()
    known = tmp_path / "known.txt"
    known.write_text(f"{RECORDS[0]} a known bug\n")
    argv = ["check", "--orbits", str(orbits), "--exclude", RECORDS[3], "--known-failures", str(known)]
    doc, _, tc = _reports(tmp_path, argv, 1)
    verdicts = {r["id"]: r["verdict"] for r in doc["results"]}
    assert verdicts[RECORDS[0]] == "xfail" and verdicts[RECORDS[1]] == "error"
    assert verdicts[RECORDS[2]] == "fail" and verdicts[RECORDS[3]] == "skipped"
    assert {verdicts[r] for r in RECORDS[4:]} == {"pass"}
    assert tc[RECORDS[1]].find("error").get("type") == "golden.malformed" and tc[RECORDS[1]].get("line") == "1"
    _one_error(capsys, f"{RECORDS[1]}.json", "line 1")


def test_suite_version_json_names_the_folders(tmp_path, capsys):
    """Before: --suite-version ignored --json; the way to the case folders was a python -c line."""
    assert main(["check", "--suite-version", "--json", "-"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["version"] == V.SUITE_VERSION and d["digest"] == V.recorded()["digest"] and d["digest_matches"]
    assert Path(d["cases"]["folder"]) == GOLDEN / "cases" and Path(d["orbits"]["folder"]) == GOLDEN / "orbits"
    assert Path(d["cases"]["index"]).is_file() and Path(d["format_description"]).is_file()
    assert d["cases"]["ids"] == CASES and d["orbits"]["ids"] == RECORDS
    assert d["cases"]["levels"] == {str(lv): [c for c in CASES if LEVEL[c] == lv] for lv in sorted(set(LEVEL.values()))}
    js = tmp_path / "suite.json"
    assert main(["check", "--suite-version", "--json", str(js)]) == 0
    assert f"{V.SUITE_NAME} {V.SUITE_VERSION}: cases" in capsys.readouterr().out  # the lines as well
    assert json.loads(js.read_text()) == d
    assert main(["check", "--suite-version", "--orbits", "--suite", str(GOLDEN / "orbits"), "--json", "-"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert set(d) >= {"orbits"} and "cases" not in d and d["orbits"]["digest_matches"]


def test_export_suite_copies_the_suite_with_its_format(tmp_path, capsys):
    dest = tmp_path / "golden-suite"
    assert main(["check", "--export-suite", str(dest)]) == 0
    assert capsys.readouterr().out.startswith(f"exported {V.SUITE_NAME} {V.SUITE_VERSION} (")
    for part in ("cases", "orbits"):
        for rel in V.suite_files(GOLDEN / part):
            assert (dest / part / rel).read_bytes() == (GOLDEN / part / rel).read_bytes(), rel
    assert (dest / "cases" / "index.json").read_bytes() == (GOLDEN / "cases" / "index.json").read_bytes()
    assert (dest / "FORMAT.md").read_bytes() == (GOLDEN / "FORMAT.md").read_bytes()
    d = json.loads((dest / "suite.json").read_text())
    assert (d["cases"]["folder"], d["orbits"]["folder"], d["cases"]["index"]) == ("cases", "orbits", "cases/index.json")
    assert d["format_description"] == "FORMAT.md" and d["cases"]["ids"] == CASES
    assert not [p for p in dest.rglob("*") if ".partial-" in p.name]  # nothing left of the atomic writes
    # the copy is the recorded version, byte for byte: scoring against it works and is pinned
    assert main(["check", "--suite-version", "--suite", str(dest / "cases")]) == 0
    assert "matches the digest recorded" in capsys.readouterr().out
    out, _ = golden_sample.write_sample(dest, tmp_path / "out")
    assert (
        main(["check", str(out), "--suite", str(dest / "cases"), "--require-suite", V.SUITE_VERSION, "--summary"]) == 0
    )
    capsys.readouterr()
    assert main(["check", "--export-suite", str(dest)]) == 2
    _one_error(capsys, "--export-suite", "is not empty")
    assert main(["check", str(out), "--export-suite", str(tmp_path / "other")]) == 2
    _one_error(capsys, "--export-suite exports the installed suite and exits: no PATH")


def test_the_format_description_is_the_docs_sections():
    """FORMAT.md ships with the suite: it must be the docs' sections (.ci/golden_format.py) as they are now."""
    spec = importlib.util.spec_from_file_location("golden_format", REPO / ".ci" / "golden_format.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    want = mod.format_text()
    assert (GOLDEN / "FORMAT.md").read_text(encoding="utf-8") == want, "run python .ci/golden_format.py"
    assert "## File formats" in want and "## Model conventions an implementation must follow" in want
