"""The command line keeps its promises (issue 23): stdout carries only the result (CSV or strict JSON
that a program can parse), notes go to stderr, every JSON file is strict (no NaN), --output's format
comes from its extension, bad input is one line with exit status 2 and nothing written -- over every
subcommand, table-driven -- and no library module prints to stdout.

In-process (``main([...])``) and small: the few commands that compute use a handful of orbits."""

from __future__ import annotations

import ast
import csv
import io
import json
import math
from pathlib import Path

import numpy as np
import pytest

from gear_rattle.validation.cli import main

ROOT = Path(__file__).resolve().parents[1]


def run_cli(args, capsys):
    try:
        rc = main(args)
    except SystemExit as e:  # refused while parsing
        rc = e.code
    out = capsys.readouterr()
    return rc, out.out, out.err


def strict_json(text: str):
    """json.loads refusing NaN and the infinities (RFC 8259)."""

    def refuse(name):
        raise ValueError(f"{name} in JSON")

    return json.loads(text, parse_constant=refuse)


def parse_csv(text: str) -> list[list[str]]:
    rows = list(csv.reader(io.StringIO(text)))
    assert rows and all(rows[0]) and all(len(r) == len(rows[0]) for r in rows), text[:300]
    return rows


# --------------------------------------------------------------------- no prints in the library

#: Where printing to stdout is the job: the command line (cli.py, cliutil.py, the commands).
CLI_FILES = ("validation/cli.py", "validation/cliutil.py")
CLI_DIRS = ("validation/commands",)


def stdout_prints(source: str) -> list[int]:
    """Lines that print to stdout (``print(...)`` without ``file=``, or to sys.stdout, and
    ``sys.stdout.write``) outside a ``main`` function (a ``python -m`` entry of its own)."""
    tree = ast.parse(source)
    mains = [n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef) and n.name == "main"]
    inside_main = {id(x) for m in mains for x in ast.walk(m)}
    bad = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call) or id(node) in inside_main:
            continue
        f = node.func
        if isinstance(f, ast.Name) and f.id == "print":
            target = next((k.value for k in node.keywords if k.arg == "file"), None)
            if target is None or ast.unparse(target) == "sys.stdout":
                bad.append(node.lineno)
        elif isinstance(f, ast.Attribute) and f.attr == "write" and ast.unparse(f.value) == "sys.stdout":
            bad.append(node.lineno)
    return bad


def library_modules(root: Path):
    for top in ("core", "mapimpl", "reference", "validation", "gear_rattle"):
        for p in sorted((root / top).rglob("*.py")):
            rel = p.relative_to(root).as_posix()
            if rel in CLI_FILES or rel.startswith(CLI_DIRS):
                continue
            yield rel, p


def test_no_library_module_prints_to_stdout():
    """Analyses, I/O, plots, the report and the library compute and return; only the command line (and
    a ``python -m`` entry's own ``main``) writes to stdout."""
    found = {rel: lines for rel, p in library_modules(ROOT) if (lines := stdout_prints(p.read_text()))}
    assert not found, found


def test_the_print_scan_finds_a_print():
    assert stdout_prints("def f():\n    print('x')\n") == [2]
    assert stdout_prints("import sys\ndef f():\n    sys.stdout.write('x')\n") == [3]
    assert stdout_prints("import sys\ndef f():\n    print('x', file=sys.stdout)\n") == [3]
    assert stdout_prints("import sys\ndef f():\n    print('x', file=sys.stderr)\n") == []
    assert stdout_prints("def main():\n    print('x')\n") == []


# ------------------------------------------------------------------ bad input: every subcommand

