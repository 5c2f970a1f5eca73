"""What a failing case reports (issue 37 item 1; docs/reference/golden_commands.md, "What a failing case reports"): for
every kind of failure, the first failing row of the golden file and of the output side by side, the
rows around it aligned by event (a missing or extra row shows as such), the column, |error|, the row's
tolerance and their ratio -- on the terminal, in the JSON and in the JUnit failure -- and a wrong wall
or kind named as such.

Outputs are the certified ``expected.csv`` files with one planted defect each; no track runs."""

from __future__ import annotations

import csv
import json
import xml.etree.ElementTree as ET

import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.paths import DEFAULT_ORBITS
from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.formats.cases import load_case, read_sequence
from gear_rattle.validation.golden.scoring.cases import score_sequence

COLUMNS = ["n", "tau", "tau_mod_2pi", "wall", "sdot", "kind"]


def _rows(cid: str) -> list[list[str]]:
    """The data rows of a case's expected.csv, its six columns only (line k + 2 of the file: row k)."""
    return [r[:6] for r in csv.reader((DEFAULT_SUITE / cid / "expected.csv").read_text().splitlines()[1:])]


def _write(tmp_path, cid: str, rows: list[list[str]]):
    d = tmp_path / "out"
    d.mkdir(exist_ok=True)
    with open(d / f"{cid}.csv", "w", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerows([COLUMNS, *rows])
    return d


def _check(tmp_path, capsys, cid: str, rows: list[list[str]]) -> tuple[dict, str, ET.Element]:
    """Score one planted output: (its JSON result, the terminal output, its JUnit testcase)."""
    d = _write(tmp_path, cid, rows)
    js, xml = tmp_path / "r.json", tmp_path / "r.xml"
    assert main(["check", str(d), "--cases", cid, "--json", str(js), "--junit-xml", str(xml)]) == 1
    out = capsys.readouterr().out
    res = {r["id"]: r for r in json.loads(js.read_text())["results"]}[cid]
    tc = next(t for t in ET.parse(xml).getroot().iter("testcase") if t.get("name") == cid)
    return res, out, tc


def _ops(diff: dict) -> list[tuple]:
    return [(c["op"], c["golden_line"], c["line"]) for c in diff["context"]]


def test_a_value_beyond_its_tolerance_expected_against_got(tmp_path, capsys):
    """Before: 'tau at line 5 (|error| .., .. x tolerance)', neither value shown."""
    cid = "0002-chaotic-fig3"
    case = load_case(DEFAULT_SUITE / cid)
    rows = _rows(cid)
    abs_tol, rel = case.row_tolerances("tau")
    golden = float(rows[3][1])
    tol = float(abs_tol[3]) + rel * abs(golden)
    rows[3][1] = repr(golden + 3 * tol)
    res, out, tc = _check(tmp_path, capsys, cid, rows)
    ff = res["first_failing"]
    assert (ff["kind"], ff["column"], ff["line"], ff["golden_line"], ff["row"]) == ("value", "tau", 5, 5, 3)
    assert ff["expected"]["tau"] == golden and ff["actual"]["tau"] == golden + 3 * tol
    # 3 x the row's tolerance, as far as golden + 3 tol rounds (a row's tolerance is ~1e-11: the rounding of
    # golden + 3 tol to a float64 moves the ratio by up to ~1e-5)
    over = abs((golden + 3 * tol) - golden) / tol
    assert ff["tolerance"] == pytest.approx(tol) and ff["over_tolerance"] == pytest.approx(over, rel=1e-9)
    assert over == pytest.approx(3, rel=1e-4)
    assert ff["file"] == str(tmp_path / "out" / f"{cid}.csv")
    assert ff["golden_file"] == str(DEFAULT_SUITE / cid / "expected.csv")
    assert _ops(ff) == [("=", 3, 3), ("=", 4, 4), ("~", 5, 5), ("=", 6, 6), ("=", 7, 7)]
    assert ff["context"][2]["columns"] == ["tau"]
    assert f"tau: expected {golden!r} (golden line 5), got {golden + 3 * tol!r}" in out
    assert "<- tau" in out
    assert (tc.get("file"), tc.get("line")) == (ff["file"], "5") and tc.find("failure").get("type") == "golden.value"
    assert f"got {golden + 3 * tol!r}" in tc.find("failure").text


def test_a_wrong_wall_is_named_as_such(tmp_path, capsys):
    """The issue's example: an impact on wall -1 where the golden one is on wall 0 (its time off by 2.55),
    equal row counts.  Before: 'first failing: tau at line 3 (|error| 2.55, ...)'."""
    cid = "0001-regular-fig2"
    rows = _rows(cid)
    k = next(i for i, r in enumerate(rows) if r[3] == "0" and i > 0)
    rows[k][3], rows[k][1] = "-1", repr(float(rows[k][1]) + 2.55)
    res, out, tc = _check(tmp_path, capsys, cid, rows)
    ff = res["first_failing"]
    assert (ff["kind"], ff["column"], ff["line"], ff["golden_line"]) == ("wall", "wall", k + 2, k + 2)
    assert (ff["expected"]["wall"], ff["actual"]["wall"]) == (0, -1)
    assert res["event_difference"] == ff and not res["exact_columns_match"]
    assert res["note"].startswith(f"first failing: wall at line {k + 2} (-1 instead of 0: an event on the other wall")
    assert f"tau at line {k + 2}" not in res["note"] and "<- wall" in out
    assert res["compared_rows"] == k  # the values of the rows before it were compared
    assert tc.find("failure").get("type") == "golden.wall"


def test_a_wrong_kind_and_a_wrong_n(tmp_path, capsys):
    cid = "0007-chatter-sticking"
    rows = _rows(cid)
    rows[25][5], rows[25][4] = "stick", ""  # golden line 27 is a release
    res, _, _ = _check(tmp_path, capsys, cid, rows)
    ff = res["first_failing"]
    assert (ff["kind"], ff["line"], ff["expected"]["kind"], ff["actual"]["kind"]) == ("kind", 27, "release", "stick")
    rows = _rows(cid)
    rows[5][0] = "17"
    res, _, _ = _check(tmp_path, capsys, cid, rows)
    ff = res["first_failing"]
    assert (ff["kind"], ff["column"], ff["line"], ff["actual"]["n"]) == ("n", "n", 7, 17)
    assert res["note"].startswith("first failing: n at line 7 (17 instead of 5)")


def test_missing_rows_are_shown_missing_and_the_rows_after_them_realigned(tmp_path, capsys):
    """The issue's example: the stick and release rows of one episode missing, 41 rows instead of 43.
    Before: 'wrong number of events: 41 rows, expected 43 (first differing event at line 26 ...)', no
    rows shown, first_failing and digits null in the JSON."""
    cid = "0007-chatter-sticking"
    rows = _rows(cid)
    del rows[24:26]  # golden lines 26-27
    res, out, _ = _check(tmp_path, capsys, cid, rows)
    ff = res["first_failing"]
    assert (ff["kind"], ff["count"], ff["golden_line"], ff["line"]) == ("missing-rows", 2, 26, 26)
    assert (ff["rows"], ff["expected_rows"], ff["expected"]["kind"]) == (41, 43, "stick")
    assert _ops(ff) == [("=", 24, 24), ("=", 25, 25), ("-", 26, None), ("-", 27, None), ("=", 28, 26), ("=", 29, 27)]
    assert res["note"].startswith("wrong number of events: 41 rows, expected 43; first failing: 2 golden rows")
    assert res["digits"]["tau"] == 17.0 and res["compared_rows"] == 24
    assert "golden only" in out


def test_extra_rows_in_the_middle_and_after_the_golden_end(tmp_path, capsys):
    cid = "0002-chaotic-fig3"
    rows = _rows(cid)
    extra = list(rows[6])
    extra[1] = extra[2] = repr((float(rows[5][1]) + float(rows[6][1])) / 2)  # between lines 7 and 8
    rows.insert(6, extra)
    res, _, _ = _check(tmp_path, capsys, cid, rows)
    ff = res["first_failing"]
    assert (ff["kind"], ff["count"], ff["line"], ff["golden_line"]) == ("extra-rows", 1, 8, 8)
    assert ("+", None, 8) in _ops(ff) and ("=", 8, 9) in _ops(ff)
    # a stuck-forever orbit goes on: the rows after its last one are extra, and the report says how it ends
    cid = "0008-stuck-forever"
    rows = _rows(cid)
    stick = rows[-1]
    rows += [[stick[0], repr(float(stick[1]) + 1.0), repr(float(stick[2]) + 1.0), "0", "", "release"]]
    res, out, _ = _check(tmp_path, capsys, cid, rows)
    ff = res["first_failing"]
    assert (ff["kind"], ff["line"], ff["golden_line"], ff["expected_status"]) == (
        "extra-rows", len(rows) + 1, None, "stuck_forever",
    )  # fmt: skip
    assert "the golden sequence ends before them (stuck_forever)" in ff["message"] and "output only" in out


def test_a_truncated_output_ends_early(tmp_path, capsys):
    cid = "0001-regular-fig2"
    rows = _rows(cid)[:-3]
    res, _, _ = _check(tmp_path, capsys, cid, rows)
    ff = res["first_failing"]
    assert (ff["kind"], ff["count"], ff["line"], ff["expected_status"]) == ("missing-rows", 3, None, "active")
    assert "at the end of the file" in ff["message"]


@pytest.mark.parametrize("cid", ["0007-chatter-sticking", "0013-lower-wall-sticking", "0002-chaotic-fig3"])
def test_each_single_missing_row_is_found_where_it_is(cid):
    """Drop each row in turn: the first difference is that golden row missing (or, where it repeats the
    event and time of its neighbour, one of the two), never a cascade of value failures."""
    case = load_case(DEFAULT_SUITE / cid)
    full = read_sequence(DEFAULT_SUITE / cid / "expected.csv")
    n = len(full)
    for k in range(n):
        keep = [i for i in range(n) if i != k]
        got = type(full)(
            "x.csv", *(getattr(full, c)[keep] for c in COLUMNS), lines=[i + 2 for i in range(n - 1)]
        )  # fmt: skip
        sc = score_sequence(case, got)
        ff = sc.first_failing
        assert not sc.passed and ff.kind == "missing-rows" and ff.count == 1, (k, ff.message)
        assert ff.golden_row == k, (k, ff.message)


def test_an_orbit_record_value_expected_against_got(tmp_path, capsys):
    rid = "orbit-3-impact-fig2-alpha0.5-r0.9"
    rec = json.loads((DEFAULT_ORBITS / f"{rid}.json").read_text())
    mult = [{"re": sum(m["re"]) / 2, "im": sum(m["im"]) / 2} for m in rec["multipliers"]]
    pts = [
        {"tau_mod_2pi": sum(p["tau_mod_2pi"]) / 2, "sdot": sum(p["sdot"]) / 2, "wall": p["wall"]} for p in rec["points"]
    ]
    pts[1]["sdot"] += 1e-6
    d = tmp_path / "out"
    d.mkdir()
    text = json.dumps({"points": pts, "multipliers": mult}, indent=1)
    (d / f"{rid}.json").write_text(text)
    line = 1 + next(k for k, t in enumerate(text.splitlines()) if f'"sdot": {pts[1]["sdot"]!r}' in t)
    js = tmp_path / "o.json"
    assert main(["check", "--orbits", str(d), "--cases", rid, "--json", str(js)]) == 1
    out = capsys.readouterr().out
    ff = {r["id"]: r for r in json.loads(js.read_text())["results"]}[rid]["first_failing"]
    lo, hi = rec["points"][1]["sdot"]
    assert (ff["kind"], ff["column"], ff["index"]) == ("value", "sdot", 1)
    assert ff["expected"] == [pytest.approx(lo), pytest.approx(hi)] and ff["actual"] == pts[1]["sdot"]
    assert ff["error"] == pytest.approx(1e-6, rel=1e-3) and ff["line"] == line  # that of points[1].sdot
    assert "sdot: expected [" in out


def test_an_empty_output_and_a_value_before_the_events_part(tmp_path, capsys):
    """A file with its header only: every golden row missing (counted, not cut at the window); a value
    failing before the sequences part: both reported, the value first."""
    cid = "0007-chatter-sticking"
    res, out, _ = _check(tmp_path, capsys, cid, [])
    ff = res["first_failing"]
    assert (ff["kind"], ff["count"], ff["golden_line"], ff["line"], ff["row"]) == ("missing-rows", 43, 2, None, None)
    assert res["digits"] == {"tau": None, "tau_mod_2pi": None, "sdot": None} and res["compared_rows"] == 0
    assert "more golden rows missing (not shown)" in out
    cid = "0013-lower-wall-sticking"
    rows = _rows(cid)
    rows[3][1] = repr(float(rows[3][1]) + 1e-6)
    k = next(i for i, r in enumerate(rows) if r[5] == "stick")
    del rows[k : k + 2]
    res, out, _ = _check(tmp_path, capsys, cid, rows)
    ff, ev = res["first_failing"], res["event_difference"]
    assert (ff["kind"], ff["line"]) == ("value", 5)
    assert (ev["kind"], ev["count"], ev["golden_line"]) == ("missing-rows", 2, k + 2)
    assert res["compared_rows"] == k and "then the event sequences part: 2 golden rows missing" in out


def test_our_track_raising_on_a_case_is_an_error_of_that_case(tmp_path, capsys, monkeypatch):
    """check --self: a track that raises on one case (a crash) is an error of that case; the run goes on."""
    import gear_rattle.mapimpl.tracks as tracks
    import gear_rattle.validation.golden.self_check as self_check

    def boom(case, track="map"):
        raise FloatingPointError(f"boom on {case.id}")

    monkeypatch.setattr(self_check, "run_case", boom)
    monkeypatch.setattr(tracks, "get", lambda name: None)
    js = tmp_path / "s.json"
    cid = "0001-regular-fig2"
    assert main(["check", "--self", "--cases", cid, "--json", str(js)]) == 1
    res = {r["id"]: r for r in json.loads(js.read_text())["results"]}[cid]
    assert res["verdict"] == "error" and res["first_failing"]["kind"] == "crash"
    assert res["note"] == f"our map track raised FloatingPointError: boom on {cid}"
