"""``gear-rattle case``: a golden-format case for any input (docs/reference/golden_commands.md, "Asking the oracle")."""

from __future__ import annotations

import json
import math
import re
import time

import numpy as np
import pytest

from gear_rattle.mapimpl.certified import PREC
from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.catalog.build import build_case
from gear_rattle.validation.golden.formats.spec import Spec
from gear_rattle.validation.golden.rules.tolerances import row_tolerances
from gear_rattle.validation.golden.oracle.inputs import CaseInput, case_input
from gear_rattle.validation.golden.oracle.ondemand import TOLERANCE_LIMIT, build_user_case, certify_input, input_spec
from gear_rattle.validation.golden.rules.decisions import doubtful_decision
from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.formats.cases import load_case, load_suite, read_sequence

#: The issue's chaotic orbit (200 impacts: the amplification rule alone gives tau 5e-3).
CHAOS = ["--alpha", "2.2", "--beta", "0.05", "--gamma", "0.3", "--r", "0.7", "--tau0", "1", "--sdot0", "0.2"]
#: The issue's free-flight start (30 impacts: 2e-3 before).
FREE = [
    "--alpha",
    "1.1",
    "--beta",
    "0.2",
    "--gamma",
    "-0.05",
    "--r",
    "0.8",
    "--tau0",
    "0",
    "--s0",
    "-0.5",
    "--sdot0",
    "0",
]


def _settings(folder) -> dict:
    return json.loads((folder / "settings.json").read_text())


def _loosest(settings: dict) -> float:
    return max(v["abs"] for v in settings["tolerances"].values())


def _input(args: list[str], impacts: int) -> CaseInput:
    return case_input(
        "x",
        *(float(a) for a in args[1:8:2]),
        float(args[9]),
        float(args[-1]),
        impacts,
        s0=float(args[11]) if "--s0" in args else None,
    )


