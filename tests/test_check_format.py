"""`gear-rattle check` reads exactly the format of docs/reference/golden_formats.md ("What check reads") and selects
cases as documented (issue 30 items 1 and 5): each test here is a defect of the old checker.

The output of a perfect implementation is stood in for by the certified `expected.csv` (its radius
columns are extra trailing columns) and by the orbit records' midpoints; no track runs, no JAX."""

import json
import shutil
import time

import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.paths import DEFAULT_ORBITS
from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.formats.cases import load_suite, read_sequence
from gear_rattle.validation.golden.scoring.cases import score_sequence

CID = "0001-regular-fig2"
RID = "orbit-3-impact-fig2-alpha0.5-r0.9"


def _expected_lines(cid=CID):
    return (DEFAULT_SUITE / cid / "expected.csv").read_text().splitlines()


def _write(tmp_path, text, cid=CID, mode="w"):
    d = tmp_path / "out"
    d.mkdir(exist_ok=True)
    f = d / f"{cid}.csv"
    if mode == "wb":
        f.write_bytes(text)
    else:
        with open(f, "w", newline="", encoding="utf-8") as fh:
            fh.write(text)
    return d


def _check(d, *args):
    return main(["check", str(d), "--summary", *args])


def _one_error(capsys, *needles):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    for n in needles:
        assert n in err[0], (n, err[0])
    return err[0]


@pytest.mark.parametrize("column, pos", [("tau", 1), ("kind", 5), ("n", 0)])
def test_a_duplicate_column_name_is_malformed(tmp_path, capsys, column, pos):
    """The old checker read the last column of a name: a wrong tau (+0.5 on every row) passed when a
    trailing column also named tau held the right values."""
    lines = _expected_lines()
    out = [lines[0] + f",{column}"]
    for r in lines[1:]:
        f = r.split(",")
        right = f[pos]
        if column == "tau":
            f[pos] = repr(float(f[pos]) + 0.5)
        elif column == "kind":
            f[pos] = "stick"
        else:
            f[pos] = str(int(f[pos]) + 7)
        out.append(",".join(f) + f",{right}")
    d = _write(tmp_path, "\n".join(out) + "\n")
    assert _check(d, "--cases", CID) == 1  # malformed: an error of its case, exit 1
    _one_error(capsys, f"{CID}.csv", "line 1, column", f"duplicate column name {column!r}")


def test_a_duplicate_json_key_is_malformed(tmp_path, capsys):
    """json.loads kept the last of two keys: a wrong value followed by a right one passed."""
    rec = json.loads((DEFAULT_ORBITS / f"{RID}.json").read_text())
    pts = [
        {"tau_mod_2pi": sum(p["tau_mod_2pi"]) / 2, "sdot": sum(p["sdot"]) / 2, "wall": p["wall"]} for p in rec["points"]
    ]
    mult = [{"re": sum(m["re"]) / 2, "im": sum(m["im"]) / 2} for m in rec["multipliers"]]
    wrong = [dict(p, sdot=p["sdot"] + 1) for p in pts]
    d = tmp_path / "out"
    d.mkdir()
    text = '{"points": %s, "multipliers": %s,\n "points": %s}' % (json.dumps(wrong), json.dumps(mult), json.dumps(pts))
    (d / f"{RID}.json").write_text(text)
    assert main(["check", "--orbits", str(d), "--cases", RID]) == 1  # malformed: an error of its case, exit 1
    _one_error(capsys, f"{RID}.json", "line 2, column 2", "duplicate key 'points'")


@pytest.mark.parametrize("char", ["\x85", "\u2028", "\u2029", "\x00", "\x0b", "\x0c", "\x1c", "\x7f", "\ufeff"])
def test_characters_the_format_does_not_allow(tmp_path, capsys, char):
    """Unicode line breaks were line ends to str.splitlines (a row split in two, or an ignored one);
    now any control or separator character (and a byte-order mark after the start) is malformed."""
    lines = _expected_lines()
    lines[4] = lines[4] + char  # inside the last (extra) field of line 5
    d = _write(tmp_path, "\n".join(lines) + "\n")
    assert _check(d, "--cases", CID) == 1  # malformed: an error of its case, exit 1
    _one_error(capsys, "line 5, column", f"U+{ord(char):04X}")