#: (arguments, text the one line must contain).  Each is refused before computing: exit 2, one line
#: on stderr, nothing on stdout, nothing written in the working directory.
BAD = [
    (["simulate", "--impacts", "-1"], "--impacts"),
    (["simulate", "--r", "2"], "r=2"),
    (["simulate", "--output", "x.svg"], ".csv, .json, .npz"),
    (["simulate", "--output", "x.csv", "--format", "json"], "--format=json"),
    (["simulate", "--output", ""], "empty"),
    (["simulate", "--plot", "x.bogus"], "--plot"),
    (["simulate", "--bogus"], "gear-rattle simulate: error: unrecognized arguments: --bogus"),
    (["report", "--sections", "nope"], "--sections"),
    (["report", "--out", ""], "--out=''"),
    (["report", "--seed", "-1"], "--seed"),
    (["bifurcation", "--lo", "0.5", "--hi", "2"], "--hi=2.0"),
    (["bifurcation", "--param", "alpha", "--lo", "1", "--hi", "1e308"], "--hi=1e+308"),
    (["bifurcation", "--values", "0"], "--values"),
    (["lyapunov", "--lo", "0.9", "--hi", "0.8"], "lo <= hi"),
    (["lyapunov", "--impacts", "0"], "--impacts"),
    (["orbit"], "{find,continue}"),
    (["orbit", "find", "--ds", "0.1", "--lo", "0.5"], "'continue' only"),
    (["orbit", "continue", "--lo", "0.95", "--hi", "1.0"], "around the starting --r=0.9"),
    (["orbit", "continue", "--hi", "1.5"], "--hi=1.5"),
    (["orbit", "find", "--tau0", "1"], "together"),
    (["timeseries", "--figure", "fig5", "--r", "0.5", "--alpha", "2"], "--alpha, --r"),
    (["timeseries", "--impacts", "1"], "--impacts"),
    (["basins", "--nx", "0"], "--nx"),
    (["basins", "--window", "1", "0", "0", "1"], "--window"),
    (["basins", "--out", ""], "--out=''"),
    (["uncertainty", "--points", "5"], "--points"),
    (["uncertainty", "--eps-min", "1e-3", "--eps-max", "1e-4"], "--eps-min"),
    (["transients", "--nx", "0"], "--nx"),
    (["transients", "--delta", "2"], "--delta"),
    (["transients", "--out", "/proc/x"], "does not accept new files"),
    (["atlas", "--n-alpha", "0"], "--n-alpha"),
    (["atlas", "--alpha-lo", "1e308"], "--alpha-lo"),
    (["atlas", "--store", "", "--scheduler", "serial"], "--store=''"),
    (["check"], "missing PATH"),
    (["check", ""], "PATH=''"),
    (["check", "p", "--out", "o"], "--out needs --self"),
    (["check", "--self", "--suite", "nowhere"], "not found"),
    (["case", "--out", "s", "--alpha", "1"], "missing --beta"),
    (["fuzz", "--impl", "x", "--budget", "0"], "--budget"),
]