@pytest.mark.parametrize("args, impacts, before", [(CHAOS, 200, 1e-4), (FREE, 30, 1e-5)])
def test_long_orbits_become_truncated_cases_with_tight_tolerances(args, impacts, before, tmp_path, capsys):
    """The rule alone (the generator's build_case: no horizon) gives the last rows of these orbits tolerances of
    1e-5 or more (measured 4.8e-4 and 4.2e-5); the case stops at the last impact whose rows keep every
    tolerance below 1e-6, and says so in settings.json and on stderr."""
    inp = _input(args, impacts)
    spec = Spec("x", "x", inp.params, inp.tau0, inp.sdot0, impacts, s0=inp.s0)
    old, _, _ = build_case(spec, tracks=False)
    assert _loosest(old) >= before  # the orbit uncut (no horizon for user input)
    capsys.readouterr()
    assert main(["case", *args, "--impacts", str(impacts), "--id", "long", "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    s = _settings(tmp_path / "long")
    t = s["notes"]["truncation"]
    assert _loosest(s) < TOLERANCE_LIMIT
    assert t["requested_impacts"] == impacts and t["kept_impacts"] == s["n_impacts"] < impacts
    assert "truncated" in s["tags"]
    assert f"case long: stops at impact {s['n_impacts']} of {impacts}" in err and len(err.strip().splitlines()) == 1
    # the longest such case: one impact more would have a row whose tolerance is at or above the limit, or ask a
    # sticking decision in doubt within its row's tolerances (the sticking-decision rule)
    orb = certify_input(inp, s["n_impacts"] + 1, PREC)[0]
    spec = input_spec(inp, s["n_impacts"] + 1)
    longer = row_tolerances(spec, orb)
    doubt = doubtful_decision(spec, orb, longer.values["tau"], longer.values["sdot"])
    over = max(float(np.nanmax(v)) for v in longer.values.values()) >= TOLERANCE_LIMIT
    assert over or (doubt is not None and doubt[0] == s["n_impacts"])


def test_max_tolerance_trades_length_for_tightness(tmp_path, capsys):
    """`case --max-tolerance T`: a smaller T, a shorter case whose every row's tolerance is below T (measured on
    the chaotic input: 171 impacts at 1e-6, 29 at 1e-9); T out of its range is a one-line usage error
    (a ValueError naming max_tolerance in the library)."""
    lengths = []
    for k, limit in enumerate(("1e-6", "1e-9")):
        argv = ["case", *CHAOS, "--impacts", "200", "--id", f"t{k}", "--out", str(tmp_path), "--quiet"]
        assert main([*argv, "--max-tolerance", limit]) == 0
        s = _settings(tmp_path / f"t{k}")
        tols = load_case(tmp_path / f"t{k}").row_tol
        assert max(float(np.nanmax(v)) for v in tols.values()) < float(limit)
        assert s["notes"]["truncation"]["limit"] == float(limit)
        lengths.append(s["n_impacts"])
    assert lengths[1] < lengths[0] < 200
    capsys.readouterr()
    for bad in ("0", "1e-15", "0.01", "nan", "x"):
        argv = ["case", *CHAOS, "--impacts", "5", "--id", "b", "--out", str(tmp_path), "--max-tolerance", bad]
        with pytest.raises(SystemExit) as ex:  # (argparse's usage error)
            main(argv)
        assert ex.value.code == 2
        err = capsys.readouterr().err
        assert "--max-tolerance" in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    inp = _input(CHAOS, 5)
    for value in (0.0, -1.0, 1.0, math.nan, math.inf, 1e-20):
        with pytest.raises(ValueError, match="max_tolerance"):
            build_user_case(inp, max_tolerance=value)


@pytest.mark.parametrize("prefix", ["0001", "0002", "0003", "0004", "0007", "0008", "0010", "0016", "0020", "0024"])
def test_shipped_inputs_give_the_shipped_cases(prefix, tmp_path):
    """A shipped case's input through `gear-rattle case` gives its expected.csv byte for byte, the tolerance of
    every row included, and its tolerances: one rule for both (every shipped case but 0015, whose stick row
    after a chatter down to 1.3e-8 has 3.4e-6, beyond `case`'s limit)."""
    cid = next(p.name for p in DEFAULT_SUITE.iterdir() if p.name.startswith(prefix))
    s = _settings(DEFAULT_SUITE / cid)
    p, ini = s["params"], s["initial_state"]
    args = ["case", "--s0", repr(ini["s0"])] if "s0" in ini else ["case"]
    args += [
        "--alpha",
        repr(p["alpha"]),
        "--beta",
        repr(p["beta"]),
        "--gamma",
        repr(p["gamma"]),
        "--r",
        repr(p["r"]),
        "--tau0",
        repr(ini["tau0"]),
        "--sdot0",
        repr(ini["sdot0"]),
        "--impacts",
        str(s["n_impacts"]),
        "--id",
        cid,
        "--out",
        str(tmp_path),
        "--quiet",
    ]
    assert main(args) == 0
    mine = _settings(tmp_path / cid)
    assert (tmp_path / cid / "expected.csv").read_text() == (DEFAULT_SUITE / cid / "expected.csv").read_text()
    assert mine["tolerances"] == s["tolerances"] and mine["expected_status"] == s["expected_status"]
    assert "truncation" not in mine["notes"]


def test_check_scores_a_user_suite_as_the_shipped_one(tmp_path, capsys):
    """`check OUT --suite SUITE` on a suite of `case`: our map track's files pass; one impact time moved
    by 1e-6 (a row of a truncated chaotic case) fails it, as it would fail a shipped case."""
    suite, out = tmp_path / "suite", tmp_path / "out"
    assert main(["case", *CHAOS, "--impacts", "200", "--id", "chaos", "--out", str(suite), "--quiet"]) == 0
    assert main(["case", *FREE, "--impacts", "30", "--id", "free", "--out", str(suite), "--quiet"]) == 0
    assert main(["check", "--self", "--suite", str(suite), "--out", str(out), "--quiet"]) == 0
    assert main(["check", str(out), "--suite", str(suite)]) == 0
    assert [c.id for c in load_suite(suite)] == ["chaos", "free"]
    lines = (out / "chaos.csv").read_text().splitlines()
    f = lines[-1].split(",")
    f[1] = repr(float(f[1]) + 1e-6)
    (out / "chaos.csv").write_text("\n".join(lines[:-1] + [",".join(f)]) + "\n")
    capsys.readouterr()
    assert main(["check", str(out), "--suite", str(suite)]) == 1
    text = capsys.readouterr().out
    assert re.search(r"^chaos +FAIL ", text, re.M) and re.search(r"^free +PASS ", text, re.M)
    # the user's suite is named as such, its digest recorded by `case`: not the shipped suite, not modified
    assert text.startswith("suite: user suite (gear-rattle case) unversioned: cases ") and "matches" in text


def test_batch_from_csv_and_json_and_the_index(tmp_path, capsys):
    """--from a CSV (empty s0: a pre-impact start) and a JSON list; the index keeps the fields it had
    (a version another tool wrote) and lists every case."""
    suite = tmp_path / "s"
    suite.mkdir()
    (suite / "index.json").write_text(json.dumps({"suite_version": "user-7", "cases": []}))
    (tmp_path / "in.csv").write_text(
        "id,alpha,beta,gamma,r,tau0,sdot0,s0,impacts\na,0.5,0.1,0.1,0.9,0,0.5,,5\nb,1,0.1,-0.2,0.8,0,0,-0.5,5\n"
    )
    (tmp_path / "in.json").write_text(
        json.dumps(
            [{"id": "c", "alpha": 2.0, "beta": 0.1, "gamma": -1.0, "r": 0.5, "tau0": 0.0, "sdot0": -0.5, "impacts": 40}]
        )
    )
    assert main(["case", "--from", str(tmp_path / "in.csv"), "--out", str(suite), "--quiet"]) == 0
    assert main(["case", "--from", str(tmp_path / "in.json"), "--out", str(suite), "--quiet"]) == 0
    idx = json.loads((suite / "index.json").read_text())
    assert idx["suite_version"] == "user-7" and "bug_classes" in idx
    assert [c["id"] for c in idx["cases"]] == ["a", "b", "c"]
    assert load_case(suite / "b").settings["initial_state"]["kind"] == "free-flight"
    c = idx["cases"][2]
    assert c["level"] == 2 and c["stick_walls"] == [-1] and "lower-wall-sticking" in c["catches"]
    capsys.readouterr()
    assert main(["case", "--from", str(tmp_path / "in.csv"), "--out", str(suite)]) == 2  # ids taken
    assert "use --replace" in capsys.readouterr().err
    assert main(["case", "--from", str(tmp_path / "in.csv"), "--out", str(suite), "--replace", "--quiet"]) == 0


@pytest.mark.parametrize(
    "text, message",
    [
        (
            "id,alpha,beta,gamma,r,tau0,sdot0,impacts\na,0.5,0.1,0.1,1.5,0,0.5,5\n",
            "line 2: field r: parameter r='1.5' is out of range",
        ),
        (
            "id,alpha,beta,gamma,r,tau0,sdot0,impacts\na,0.5,0.1,0.1,0.9,0,0,5\n",
            "line 2: field sdot0: sdot0=0.0 is out of range",
        ),
        (
            "id,alpha,beta,gamma,r,tau0,sdot0,impacts\na,0.5,0.1,0.1,0.9,0,0.5,2.5\n",
            "impacts=2.5 is out of range: allowed an integer 0 <= impacts",
        ),
        ("id,alpha,beta,gamma,r,tau0,sdot0\na,0.5,0.1,0.1,0.9,0,0.5\n", "line 1: missing field(s) impacts"),
        ("id,alpha,beta,gamma,r,tau0,sdot0,impacts,x\na,0.5,0.1,0.1,0.9,0,0.5,5,1\n", "unknown field(s) 'x'"),
        ("id,alpha,beta,gamma,r,tau0,sdot0,impacts\n../a,0.5,0.1,0.1,0.9,0,0.5,5\n", "id='../a' is out of range"),
        (
            "id,alpha,beta,gamma,r,tau0,sdot0,impacts\na,0.5,0.1,0.1,0.9,0,0.5,5\na,0.5,0.1,0.1,0.9,0,0.5,5\n",
            "duplicate id 'a'",
        ),
        ('[{"id": "a"', "invalid JSON"),
    ],
)
def test_bad_inputs_are_one_line_usage_errors(text, message, tmp_path, capsys):
    (tmp_path / "in.csv").write_text(text)
    capsys.readouterr()
    assert main(["case", "--from", str(tmp_path / "in.csv"), "--out", str(tmp_path / "s")]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not (tmp_path / "s").exists()


def test_single_case_usage_errors(tmp_path, capsys):
    base = ["case", *CHAOS, "--impacts", "5", "--out", str(tmp_path)]
    assert main(base) == 2
    assert "missing --id" in capsys.readouterr().err
    assert main([*base, "--id", "a", "--from", "x.csv"]) == 2
    assert "drop --alpha" in capsys.readouterr().err
    assert main(["case", "--impacts", "5", "--id", "a", "--out", str(DEFAULT_SUITE), *CHAOS]) == 2
    assert "shipped suite" in capsys.readouterr().err


def test_stick_time_is_the_cases_threshold(tmp_path):
    """--stick-time changes the sticking policy of the certified orbit and is recorded in settings.json:
    the chatter of case 0007 sticks at 1e-6 and bounces on (more impact rows, no stick row) at 1e-9."""
    args = [
        "case",
        "--alpha",
        "2",
        "--beta",
        "0.1",
        "--gamma",
        "1",
        "--r",
        "0.5",
        "--tau0",
        "0",
        "--sdot0",
        "0.5",
        "--impacts",
        "40",
        "--out",
        str(tmp_path),
        "--quiet",
    ]
    assert main([*args, "--id", "default"]) == 0
    assert main([*args, "--id", "short", "--stick-time", "1e-9"]) == 0
    a, b = (read_sequence(tmp_path / i / "expected.csv") for i in ("default", "short"))
    assert "stick" in set(a.kind) and "stick" not in set(b.kind)
    assert _settings(tmp_path / "short")["stick_time"] == 1e-9


@pytest.mark.slow
def test_batch_of_1000_cases_within_a_minute(tmp_path):
    """1000 inputs of 10 impacts in <= 60 s on 2 cores (measured 20.6 s for the command at load 1.7)."""
    import random

    rnd = random.Random(1)
    inputs = []
    for k in range(1000):
        d = {
            "id": f"c{k:04d}",
            "alpha": round(rnd.uniform(0.1, 3.5), 3),
            "beta": round(rnd.uniform(0.01, 0.5), 3),
            "gamma": round(rnd.uniform(-0.5, 0.5), 3),
            "r": round(rnd.uniform(0.5, 1.0), 3),
            "tau0": round(rnd.uniform(0, 6.28), 3),
            "sdot0": round(rnd.choice([-1, 1]) * rnd.uniform(0.05, 2), 3),
            "impacts": 10,
        }
        if k % 4 == 0:
            d["s0"] = round(rnd.uniform(-0.9, -0.1), 3)
        inputs.append(d)
    (tmp_path / "in.json").write_text(json.dumps(inputs))
    t = time.perf_counter()
    assert main(["case", "--from", str(tmp_path / "in.json"), "--out", str(tmp_path / "s"), "--quiet"]) == 0
    assert time.perf_counter() - t <= 60.0
    assert len(load_suite(tmp_path / "s")) == 1000


def test_near_miss_within_the_gap_error_ends_the_case(tmp_path, capsys):
    """A flight that turns back 2.8e-15 below s = 0 (found by the fuzzer: our diffrax track took it for an
    impact with sdot -6.7e-6) cannot be told from a contact by a correct float64 implementation (gap error
    3e-14): the case stops before the impact that ends it, and says why."""
    args = [
        "case",
        "--alpha",
        "1.245",
        "--beta",
        "0.1",
        "--gamma",
        "0.1",
        "--r",
        "0.9",
        "--tau0",
        "5.951",
        "--sdot0",
        "0.135696112133537",
        "--impacts",
        "3",
        "--id",
        "m",
        "--out",
        str(tmp_path),
    ]
    capsys.readouterr()
    assert main(args) == 0
    s = _settings(tmp_path / "m")
    assert s["n_impacts"] == 0 and s["notes"]["truncation"]["requested_impacts"] == 3
    assert "turns back 2.8e-15 from a wall" in capsys.readouterr().err
    # a near miss well outside it (0024: 9.95e-10, 3e4 times the gap error) is kept
    inp = case_input("n", 0.5, 0.1, 0.1, 0.9, 3.0, 0.93996694232023, 10)
    assert build_user_case(inp).settings["n_impacts"] == 10


def test_a_case_is_certified_by_the_tracks_precision_schedule():
    """`case` certifies at the precision the certified track's schedule settles on (one mechanism): started at
    64 bits, too few for float64-tight enclosures, the schedule rises to 128 and the case is the one built
    from 320 bits byte for byte (on the base commit the case was certified at the fixed 64 bits given)."""
    inp = case_input("chaos", 2.2, 0.05, 0.3, 0.7, 1.0, 0.2, 10)
    low, default = build_user_case(inp, prec=64), build_user_case(inp)
    assert low.provenance["precision_bits"] == 128 and default.provenance["precision_bits"] == 320
    assert low.expected == default.expected and low.settings["tolerances"] == default.settings["tolerances"]