def test_unicode_line_break_inside_a_json_string_is_malformed(tmp_path, capsys):
    d = tmp_path / "out"
    d.mkdir()
    (d / f"{RID}.json").write_text('{"points\u2028": 1, "value": 2}')
    assert main(["check", "--orbits", str(d), "--cases", RID]) == 1  # malformed: an error of its case, exit 1
    _one_error(capsys, "line 1, column 9", "U+2028")


def test_a_lone_carriage_return_is_malformed_and_crlf_is_accepted(tmp_path, capsys):
    lines = _expected_lines()
    d = _write(tmp_path, "\r\n".join(lines) + "\r\n")
    assert _check(d, "--cases", CID) == 0, capsys.readouterr()
    d = _write(tmp_path, "\n".join(lines[:3]) + "\r" + "\n".join(lines[3:]) + "\n")
    assert _check(d, "--cases", CID) == 1  # malformed: an error of its case, exit 1
    _one_error(capsys, "line 3, column", "carriage return")


def test_blank_lines_are_skipped_before_the_header_too(tmp_path, capsys):
    """docs/golden.md says blank lines are skipped; the old checker refused one before the header."""
    lines = _expected_lines()
    d = _write(tmp_path, "\n \t\n" + "\n".join(lines[:5]) + "\n\n" + "\n".join(lines[5:]) + "\n")
    assert _check(d, "--cases", CID) == 0, capsys.readouterr()
    # and a note names the file's own line numbers
    rows = lines[:5] + [""] + lines[5:]
    f = rows[9].split(",")
    f[1] = repr(float(f[1]) + 1e-6)
    rows[9] = ",".join(f)
    d = _write(tmp_path, "\n \t\n" + "\n".join(rows) + "\n")
    assert main(["check", str(d), "--cases", CID]) == 1
    assert "first failing: tau at line 12 " in capsys.readouterr().out


@pytest.mark.parametrize(
    "what",
    ["csv-field-131073", "json-depth-1000", "json-int-310-digits", "json-1e400", "csv-field-1001", "csv-columns-101"],
)
def test_inputs_that_gave_tracebacks(tmp_path, capsys, what):
    """A CSV field over 131072 characters (csv.Error), JSON nested 1000 deep (RecursionError) and a
    310-digit JSON integer (OverflowError) were tracebacks with exit status 1: now one line on stderr,
    and an error of that case alone (exit 1: a malformed output is an error of its case)."""
    if what.startswith("csv"):
        lines = _expected_lines()
        if what == "csv-columns-101":
            lines = [r + ",x" * 92 for r in lines]
            lines[0] = ",".join(lines[0].split(",")[:9] + [f"c{k}" for k in range(92)])
            needle = "more than 100 columns"
        else:
            n = 131073 if what.endswith("131073") else 1001
            lines[3] = lines[3] + "," + "7" * n
            lines = [lines[0] + ",note"] + [r + ",x" if k != 2 else r for k, r in enumerate(lines[1:])]
            needle = "longer than 1000 characters"
        d = _write(tmp_path, "\n".join(lines) + "\n")
        assert _check(d, "--cases", CID) == 1  # malformed: an error of its case, exit 1
        _one_error(capsys, needle)
        return
    d = tmp_path / "out"
    d.mkdir()
    body = {"json-depth-1000": "[" * 1000 + "]" * 1000, "json-int-310-digits": "1" + "0" * 309, "json-1e400": "1e400"}[
        what
    ]
    (d / f"{RID}.json").write_text('{"value": %s, "points": [], "multipliers": []}' % body)
    assert main(["check", "--orbits", str(d), "--cases", RID]) == 1  # malformed: an error of its case, exit 1
    _one_error(capsys, f"{RID}.json", "line 1, column", "limit" if "1e400" not in what else "not a finite number")


