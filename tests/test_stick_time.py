"""The sticking policy's threshold ``stick_time`` is a parameter of every track (issue 36 item 4): the map,
scipy and diffrax tracks and the certified track take it through :func:`gear_rattle.mapimpl.tracks.orbit`,
agree on it, and so do ``trackimpl`` (our tracks under the fuzz protocol), ``simulate --stick-time`` and
``case --stick-time`` (one range, the library's: ``0 <= stick_time <= MAX_STICK_TIME``)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gear_rattle.core.params import Params
from gear_rattle.mapimpl.sticking import MAX_STICK_TIME, STICK_TIME
from gear_rattle.mapimpl.tracks import orbit
from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.rules.thresholds import stick_ratio_sdot0
from gear_rattle.validation.golden.oracle.inputs import case_input
from gear_rattle.validation.golden.oracle.ondemand import build_user_case, write_user_case
from gear_rattle.validation.golden.formats.cases import load_case
from gear_rattle.validation.golden.scoring.cases import score_file

#: Case 0007's chatter (upper wall), impact 0 at tau0 = 0 with the accumulation time t_acc = 3e-5: it sticks
#: at once for stick_time >= 3e-5, after a few bounces below (t_acc halves at each bounce: r = 0.5).
CHATTER = Params(2.0, 0.1, 1.0, 0.5)
T_ACC = 3e-5
SDOT0 = stick_ratio_sdot0(CHATTER, 0.0, 0, T_ACC / STICK_TIME)
IMPACTS = 12


def _bounces_before_stick(seq) -> int:
    """Impact rows before the first stick row."""
    kinds = list(seq.kind)
    return kinds[: kinds.index("stick")].count("impact") if "stick" in kinds else -1


@pytest.mark.parametrize("stick_time", [1e-5, 1e-4, 1e-3])
def test_every_track_takes_stick_time_and_agrees(stick_time):
    """At a threshold other than 1e-6 the four tracks give the same events (kinds, walls) and the float64 ones
    lie within 1e-9 of the certified values; the chatter sticks at once above t_acc and after bounces below,
    and at 1e-5 later than at 1e-4 but earlier than at the default (on the old code, the map track refused the
    option and the numerical tracks did not take it)."""
    seqs = {t: orbit(CHATTER, 0.0, SDOT0, IMPACTS, track=t, stick_time=stick_time) for t in ("map", "scipy", "diffrax")}
    cert = orbit(CHATTER, 0.0, SDOT0, IMPACTS, track="certified", stick_time=stick_time)
    default = orbit(CHATTER, 0.0, SDOT0, IMPACTS, track="map")
    bounces = _bounces_before_stick(cert)
    assert bounces == (1 if stick_time >= T_ACC else 3)  # impact 0 counted
    assert _bounces_before_stick(default) > 3
    for name, seq in seqs.items():
        assert list(seq.kind) == list(cert.kind) and list(seq.wall) == list(cert.wall), name
        assert np.nanmax(np.abs(seq.tau - cert.tau)) < 1e-9, name
        assert np.nanmax(np.abs(np.nan_to_num(seq.sdot) - np.nan_to_num(cert.sdot))) < 1e-9, name
        assert seq.meta["stick_time"] == stick_time, name
    assert "stick_time" not in default.meta  # an orbit under the default writes what it wrote before


@pytest.mark.parametrize("track", ["map", "scipy", "diffrax", "certified"])
@pytest.mark.parametrize("bad", [-1e-9, 0.5, float("nan")])
def test_stick_time_out_of_range_is_refused_naming_it(track, bad):
    with pytest.raises(ValueError, match=r"stick_time=.* is out of range: allowed .*0\.01"):
        orbit(CHATTER, 0.0, SDOT0, 3, track=track, stick_time=bad)


def test_trackimpl_runs_a_case_of_another_threshold(tmp_path):
    """A case built at stick_time = 1e-4 (it sticks at impact 0) runs on our tracks under the fuzz protocol and
    passes the scorer (the old trackimpl refused any threshold but 1e-6: exit 2)."""
    from gear_rattle.validation.commands import trackimpl

    case = build_user_case(case_input("st", *CHATTER.as_dict().values(), 0.0, SDOT0, 10, stick_time=1e-4))
    assert case.settings["stick_time"] == 1e-4 and "stick" in case.expected
    folder = write_user_case(tmp_path / "suite", case)
    given = tmp_path / "given" / "st"
    given.mkdir(parents=True)
    (given / "settings.json").write_text(json.dumps(case.settings))
    for track in ("map", "scipy"):
        assert trackimpl.main(["--track", track, str(tmp_path / "given"), str(tmp_path / track)]) == 0
        assert score_file(load_case(folder), tmp_path / track / "st.csv").passed, track


def test_simulate_takes_stick_time(tmp_path, capsys):
    """``simulate --stick-time``: the chatter sticks at impact 0 at 1e-4 (not at the default), on the map and
    certified tracks alike; out of the library's range, one line and exit 2."""
    base = ["simulate", "--alpha", "2", "--beta", "0.1", "--gamma", "1", "--r", "0.5", "--tau0", "0"]
    base += ["--sdot0", repr(SDOT0), "--impacts", "4", "--format", "json", "--quiet"]
    rows = {}
    for name, extra in (("default", []), ("map", ["--stick-time", "1e-4"]), ("cert", ["--stick-time", "1e-4"])):
        track = ["--track", "certified"] if name == "cert" else []
        assert main([*base, *extra, *track, "--output", str(tmp_path / f"{name}.json")]) == 0
        rows[name] = [e["kind"] for e in json.loads((tmp_path / f"{name}.json").read_text())["events"]]
    assert rows["map"][1] == "stick" == rows["cert"][1] and rows["default"][1] == "impact"
    capsys.readouterr()
    with pytest.raises(SystemExit) as e:
        main([*base, "--stick-time", "0.5"])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--stick-time" in err[0] and f"{MAX_STICK_TIME:g}" in err[0]


def test_case_stick_time_range_is_the_librarys(tmp_path, capsys):
    """``case --stick-time`` and ``--from``'s ``stick_time`` accept what the tracks take (up to 1e-2) and no
    more (the old range was 0 ... 1, which the certified track then refused)."""
    with pytest.raises(ValueError, match=r"stick_time=0\.5 is out of range: allowed .*0\.01"):
        case_input("x", 2.0, 0.1, 1.0, 0.5, 0.0, 0.5, 3, stick_time=0.5)
    assert case_input("x", 2.0, 0.1, 1.0, 0.5, 0.0, 0.5, 3, stick_time=MAX_STICK_TIME).stick_time == 1e-2
    args = ["case", "--alpha", "2", "--beta", "0.1", "--gamma", "1", "--r", "0.5", "--tau0", "0", "--sdot0", "0.5"]
    with pytest.raises(SystemExit) as e:
        main([*args, "--impacts", "3", "--id", "x", "--out", str(tmp_path), "--stick-time", "0.5"])
    assert e.value.code == 2 and "--stick-time=0.5 is out of range" in capsys.readouterr().err
