"""Golden conformance suite: case folders, certification, and ``gear-rattle check``."""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pytest

from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.suite import (
    DEFAULT_SUITE, RADIUS_COLUMNS, TWO_PI, case_ids, load_case, load_suite, read_sequence,
)

CASES = case_ids()


def test_suite_covers_the_required_situations():
    tags = set()
    for cid in CASES:
        tags |= set(load_case(DEFAULT_SUITE / cid).settings["tags"])
    assert 8 <= len(CASES) <= 12
    for t in ("regular", "chaotic", "grazing", "chatter", "sticking", "stuck-forever", "small-beta",
              "return-to-start-wall", "negative-gamma", "free-flight"):
        assert t in tags, t


@pytest.mark.parametrize("cid", CASES)
def test_case_folder_is_well_formed(cid):
    folder = DEFAULT_SUITE / cid
    assert {p.name for p in folder.iterdir()} == {"settings.json", "expected.csv", "provenance.json"}
    case = load_case(folder)  # strict parse: header, numbers, row count
    s, e = case.settings, case.expected
    assert s["id"] == cid and len(e) == s["expected_rows"]
    prov = json.loads((folder / "provenance.json").read_text())
    assert prov["id"] == cid and prov["precision_bits"] >= 256 and len(prov["rows"]) == len(e)
    assert prov["status"] == s["expected_status"]
    assert {"python-flint", "numpy", "jax"} <= set(prov["software"])
    # both tracks agreed with the certified values when the case was generated
    for tr in ("map", "scipy"):
        assert prov["tracks_agreement"][tr]["agrees"] is True
    # certified bounds are far below the tolerances
    tol = min(v["abs"] for v in s["tolerances"].values())
    for c in RADIUS_COLUMNS:
        r = e.extra[c]
        assert np.all(np.nan_to_num(r) <= 1e-3 * tol)
    assert float(prov["radius"]["ball"]["tau_max"]) < 1e-40
    # model conventions: time order, wall codes and pre-impact velocity signs, phase, sticking rows
    assert np.all(np.diff(e.tau) >= 0) and np.all(np.diff(e.n) >= 0)
    imp = e.kind == "impact"
    assert np.all(e.sdot[imp & (e.wall == 0)] > 0) and np.all(e.sdot[imp & (e.wall == -1)] < 0)
    assert np.all(np.isnan(e.sdot[~imp]))
    assert np.all((e.tau_mod_2pi >= 0) & (e.tau_mod_2pi < TWO_PI))
    d = np.abs(np.mod(e.tau, TWO_PI) - e.tau_mod_2pi)
    assert np.all(np.minimum(d, TWO_PI - d) <= 1e-12 * (1 + np.abs(e.tau)))
    kinds = list(e.kind)
    for i, k in enumerate(kinds):
        if k == "stick":
            if i + 1 < len(kinds):
                assert kinds[i + 1] == "release" and e.wall[i + 1] == e.wall[i]
            else:
                assert s["expected_status"] == "stuck_forever"
    if s["expected_status"] == "active":
        assert int(e.n[-1]) == s["n_impacts"]


@pytest.fixture(scope="module")
def map_outputs(tmp_path_factory):
    out = tmp_path_factory.mktemp("map_outputs")
    rc = main(["check", "--self", "--track", "map", "--write", str(out), "--quiet"])
    return rc, out


def test_map_track_passes_every_case(map_outputs, capsys):
    rc, out = map_outputs
    assert rc == 0
    assert sorted(p.stem for p in out.glob("*.csv")) == CASES
    # and the written files score the same through the file path
    assert main(["check", str(out)]) == 0
    table = capsys.readouterr().out
    assert f"{len(CASES)}/{len(CASES)} cases pass" in table


#: float64 error budget of the map track (absolute): the map's values must lie within the certified
#: enclosure widened by this (100x tighter than the loosest case tolerance used for the map).
MAP_SLACK = 2e-11


def test_certified_enclosures_contain_the_map_values(map_outputs):
    _, out = map_outputs
    for case in load_suite():
        got = read_sequence(out / f"{case.id}.csv", expected_rows=len(case.expected))
        e = case.expected
        assert list(got.kind) == list(e.kind) and np.array_equal(got.wall, e.wall) and np.array_equal(got.n, e.n)
        for c, rc in (("tau", "tau_radius"), ("sdot", "sdot_radius")):
            a, b, r = getattr(got, c), getattr(e, c), e.extra[rc]
            m = ~np.isnan(b)
            assert np.all(np.abs(a[m] - b[m]) <= r[m] + MAP_SLACK * (1 + np.abs(b[m]))), (case.id, c)