@pytest.mark.parametrize("args,needle", BAD, ids=[" ".join(a) or "none" for a, _ in BAD])
def test_bad_input_is_one_line_exit_2_nothing_written(args, needle, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(args, capsys)
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert needle in err, err
    assert out == ""
    assert list(tmp_path.iterdir()) == []


def test_every_subcommand_is_in_the_table():
    from gear_rattle.validation.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    assert set(sub.choices) == {a[0] for a, _ in BAD}


# ------------------------------------------------------------------- stdout is the result

R08 = ["--r", "0.8", "--tau0", "6.0246", "--sdot0", "0.8276"]  # a guess of Fig. 4's stable 6-impact orbit


@pytest.mark.parametrize(
    "args",
    [
        ["simulate", "--impacts", "5"],
        ["simulate", "--impacts", "5", "--format", "json"],
        ["simulate", "--impacts", "5", "--track", "scipy"],
        ["timeseries", "--impacts", "40", "--transient", "10"],
        ["timeseries", "--impacts", "40", "--transient", "10", "--format", "json"],
        ["lyapunov", "--impacts", "50", "--transient", "10"],
        ["lyapunov", "--alpha", "0", "--impacts", "50", "--format", "json"],  # an orbit that ends: NaN -> null
        ["orbit", "find", *R08],
        ["orbit", "find", *R08, "--format", "json"],
    ],
    ids=lambda a: " ".join(a),
)
def test_stdout_parses(args, capsys):
    rc, out, err = run_cli(args, capsys)
    assert rc == 0, err
    if "json" in args:
        strict_json(out)
    else:
        parse_csv(out)
    assert all(line.startswith("gear-rattle ") for line in err.splitlines()), err  # notes, labelled


def test_lyapunov_of_an_orbit_that_ended_is_nan_with_a_note(capsys):
    """alpha = 0: the tooth sticks for ever after a few impacts; the exponents were reported as 0.0."""
    rc, out, err = run_cli(["lyapunov", "--alpha", "0", "--impacts", "50", "--format", "json"], capsys)
    d = strict_json(out)
    assert rc == 0 and d["lam"] == [[None, None]] and d["active"] == [False]
    assert "ended" in err and "NaN" in err


def test_orbit_find_writes_real_files_and_fails_in_one_line(tmp_path, capsys):
    """orbit find --output o.npz wrote text, o.csv had prose lines; a run that did not converge exited 1
    with nothing on stderr."""
    for ext in ("npz", "csv", "json"):
        assert main(["orbit", "find", *R08, "--output", str(tmp_path / f"o.{ext}")]) == 0
    err = capsys.readouterr().err
    assert "converged" in err and "multipliers" in err
    with np.load(tmp_path / "o.npz", allow_pickle=False) as z:
        assert z["tau_mod_2pi"].shape == (6,) and bool(z["converged"]) and z["multipliers"].shape == (2,)
    assert parse_csv((tmp_path / "o.csv").read_text())[0] == ["k", "tau_mod_2pi", "sdot", "wall"]
    assert strict_json((tmp_path / "o.json").read_text())["stable"] is True
    rc, out, err = run_cli(["orbit", "find", "--settle", "100", "--output", str(tmp_path / "n.csv")], capsys)
    assert rc == 1 and out == "" and len(err.splitlines()) == 1 and "did not converge" in err
    assert not (tmp_path / "n.csv").exists()


def test_output_format_from_the_extension(tmp_path, capsys):
    """simulate --output x.json wrote CSV (and .svg got CSV too)."""
    for ext in ("csv", "json", "npz"):
        assert main(["simulate", "--impacts", "4", "--output", str(tmp_path / f"s.{ext}")]) == 0
    assert parse_csv((tmp_path / "s.csv").read_text())[0][:2] == ["n", "tau"]
    assert len(strict_json((tmp_path / "s.json").read_text())["events"]) == 5
    with np.load(tmp_path / "s.npz", allow_pickle=False) as z:
        assert z["tau"].shape == (5,) and str(z["kind"][0]) == "impact"
    assert main(["simulate", "--impacts", "4", "--output", "/dev/null", "--format", "json"]) == 0  # no extension


def test_human_summary_on_a_terminal_json_elsewhere(monkeypatch, capsys):
    from gear_rattle.validation import cliutil

    cliutil.print_result({"x": math.nan}, ["x is not a number"], ["out/x.json"])
    assert strict_json(capsys.readouterr().out) == {"x": None}
    monkeypatch.setattr(cliutil, "is_terminal", lambda stream: True)
    cliutil.print_result({"x": 1.0}, ["x is one"], ["out/x.npz", "out/x.json"])
    out = capsys.readouterr().out
    assert out.startswith("x is one\n") and "out/x.json" in out and "out/x.npz" not in out and "{" not in out


# ----------------------------------------------------- strict JSON in every file a command writes


def _json_files(root: Path) -> list[Path]:
    return sorted(p for p in root.rglob("*.json"))


def test_every_json_file_is_strict(tmp_path, capsys):
    """10 of 25 JSON files of the issue's audit held a bare NaN.  Every JSON file these commands write
    parses with a parser that refuses NaN (and their stdout too)."""
    runs = [
        ["transients", "--nx", "5", "--cap", "300", "--out", str(tmp_path / "t"), "--quiet"],  # fits fail: null
        ["uncertainty", "--points", "10", "--n-eps", "3", "--ns", "50", "100", "--out", str(tmp_path / "u"), "--quiet"],
        ["simulate", "--alpha", "0", "--impacts", "20", "--output", str(tmp_path / "s.json")],
        ["lyapunov", "--alpha", "0", "--impacts", "20", "--output", str(tmp_path / "l.json")],
        ["check", "--self", "--orbits", "--cases", "orbit-3-impact-fig2-alpha0.5-r0.9", "--out", str(tmp_path / "c")],
    ]
    for args in runs:
        rc, out, err = run_cli(args, capsys)
        assert rc == 0, (args, err)
        if args[0] in ("transients", "uncertainty"):
            strict_json(out)
    files = _json_files(tmp_path)
    manifests = [f for f in files if f.name.endswith(".manifest.json")]  # one per --out folder (naming the run)
    assert len(files) - len(manifests) == 5 and len(manifests) == 3, files
    for f in files:
        strict_json(f.read_text())


def test_every_committed_json_file_is_strict():
    """The published report's crises.json held bare Infinity (written before the strict writer): every JSON
    file of the repository (the report, the golden cases, the benchmarks) parses with a parser that
    refuses NaN and the infinities."""
    files = [f for top in ("docs", "validation", "benchmarks", "tests") for f in (ROOT / top).rglob("*.json")]
    assert len(files) > 50, files  # the golden cases and the report are there
    for f in files:
        try:
            strict_json(f.read_text())
        except ValueError as e:
            pytest.fail(f"{f.relative_to(ROOT)}: {e}")


def test_report_json_is_strict_and_rerender_reads_null_back(tmp_path, monkeypatch):
    """summary.json and document.json went through json.dumps (a NaN value was written as NaN); now the
    strict writer, and rerender reads the report back."""
    import reportfake
    from gear_rattle.validation.report import builder
    from gear_rattle.validation.report.verdict import row

    fake = reportfake.fake_section

    def with_nan(ctx):
        sec = fake(ctx)
        sec.numbers.append(row("nan_row", "a value that is NaN", math.nan, math.nan, paper=None, tolerance=1.0))
        return sec

    monkeypatch.setattr(reportfake, "fake_section", with_nan)
    out = reportfake.build_fake_report(tmp_path / "r", monkeypatch)
    summary = strict_json((out / "summary.json").read_text())
    strict_json((out / "document.json").read_text())
    nan_row = next(n for n in summary["numbers"] if n["key"] == "nan_row")
    assert nan_row["value"] is None
    builder.rerender(out)
    assert (
        next(n for n in strict_json((out / "summary.json").read_text())["numbers"] if n["key"] == "nan_row")["value"]
        is None
    )


def test_an_interrupted_report_leaves_out_as_it_was(tmp_path, monkeypatch):
    """report interrupted left figures in --out: it writes into a folder beside it and moves in at the end."""
    import reportfake

    out = tmp_path / "r"
    out.mkdir()
    (out / "keep.txt").write_text("mine")

    fake = reportfake.fake_section

    def interrupted(ctx):
        fake(ctx)  # its figure is written
        raise KeyboardInterrupt

    monkeypatch.setattr(reportfake, "fake_section", interrupted)
    with pytest.raises(KeyboardInterrupt):
        reportfake.build_fake_report(out, monkeypatch)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r"]  # no staging folder left
    assert sorted(p.name for p in out.iterdir()) == ["keep.txt"]


# --------------------------------------------------------------------------- the library's errors


def test_library_arguments_name_themselves():
    import gear_rattle as gr
    from gear_rattle.core.params import Params

    p = Params(3.0, 0.1, 0.1, 0.9)
    with pytest.raises(TypeError, match="params is a dict"):
        gr.orbit({"alpha": 3}, 0.0, 0.5, 3)
    with pytest.raises(TypeError, match="alpha='3' is a str"):
        Params("3", 0.1, 0.1, 0.9)
    with pytest.raises(TypeError, match="r=True"):
        Params(3.0, 0.1, 0.1, True)
    with pytest.raises(ValueError, match="param"):
        gr.lyapunov(p, param="bogus")
    with pytest.raises(ValueError, match="tau0=nan"):
        gr.find_periodic(p, math.nan, 0.5, 6)
    with pytest.raises(TypeError, match="params is a dict"):  # the facade's name (mapimpl.lyapunov's is base)
        gr.lyapunov({"alpha": 3})
    with pytest.warns(DeprecationWarning, match="period"):
        gr.find_periodic(Params(3.0, 0.1, 0.1, 0.8), 6.0246, 0.8276, impacts=6)
    with pytest.warns(DeprecationWarning, match="n_impacts"):
        gr.lyapunov(p, n=50, transient=10)


def test_find_periodic_singular_step_and_divergence(monkeypatch):
    """A 1-impact orbit at alpha = 0.5 raised numpy's LinAlgError ('Singular matrix') from a diverged
    Newton iterate; Newton now stops there (not converged), and a singular step at the guess is a
    ValueError naming the guess."""
    import gear_rattle.mapimpl.periodic as P
    from gear_rattle.core.params import Params

    o = P.find_periodic(Params(0.5, 0.1, 0.1, 0.9), 0.0, 0.5, 1)
    assert not o.converged and np.all(np.isfinite([o.theta[0], o.sdot[0]]))
    real = P.pfold

    def identity_jacobian(*a, **k):
        tp, sp, J, walls, stuck, ok = real(*a, **k)
        return tp, sp, np.eye(2), walls, stuck, ok

    monkeypatch.setattr(P, "pfold", identity_jacobian)
    with pytest.raises(ValueError, match="singular"):
        P.find_periodic(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 6)
    # singular at a later iterate (orbit find --r 1 --alpha 1e10 was exit 2, 'allowed a guess ...', for a guess
    # it had not been given): Newton stops there, not converged
    calls = []

    def singular_after_the_first(*a, **k):
        tp, sp, J, walls, stuck, ok = real(*a, **k)
        calls.append(1)
        return tp, sp, (J if len(calls) == 1 else np.eye(2)), walls, stuck, ok

    monkeypatch.setattr(P, "pfold", singular_after_the_first)
    o = P.find_periodic(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 6)
    assert not o.converged and o.iterations == 2


def test_basins_mesh_keeps_the_profile_ratio():
    """basins --nx 120 gave 120 x 60 and --nx 121 gave 121 x 121."""
    from gear_rattle.validation.transient.settings import basins_mesh

    assert basins_mesh("quick", None, None) == (120, 60)
    assert basins_mesh("quick", 121, None) == (121, 60)
    assert basins_mesh("quick", 240, None) == (240, 120)
    assert basins_mesh("paper", 100, None) == (100, 100)
    assert basins_mesh("quick", 10, 7) == (10, 7)


# ------------------------------------------------------------- odd paths, extreme models, files


def test_stdout_that_cannot_be_written_is_one_line(tmp_path, monkeypatch, capsys):
    """`gear-rattle simulate > /dev/full` and a closed stdout (`>&-`) ended in tracebacks."""
    import sys

    monkeypatch.setattr(sys, "stdout", None)
    assert main(["simulate", "--impacts", "2"]) == 2
    full = open("/dev/full", "w")
    monkeypatch.setattr(sys, "stdout", full)
    try:
        assert main(["simulate", "--impacts", "2"]) == 2
    finally:
        monkeypatch.undo()
        full.close()
    err = capsys.readouterr().err.splitlines()
    assert "stdout is closed" in err[0] and "No space left on device" in err[1] and len(err) == 2


@pytest.mark.parametrize(
    "args,needle",
    [
        (["orbit", "find", "--gamma", "1e10", "--settle", "100"], "did not converge"),  # was 'Array must not ...'
        (["orbit", "continue", "--r", "1", "--settle", "100"], "did not converge"),  # exit 2 from the library
    ],
)
def test_extreme_models_fail_in_one_line(args, needle, capsys):
    rc, out, err = run_cli(args, capsys)
    assert rc == 1 and out == "" and len(err.splitlines()) == 1 and needle in err, err


def test_every_step_stuck_has_no_free_exponent():
    """beta = 1e10: every step sticks; the exponents of the free steps were 0.0 (no free step)."""
    import gear_rattle as gr

    res = gr.lyapunov(gr.Params(3.0, 1e10, 0.1, 0.9), n_impacts=50, transient=5, progress=False)
    assert res.n_stuck[0] == 50 and np.all(np.isneginf(res.lam)) and np.all(np.isnan(res.lam_free))


def test_paths_with_spaces_and_unicode(tmp_path, capsys):
    for name in ("a b/c d.csv", "ü/ß.json"):
        assert main(["simulate", "--impacts", "2", "--output", str(tmp_path / name)]) == 0
        assert (tmp_path / name).stat().st_size > 0


def test_every_numeric_option_states_its_range():
    """--help missed the ranges of --transient, --lo/--hi, --settle, --n-lo, --window, --eps-min and the
    atlas options: every option that takes a number says what is allowed."""
    import argparse
    import re

    from gear_rattle.validation.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    missing = []
    for name, sp in sub.choices.items():
        for a in sp._actions:
            numeric = a.type is float or getattr(a.type, "__name__", "") in ("integer", "number")
            if not numeric or a.help == argparse.SUPPRESS:
                continue
            if not re.search(r"<=|<|>=|>| to \d|\d to |!=|nonzero|finite", a.help):
                missing.append(f"{name} {a.option_strings[0]}: {a.help}")
    assert not missing, missing


@pytest.mark.parametrize(
    "text, value",
    [
        ("1000", 1000),
        ("1e3", 1000),
        ("2.0e1", 20),
        ("1_0", 10),
        (" 7", 7),
        ("0e5", 0),
        ("1.5", None),
        ("nan", None),
        ("inf", None),
        ("0x10", None),
        ("1e-400000", None),
        ("1e400000", "range"),
        ("-1e31", "range"),
    ],
)
def test_integer_options_take_exponent_notation(text, value):
    """--impacts 1e3 was refused ('not an integer'); an integral value in exponent notation is the integer,
    1.5 or nan is refused naming the range, 1e400000 is out of range (not converted)."""
    import argparse

    from gear_rattle.validation.cliutil import int_range

    conv = int_range("--impacts", 0, 10_000_000)
    if isinstance(value, int):
        assert conv(text) == value
    else:
        msg = "is out of range: allowed 0 <=" if value == "range" else "is not an integer: allowed 0 <="
        with pytest.raises(argparse.ArgumentTypeError, match=msg):
            conv(text)


@pytest.mark.parametrize("args", [["--r", "0.05"], ["--param", "alpha", "--alpha", "0.05"]])
def test_orbit_continue_default_bounds_are_in_range(args, capsys):
    """orbit continue --r 0.05 refused its own default '--lo=-0.05' (the value - 0.1): the defaults stay
    in the parameter's range, so the run gets past the bounds (to Newton)."""
    rc, out, err = run_cli(["orbit", "continue", *args, "--settle", "20", "--max-points", "2", "--quiet"], capsys)
    assert "--lo" not in err and "--hi" not in err and rc in (0, 1), err
