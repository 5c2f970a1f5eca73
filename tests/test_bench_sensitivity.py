"""The sensitivity benchmark's pieces (benchmarks/bench_sensitivity.py, issue 36 item 3): the search of the smallest
detected size, the reading of both fuzzers' summaries, and one tiny configuration run end to end (one class, two
sizes, the suite only) with its JSON and figure."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import bench_sensitivity as bench  # noqa: E402


@pytest.mark.parametrize("n", range(1, 10))
def test_search_finds_the_last_detected_index_from_any_guess(n):
    """For every threshold (-1: nothing detected) and every guess, the answer, each index asked at most once and
    no more than 2 log2(n) + 2 questions."""
    for k in range(-1, n):
        for guess in range(n):
            asked: list[int] = []

            def detect(i, k=k, asked=asked):
                asked.append(i)
                return i <= k

            assert bench.search(detect, n, guess) == k, (n, k, guess)
            assert len(asked) == len(set(asked)), (n, k, guess, asked)
            assert len(asked) <= 2 * n.bit_length() + 2, (n, k, guess, asked)


def test_findings_of_both_fuzzers_and_what_counts_as_detected():
    """Today's fuzzer reports groups with a signature, the former one failures without: both read; a timeout or
    crash is no detection of a planted error."""
    new = {"groups": [{"signature": {"kind": "timeout", "text": "a timeout"}, "scenario": "long-flight"}]}
    new["groups"].append({"signature": {"kind": "value", "text": "tau"}, "scenario": "paper", "found_after_s": 3.0})
    old = {"failures": [{"scenario": "graze", "message": "first failing: tau", "found_after_s": 2.0}]}
    got = bench._findings(new)
    assert [f["kind"] for f in got] == ["timeout", "value"] and got[1]["scenario"] == "paper"
    assert bench._findings(old) == [
        {
            "kind": "value",
            "signature": None,
            "scenario": "graze",
            "message": "first failing: tau",
            "found_after_s": 2.0,
            "input": None,
        }
    ]
    assert [f["kind"] in bench.NOT_SCORED for f in got] == [True, False]


def test_sizes_are_ordered_as_the_class_grid_and_checked():
    assert bench._sizes(["digits=16,10,12"]) == {"digits": (10.0, 12.0, 16.0)}
    assert bench._sizes(["restitution=1e-15,1e-9"]) == {"restitution": (1e-9, 1e-15)}
    with pytest.raises(SystemExit, match="--sizes 'nope=1'"):
        bench._sizes(["nope=1"])
    for c in bench.CLASSES.values():  # every grid runs from the largest error to the smallest
        err = [-x if c.name == "digits" else x for x in c.grid]
        assert err == sorted(err, reverse=True), c.name
        assert c.float64 < c.target if c.name != "digits" else c.float64 > c.target


def test_one_class_two_sizes_suite_only(tmp_path):
    """restitution 1e-9 fails every shipped case, 1e-15 none: the smallest detected is 1e-9; the JSON holds both
    runs and the figure is a PNG (a class the suite never detects is drawn too)."""
    out, fig = tmp_path / "s.json", tmp_path / "s.png"
    argv = ["--classes", "restitution", "--sizes", "restitution=1e-9,1e-15", "--no-fuzz", "--no-control"]
    assert bench.main([*argv, "--checkout", f"after={ROOT}", "--out", str(out), "--figure", str(fig)]) == 0
    res = json.loads(out.read_text())
    suite = res["classes"]["restitution"]["results"]["after"]["suite"]
    assert suite["smallest_detected"] == 1e-9
    assert [(e["size"], e["detected"]) for e in suite["evaluated"]] == [(1e-9, True), (1e-15, False)]
    assert len(suite["evaluated"][0]["failing"]) == 25 and suite["evaluated"][1]["failing"] == []
    assert len(res["runs"]) == 2 and res["checkouts"]["after"]["version"].startswith("gear-rattle")
    assert fig.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    res["classes"]["restitution"]["results"]["after"]["suite"]["smallest_detected"] = None
    res["classes"]["restitution"]["results"]["after"]["fuzz"] = {"smallest_detected": 1e-15}
    (tmp_path / "t.json").write_text(json.dumps(res))
    assert bench.main(["--plot-only", str(tmp_path / "t.json"), "--figure", str(tmp_path / "t.png")]) == 0
    assert (tmp_path / "t.png").read_bytes()[:4] == b"\x89PNG"


FIELDS = {
    "restitution": "restitution",
    "two-pi": "two_pi",
    "forcing": "forcing",
    "digits": "digits",
    "fixed-step": "step",
    "contact-tolerance": "contact_tol",
    "gap-scale": "gap_scale",
}


def test_every_size_of_every_class_names_a_mutant_of_that_size():
    """tests/mutant_impl.py knows each class's mutant at each size of its grid, with that one field changed
    (contact-tolerance-T of any T: the mutation test's two tolerances only, before this benchmark)."""
    from golden_mutants import BASE
    from mutant_impl import mutant

    assert set(FIELDS) == set(bench.CLASSES)
    for name, c in bench.CLASSES.items():
        for x in c.grid:
            m = mutant(c.mutant(x))
            assert getattr(m, FIELDS[name]) == x, (name, x)
            changed = [f for f in FIELDS.values() if getattr(m, f) != getattr(BASE, f)]
            assert changed == [FIELDS[name]] or (name == "gap-scale" and x == 1.0), (name, x, changed)


def test_fuzz_on_names_the_checkouts_the_fuzzer_runs_on():
    """--fuzz-on after: the suite on every checkout, the fuzzer on those named; a name that is no checkout is an
    error naming the option."""
    cos = [bench.checkout(f"before={ROOT}"), bench.checkout(f"after={ROOT}")]
    b = bench.Bench(bench.parse(["--fuzz-on", "after", "--out", ""]), cos, None)
    assert [b.fuzzes(co) for co in cos] == [False, True]
    b = bench.Bench(bench.parse(["--out", ""]), cos, None)
    assert [b.fuzzes(co) for co in cos] == [True, True]
    b = bench.Bench(bench.parse(["--no-fuzz", "--fuzz-on", "after", "--out", ""]), cos, None)
    assert [b.fuzzes(co) for co in cos] == [False, False]
    with pytest.raises(SystemExit, match="--fuzz-on: \\['today'\\]"):
        bench.main(["--checkout", f"after={ROOT}", "--fuzz-on", "today", "--out", ""])