def test_corrupted_output_fails(map_outputs, tmp_path, capsys):
    _, out = map_outputs
    bad = tmp_path / "bad"
    shutil.copytree(out, bad)
    f = bad / "0001-regular-fig2.csv"
    lines = f.read_text().splitlines()
    fields = lines[5].split(",")
    fields[1] = repr(float(fields[1]) + 1e-6)
    lines[5] = ",".join(fields)
    f.write_text("\n".join(lines) + "\n")
    capsys.readouterr()
    assert main(["check", str(bad)]) == 1
    o = capsys.readouterr().out
    assert "0001-regular-fig2" in o and "FAIL" in o and "line 6" in o
    assert o.count("FAIL") == 1
    # a wrong event kind fails the exact columns
    g = bad / "0002-chaotic-fig3.csv"
    g.write_text(g.read_text().replace("impact\n", "stick\n", 1))
    assert main(["check", str(bad), "--cases", "0002-chaotic-fig3"]) == 1
    assert "MISMATCH" in capsys.readouterr().out


def _one_line_error(capsys, *needles):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    for n in needles:
        assert n in err[0], (n, err[0])
    assert "Traceback" not in err[0]


@pytest.mark.parametrize("kind", ["missing_column", "wrong_header", "non_numeric", "missing_file",
                                  "bad_kind", "empty_sdot_on_impact"])
def test_malformed_files_exit_2_with_one_line(map_outputs, tmp_path, capsys, kind):
    _, out = map_outputs
    cid = "0003-free-flight-start"
    d = tmp_path / kind
    d.mkdir()
    shutil.copy(out / f"{cid}.csv", d / f"{cid}.csv")
    f = d / f"{cid}.csv"
    lines = f.read_text().splitlines()
    needles = [f"{cid}.csv"]
    if kind == "missing_column":
        lines = [",".join(x.split(",")[:4] + x.split(",")[5:]) for x in lines]
        needles += ["line 1", "sdot"]
    elif kind == "wrong_header":
        lines[0] = "n,tau_mod_2pi,tau,wall,sdot,kind"
        needles += ["line 1", "header"]
    elif kind == "non_numeric":
        lines[4] = lines[4].replace(lines[4].split(",")[4], "fast", 1)
        needles += ["line 5", "sdot", "fast"]
    elif kind == "missing_file":
        f.unlink()
        needles += ["missing file"]
    elif kind == "bad_kind":
        lines[3] = lines[3].rsplit(",", 1)[0] + ",bounce"
        needles += ["line 4", "bounce"]
    elif kind == "empty_sdot_on_impact":
        p = lines[2].split(",")
        p[4] = ""
        lines[2] = ",".join(p)
        needles += ["line 3", "sdot"]
    if f.exists():
        f.write_text("\n".join(lines) + "\n")
    capsys.readouterr()
    assert main(["check", str(d), "--cases", cid]) == 2
    _one_line_error(capsys, *needles)


def test_check_usage_errors(tmp_path, capsys):
    assert main(["check"]) == 2
    _one_line_error(capsys, "PATH")
    assert main(["check", str(tmp_path), "--self"]) == 2
    _one_line_error(capsys, "not both")
    assert main(["check", str(tmp_path / "nope")]) == 2
    _one_line_error(capsys, "not a directory")
    assert main(["check", "--self", "--suite", str(tmp_path / "nosuite")]) == 2
    _one_line_error(capsys, "nosuite")
    assert main(["check", "--self", "--cases", "9999-nothing"]) == 2
    _one_line_error(capsys, "9999-nothing")
    with pytest.raises(SystemExit) as ex:
        main(["check", "--self", "--track", "euler"])
    assert ex.value.code == 2


def test_check_self_reports_unavailable_track(monkeypatch, capsys):
    import importlib

    real = importlib.import_module

    def fake(name, *a, **k):
        if name == "gear_rattle.reference.diffrax_track":
            raise ImportError("No module named 'diffrax'")
        return real(name, *a, **k)

    monkeypatch.setattr(importlib, "import_module", fake)
    assert main(["check", "--self", "--track", "diffrax", "--cases", "0008-stuck-forever"]) == 2
    _one_line_error(capsys, "diffrax", "not available")


def test_other_suite_directory(tmp_path, map_outputs, capsys):
    _, out = map_outputs
    suite = tmp_path / "suite"
    shutil.copytree(DEFAULT_SUITE / "0008-stuck-forever", suite / "0008-stuck-forever")
    assert main(["check", str(out), "--suite", str(suite)]) == 0
    assert "1/1 cases pass" in capsys.readouterr().out