def test_a_huge_file_is_refused_in_bounded_time(tmp_path, capsys):
    """10^6 extra rows took the old checker 10-21 s to parse; the file is now refused after reading at
    most 2 MiB + 1 bytes, and a file of more than 20000 lines after counting them."""
    lines = _expected_lines()
    d = _write(tmp_path, "\n".join(lines) + ("\n" + lines[-1]) * 1_000_000 + "\n")
    t = time.perf_counter()
    assert _check(d, "--cases", CID) == 1  # malformed: an error of its case, exit 1
    assert time.perf_counter() - t < 3.0
    _one_error(capsys, "larger than 2097152 bytes")
    d = _write(tmp_path, "\n".join(lines) + "\n0,0,0,0,1,impact,0,0,0" * 30_000 + "\n")
    t = time.perf_counter()
    assert _check(d, "--cases", CID) == 1  # malformed: an error of its case, exit 1
    assert time.perf_counter() - t < 3.0
    _one_error(capsys, "line 20001, column 1: more than 20000 lines")


def test_repeated_cases_accumulate(tmp_path, capsys):
    """`--cases A --cases B` scored only B."""
    d = tmp_path / "out"
    d.mkdir()
    for cid in ("0001-regular-fig2", "0007-chatter-sticking", "0008-stuck-forever"):
        shutil.copy(DEFAULT_SUITE / cid / "expected.csv", d / f"{cid}.csv")
    assert _check(d, "--cases", "0001-regular-fig2", "--cases", "0007-chatter-sticking", "0008-stuck-forever") == 0
    assert capsys.readouterr().out.startswith("3/3 cases pass")


def test_level_selects_cases(tmp_path, capsys):
    """`--level 1,2` selects by the level of index.json / settings.json; a missing output file is a
    failing case ("no output") and the run goes on."""
    index = json.loads((DEFAULT_SUITE / "index.json").read_text())
    by_level = {lv: [c["id"] for c in index["cases"] if c["level"] == lv] for lv in (1, 2, 3)}
    d = tmp_path / "out"
    d.mkdir()
    for cid in by_level[1]:
        shutil.copy(DEFAULT_SUITE / cid / "expected.csv", d / f"{cid}.csv")
    assert _check(d, "--level", "1") == 0
    n1 = len(by_level[1])
    assert capsys.readouterr().out.startswith(f"{n1}/{n1} cases pass")
    n12 = n1 + len(by_level[2])
    assert main(["check", str(d), "--level", "1,2"]) == 1
    out = capsys.readouterr()
    assert out.err == ""
    assert out.out.splitlines()[-1].startswith(f"{n1}/{n12} cases pass")
    assert out.out.count("no output") == len(by_level[2])
    assert _check(d, "--level", "2", "--level", "1") == 1
    assert capsys.readouterr().out.startswith(f"{n1}/{n12} cases pass")
    assert _check(d, "--level", "3", "--cases", by_level[1][0]) == 2
    _one_error(capsys, "no case selected by --cases", "--level 3")
    with pytest.raises(SystemExit) as ex:
        main(["check", str(d), "--level", "1,4"])
    assert ex.value.code == 2
    _one_error(capsys, "--level", "allowed levels 1, 2, 3")
    assert main(["check", "--orbits", str(d), "--level", "1"]) == 2
    _one_error(capsys, "no record selected by --level 1")


def test_help_names_the_installed_suite(capsys):
    """`check --help` named `validation/golden/cases`, a repository path: now the package's own copy."""
    with pytest.raises(SystemExit):
        main(["check", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "the copy installed with this package" in out
    assert str(DEFAULT_SUITE) in "".join(out.split())  # (wrapped by argparse: compared without blanks)


def test_score_fields_for_machine_readable_output(tmp_path):
    """The fields a JSON / JUnit report reads: level, digits per column, worst error over tolerance,
    first failing row (0-based data row)."""
    case = load_suite(DEFAULT_SUITE, ["0007-chatter-sticking"])[0]
    lines = (DEFAULT_SUITE / case.id / "expected.csv").read_text().splitlines()
    f = lines[5].split(",")
    f[1] = repr(float(f[1]) + 3 * float(case.row_tolerances("tau")[0][4]))  # 3 times this row's own tolerance
    lines[5] = ",".join(f)
    p = tmp_path / "x.csv"
    p.write_text("\n".join(lines) + "\n")
    s = score_sequence(case, read_sequence(p))
    assert not s.passed and s.level == 2 and s.first_row == 4 and not s.no_output
    assert s.worst_ratio == pytest.approx(3, rel=1e-3)
    assert set(s.column_digits) == {"tau", "tau_mod_2pi", "sdot"} and s.column_digits["sdot"] == 17.0
