"""The output writers (validation/io): one per format -- strict JSON (no NaN or inf: null), CSV with a
header and data rows only, NPZ into exactly the path given -- and the CLI's output options built on them
(issue 24 items 1-2, issue 23 items 6-8)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from gear_rattle.validation.io import csv_columns, csv_text, json_text, jsonable, write_csv, write_json, write_npz


def _strict(text: str):
    """A JSON parser that rejects NaN, Infinity and -Infinity (RFC 8259)."""

    def no(c):
        raise ValueError(f"{c} is not JSON")

    return json.loads(text, parse_constant=no)


def test_json_is_strict_and_keeps_numbers_exact():
    obj = {
        "nan": math.nan,
        "inf": np.inf,
        "minf": -math.inf,
        "np": np.float64(0.1),
        "i": np.int32(7),
        "arr": np.array([1.5, np.nan, 3.0]),
        "tup": (1, 2),
        3: "int key",
        "b": np.bool_(True),
        "none": None,
        "nested": [{"x": np.float32(np.nan)}],
    }
    back = _strict(json_text(obj))
    assert back["nan"] is None and back["inf"] is None and back["minf"] is None
    assert back["np"] == 0.1 and back["i"] == 7 and back["arr"] == [1.5, None, 3.0] and back["tup"] == [1, 2]
    assert back["3"] == "int key" and back["b"] is True and back["none"] is None and back["nested"] == [{"x": None}]
    x = 0.1 + 0.2  # shortest round trip: the same float64 comes back
    assert _strict(json_text([x]))[0] == x


def test_json_refuses_objects_that_are_not_data(tmp_path):
    with pytest.raises(TypeError, match="object"):
        jsonable({"a": object()})
    with pytest.raises(TypeError, match="complex"):
        jsonable(1 + 2j)
    assert not (tmp_path / "x.json").exists()
    write_json(tmp_path / "x.json", {"v": [math.nan]})
    assert (tmp_path / "x.json").read_text() == '{\n "v": [\n  null\n ]\n}\n'


def test_csv_has_a_header_and_data_rows_only(tmp_path):
    x = 1 / 3
    header, rows = csv_columns(
        {"eps": np.array([1e-9, x]), "n": np.array([3, 4], np.int64), "ok": [True, np.bool_(False)], "s": ["a,b", None]}
    )
    text = csv_text(header, rows)
    lines = text.splitlines()
    assert lines == ["eps,n,ok,s", '1e-09,3,True,"a,b"', f"{x!r},4,False,"]
    assert float(lines[2].split(",")[0]) == x  # repr: exact round trip, never "np.float64(...)"
    with pytest.raises(ValueError, match="fields"):
        csv_text(["a", "b"], [[1]])
    with pytest.raises(ValueError, match="lengths"):
        csv_columns({"a": [1, 2], "b": [1]})
    write_csv(tmp_path / "t.csv", ["a"], [[np.float64(2.5)]])
    assert (tmp_path / "t.csv").read_text() == "a\n2.5\n"


def test_npz_is_written_to_exactly_the_path_given(tmp_path):
    for name in ("data.npz", "data.bin", "data"):
        p = write_npz(tmp_path / name, a=np.arange(3), b=np.float64(0.5))
        assert p == tmp_path / name and p.exists()
        z = np.load(p)
        assert np.array_equal(z["a"], np.arange(3)) and float(z["b"]) == 0.5
    assert sorted(f.name for f in tmp_path.iterdir()) == ["data", "data.bin", "data.npz"]


def test_cli_output_npz_and_pure_csv(tmp_path, capsys):
    """``--output x.npz`` writes a real NPZ, ``--output x.csv`` (and stdout) pure CSV, through the one
    output helper of the commands."""
    from gear_rattle.validation.cli import main

    base = ["lyapunov", "--impacts", "300", "--transient", "10", "--quiet"]
    assert main(base + ["--output", str(tmp_path / "l.npz")]) == 0
    z = np.load(tmp_path / "l.npz")
    assert {"values", "lam", "lam_free", "n_stuck"} <= set(z.files) and z["lam"].shape == (1, 2)
    assert main(base + ["--output", str(tmp_path / "l.csv")]) == 0
    header, row = (tmp_path / "l.csv").read_text().splitlines()
    assert header.startswith("r,lambda1,lambda2") and float(row.split(",")[1]) == float(z["lam"][0, 0])
    capsys.readouterr()
    assert main(base) == 0
    assert capsys.readouterr().out == (tmp_path / "l.csv").read_text()