# ---------------------------------------------------------------------------------------------
# certification


@pytest.mark.parametrize("cid", ["0003-free-flight-start", "0008-stuck-forever", "0005-near-miss-return"])
def test_recertification_reproduces_the_committed_files(cid):
    pytest.importorskip("flint")
    from gear_rattle.validation.golden.generate import build_case, spec_from_settings

    folder = DEFAULT_SUITE / cid
    settings = json.loads((folder / "settings.json").read_text())
    s, text, prov = build_case(spec_from_settings(settings), tracks=False)
    assert text == (folder / "expected.csv").read_text()
    assert s == settings
    committed = json.loads((folder / "provenance.json").read_text())
    assert prov["rows"] == committed["rows"] and prov["radius"] == committed["radius"]


def test_certified_first_impact_agrees_with_50_digit_bisection():
    """Independent check of one enclosure: dense sampling + bisection at 50 digits (tests/mpref.py)."""
    mp = pytest.importorskip("mpmath")
    pytest.importorskip("flint")
    from flint import arb

    from gear_rattle.mapimpl.params import Params
    from tests.mpref import first_root
    from gear_rattle.validation.golden import certify as C

    p = Params(0.5, 0.1, 0.1, 0.9)
    with C.precision(256):
        c = C.certified_flight(C.Model(p), arb(0.0), 0.0, arb(-p.r * 0.5))
        t_ref, wall, v_ref = first_root(0.0, 0.0, -p.r * 0.5, p.alpha, p.beta, p.gamma, t_hi=10.0, n=2000)
        assert c.wall == wall
        assert abs(mp.mpf(c.t.mid().str(60, radius=False)) - t_ref) <= float(c.t.rad()) + 1e-45
        assert abs(mp.mpf(c.v.mid().str(60, radius=False)) - v_ref) <= float(c.v.rad()) + 1e-44
        assert float(c.t.rad()) < 1e-70


def test_certification_refuses_what_it_cannot_prove():
    pytest.importorskip("flint")
    from flint import arb

    from gear_rattle.mapimpl.params import Params
    from gear_rattle.validation.golden import certify as C

    p = Params(0.5, 0.1, 0.1, 0.9)
    with C.precision(128):
        m = C.Model(p)
        # moving into the wall it starts on: no departure certificate
        with pytest.raises(C.CertificationError, match="departure"):
            C.certified_flight(m, arb(0.0), 0.0, arb(0.3))
        # a state box so wide that the flight cannot be separated from the walls
        with pytest.raises(C.CertificationError):
            C.certified_flight(m, arb(0.0, 3.0), 0.0, arb(-0.45, 0.4))
    with pytest.raises(ValueError, match="n_impacts"):
        C.certify_orbit(p, 0.0, 0.5, -1)
    with pytest.raises(ValueError, match="prec"):
        C.certify_orbit(p, 0.0, 0.5, 1, prec=8)
    with pytest.raises(ValueError, match="sdot0"):
        C.certify_orbit(p, 0.0, 0.0, 1)
    with pytest.raises(ValueError, match="s0"):
        C.certify_orbit(p, 0.0, 0.1, 1, s0=0.5)


def test_release_times_are_zeros_of_the_contact_force():
    """Sticking rows: the release phase is the closed-form zero of f = gamma - R sin(tau - phi)."""
    case = load_case(DEFAULT_SUITE / "0007-chatter-sticking")
    p = case.settings["params"]
    e = case.expected
    rel = e.tau[e.kind == "release"]
    assert rel.size >= 1
    f = -p["alpha"] * np.sin(rel) + p["alpha"] * p["beta"] * np.cos(rel) + p["gamma"]
    assert np.all(np.abs(f) < 1e-13)
    # sticking happens within STICK_TIME of the preceding impact
    idx = np.nonzero(e.kind == "stick")[0]
    assert np.all(e.tau[idx] - e.tau[idx - 1] <= case.settings["stick_time"])
    assert math.isclose(case.settings["stick_time"], 1e-6)


def test_missing_event_fails_the_case(map_outputs, tmp_path, capsys):
    """A well-formed output with one event fewer (e.g. a missed impact) is a failed case (exit 1),
    not a malformed file."""
    _, out = map_outputs
    cid = "0007-chatter-sticking"
    d = tmp_path / "short"
    d.mkdir()
    lines = (out / f"{cid}.csv").read_text().splitlines()
    (d / f"{cid}.csv").write_text("\n".join(lines[:-1]) + "\n")
    capsys.readouterr()
    assert main(["check", str(d), "--cases", cid]) == 1
    assert "wrong number of events" in capsys.readouterr().out
