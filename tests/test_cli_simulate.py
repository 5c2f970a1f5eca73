"""CLI `gear-rattle simulate`: output formats, plot (Figs. 2-3), and one-line errors with exit 2."""

import csv
import io
import json
import subprocess
import sys

import numpy as np
import pytest

from gear_rattle.validation.cli import main


def run_cli(args, capsys):
    rc = main(args)
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_csv_rows(capsys):
    rc, out, _ = run_cli(["simulate", "--alpha", "3", "--impacts", "20"], capsys)
    assert rc == 0
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 21
    assert list(rows[0]) == ["n", "tau", "tau_mod_2pi", "wall", "sdot", "kind"]
    tau = np.array([float(r["tau"]) for r in rows])
    assert np.all(np.diff(tau) > 0)
    for r in rows:
        assert r["wall"] in ("0", "-1") and r["kind"] == "impact"
        assert (float(r["sdot"]) > 0) == (r["wall"] == "0")
        assert abs(float(r["tau_mod_2pi"]) - float(r["tau"]) % (2 * np.pi)) < 1e-12


def test_json_and_files(tmp_path, capsys):
    out = tmp_path / "o.json"
    png = tmp_path / "fig.png"
    rc, _, _ = run_cli(
        ["simulate", "--alpha", "0.5", "--impacts", "30", "--format", "json", "--output", str(out), "--plot", str(png)],
        capsys,
    )
    assert rc == 0
    d = json.loads(out.read_text())
    assert d["params"]["alpha"] == 0.5 and len(d["events"]) == 31
    assert png.stat().st_size > 10_000


def test_sticking_rows(capsys):
    rc, out, _ = run_cli(["simulate", "--alpha", "2", "--gamma", "1", "--r", "0.5", "--impacts", "150"], capsys)
    kinds = [r["kind"] for r in csv.DictReader(io.StringIO(out))]
    assert rc == 0 and "stick" in kinds and "release" in kinds


@pytest.mark.parametrize(
    "args,needle",
    [
        (["--r", "1.5"], "parameter r=1.5"),
        (["--beta", "0"], "parameter beta=0"),
        (["--alpha", "-1"], "parameter alpha=-1"),
        (["--gamma", "inf"], "parameter gamma=inf"),
        (["--impacts", "-2"], "--impacts"),
        (["--sdot0", "0"], "sdot0"),
        (["--s0", "0.3"], "s0"),
        (["--track", "rk4"], "--track"),
    ],
)
def test_bad_input_one_line_exit_2(args, needle, capsys):
    with pytest.raises(SystemExit) as e:
        rc = main(["simulate", *args])
        raise SystemExit(rc)
    err = capsys.readouterr().err
    assert e.value.code == 2
    assert needle in err
    assert len(err.strip().splitlines()) == 1
    assert "Traceback" not in err


def test_console_script_no_traceback():
    p = subprocess.run(
        [sys.executable, "-m", "gear_rattle.validation", "simulate", "--r", "2"], capture_output=True, text=True
    )
    assert p.returncode == 2
    assert p.stderr.strip().count("\n") == 0 and "allowed 0 < r <= 1" in p.stderr


def test_ended_orbit_is_reported(capsys):
    """An orbit that stops (here: alpha = gamma = 0, it coasts to rest) is said on stderr, not silent."""
    rc, out, err = run_cli(["simulate", "--alpha", "0", "--gamma", "0", "--s0", "-0.5", "--sdot0", "0.01"], capsys)
    assert rc == 0 and out.strip() == "n,tau,tau_mod_2pi,wall,sdot,kind"
    assert "status no_impact" in err
    # it made no impact at all: said so, not "after -1 impacts" (found by the oracle's tests, issue 31)
    assert "ended before its first impact" in err and "-1" not in err
