"""The certified track on demand (issue 31 item 1): ``mapimpl.certified.track.certified_orbit``,
``gr.orbit(track="certified")`` and ``gear-rattle simulate --track certified``.

Every test is cheap (under a few seconds); the long chaotic runs are in ``benchmarks/bench_certified.py``.
"""

from __future__ import annotations

import json
import math

import mpmath as mp
import numpy as np
import pytest

import gear_rattle as gr
from gear_rattle.core.paper import PAPER_PARAMS
from gear_rattle.core.params import Params
from gear_rattle.core.results import COLUMNS
from gear_rattle.mapimpl.certified import CertificationError, certify_orbit
from gear_rattle.mapimpl.certified.track import (
    BOUND_COLUMNS,
    START_PREC,
    CertifiedSequence,
    UncertifiedOrbit,
    certified_orbit,
    working_precision,
)
from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.formats.cases import load_suite, sequence_from_impacts
from gear_rattle.validation.golden.self_check import run_case
from gear_rattle.validation.golden.scoring.cases import score_sequence

from mpref import s_and_v

FIG2 = Params(0.5, 0.1, 0.1, 0.9)
FIG3 = Params(3.0, 0.1, 0.1, 0.9)
#: The issue's chaotic example: the float64 map is off by 1.4e-7 at impact 199 from (1, 0.2).
DRIFT = Params(2.2, 0.05, 0.3, 0.7)


def _contains(run, col: str, values: np.ndarray) -> bool:
    lo, hi = run.rows[col + "_lo"], run.rows[col + "_hi"]
    ok = ~np.isnan(lo)
    return bool(np.all(lo[ok] <= values[ok]) and np.all(values[ok] <= hi[ok]))


def _ulps(lo: np.ndarray, hi: np.ndarray, mid: np.ndarray) -> np.ndarray:
    ok = ~np.isnan(mid)
    return np.array([(b - a) / math.ulp(m) for a, b, m in zip(lo[ok], hi[ok], mid[ok])])


def test_rows_are_the_nearest_floats_inside_bounds_at_most_one_ulp_wide():
    run = certified_orbit(FIG3, 0.0, 0.5, 30, progress=False)
    assert run.complete and run.status == "active" and run.first_uncertified is None
    r = run.rows
    assert len(r["tau"]) == 31 and list(r["kind"]) == ["impact"] * 31
    for col, mid in (("tau", r["tau"]), ("tau_mod_2pi", r["theta"]), ("sdot", r["sdot"])):
        lo, hi = r[col + "_lo"], r[col + "_hi"]
        assert np.all(lo <= mid) and np.all(mid <= hi)
        widths = _ulps(lo, hi, mid)
        # exact (impact 0) or adjacent floats: the ball is far narrower than an ulp (320 bits)
        assert widths.max() <= 1.0 and widths.min() == 0.0, (col, widths.max())


def test_a_short_regular_orbit_contains_the_map_track_within_its_float64_error():
    """Fig. 2 (regular), 20 impacts: the map lies within 1e-13 of the certified bounds (the tracks' agreement
    bound of tests/test_tracks.py); measured 7.1e-15 in tau (2 ulps at tau ~ 20) and 3.3e-16 in sdot."""
    run = certified_orbit(FIG2, 0.0, 0.5, 20, progress=False)
    seq = gr.orbit(FIG2, 0.0, 0.5, 20, track="map")
    assert list(seq.wall) == list(run.rows["wall"])
    for col, got in (("tau", seq.tau), ("sdot", seq.sdot)):
        lo, hi = run.rows[col + "_lo"], run.rows[col + "_hi"]
        assert np.all(got >= lo - 1e-13) and np.all(got <= hi + 1e-13)


def _mp_orbit(params: Params, seq) -> list:
    """The events of Eqs. (7)-(8) as printed (tests/mpref.py, 50 digits), one per row of the float64 map's
    sequence ``seq``: each flight time by Newton from the map's flight time (an independent seed), the
    walls the map's; a release at the zero of the forcing next to the map's release time (Newton), from
    rest.  Returns ``(tau, sdot)`` per row (``sdot`` None on stick/release rows; stick rows: None)."""
    a, b, g, r = (mp.mpf(getattr(params, k)) for k in ("alpha", "beta", "gamma", "r"))
    tau, sdot, wall = mp.mpf(seq.tau[0]), mp.mpf(seq.sdot[0]), int(seq.wall[0])
    out: list = [(tau, sdot)]
    start, v0 = tau, -r * sdot
    for k in range(1, len(seq.tau)):
        kind = seq.kind[k]
        if kind == "stick":
            out.append((None, None))
            continue
        if kind == "release":
            start = mp.findroot(lambda x: -a * mp.sin(x) + a * b * mp.cos(x) + g, mp.mpf(seq.tau[k]))
            v0 = mp.mpf(0)
            out.append((start, None))
            continue
        target = int(seq.wall[k])

        def gap(t, start=start, v0=v0, wall=wall, target=target):
            return s_and_v(t, start, wall, v0, a, b, g)[0] - target

        t = mp.findroot(gap, mp.mpf(seq.tau[k] - float(start)), tol=mp.mpf(10) ** -45)
        tau, sdot, wall = start + t, s_and_v(t, start, wall, v0, a, b, g)[1], target
        out.append((tau, sdot))
        start, v0 = tau, -r * sdot
    return out


def test_bounds_contain_an_mpmath_reference_for_a_few_impacts():
    seq = gr.orbit(FIG3, 0.0, 0.5, 8, track="map")
    run = certified_orbit(FIG3, 0.0, 0.5, 8, progress=False)
    ref = _mp_orbit(FIG3, seq)
    for k, (tau, sdot) in enumerate(ref):
        assert mp.mpf(run.rows["tau_lo"][k]) <= tau <= mp.mpf(run.rows["tau_hi"][k])
        assert mp.mpf(run.rows["sdot_lo"][k]) <= sdot <= mp.mpf(run.rows["sdot_hi"][k])


def test_a_chaotic_orbit_where_float64_drifts_is_certified_and_contains_the_mpmath_reference():
    """The issue's example: from (1, 0.2) at alpha=2.2, beta=0.05, gamma=0.3, r=0.7 (chatter, sticking and
    releases on the way) the float64 map is off by 1.4e-7 at impact 199; every certified row's bounds contain
    the 50-digit reference, and are at most one ulp wide."""
    n = 199
    seq = gr.orbit(DRIFT, 1.0, 0.2, n, track="map")
    run = certified_orbit(DRIFT, 1.0, 0.2, n, progress=False)
    assert run.complete and int(np.sum(run.rows["kind"] == "impact")) == n + 1
    assert list(run.rows["kind"]) == list(seq.kind) and list(run.rows["wall"]) == list(seq.wall)
    assert abs(seq.tau[-1] - run.rows["tau"][-1]) > 1e-8  # the float64 map has drifted
    ref = _mp_orbit(DRIFT, seq)
    for k, (tau, sdot) in enumerate(ref):
        if tau is not None:
            assert mp.mpf(run.rows["tau_lo"][k]) <= tau <= mp.mpf(run.rows["tau_hi"][k]), k
        if sdot is not None:
            assert mp.mpf(run.rows["sdot_lo"][k]) <= sdot <= mp.mpf(run.rows["sdot_hi"][k]), k
    assert _ulps(run.rows["tau_lo"], run.rows["tau_hi"], run.rows["tau"]).max() <= 1.0


def test_the_precision_rises_where_the_fixed_precision_fails():
    """At 320 bits the chaotic transient of Figs. 9-11 from (3.2, 0.3) cannot be separated from the walls
    before impact 400 (certify_orbit, fixed precision); the schedule restarts at a higher precision and
    certifies all 400 impacts.  (The old code had no schedule: this test fails on it.)"""
    with pytest.raises(CertificationError, match="cannot separate"):
        certify_orbit(PAPER_PARAMS, 3.2, 0.3, 400, prec=320)
    run = certified_orbit(PAPER_PARAMS, 3.2, 0.3, 400, progress=False)
    assert run.complete and len(run.rows["tau"]) == 401
    first, last = run.attempts[0], run.attempts[-1]
    assert first.prec == START_PREC and not first.complete and first.reached < 400
    assert last.complete and last.prec > START_PREC and run.precision == last.prec
    assert 0.5 < first.growth < 1.5  # bits lost per impact, measured by the failed attempt
    # the same orbit as the fixed precision where both certify it
    fixed = certify_orbit(PAPER_PARAMS, 3.2, 0.3, 100, prec=640)
    assert np.array_equal(run.rows["tau"][:101], [float(e.tau.mid().str(45, radius=False)) for e in fixed.events])
    np.testing.assert_array_less(_ulps(run.rows["tau_lo"], run.rows["tau_hi"], run.rows["tau"]), 1.5)


def test_the_precision_limit_gives_a_certified_prefix_and_the_first_uncertified_impact():
    run = certified_orbit(PAPER_PARAMS, 3.2, 0.3, 400, max_prec=128, progress=False)
    assert not run.complete and run.status == "uncertified" and [a.prec for a in run.attempts] == [128]
    k = run.first_uncertified
    assert 20 < k < 400 and "precision limit (128 bits)" in run.reason
    assert list(run.rows["n"]) == list(range(k)) and run.impacts_certified == k
    # the prefix is the longer run's prefix, row for row
    full = certified_orbit(PAPER_PARAMS, 3.2, 0.3, k, progress=False)
    assert np.array_equal(full.rows["tau"][:k], run.rows["tau"]) and np.array_equal(
        full.rows["sdot"][:k], run.rows["sdot"]
    )
    with pytest.raises(UncertifiedOrbit, match=f"impact {k} not certified") as e:
        gr.orbit(PAPER_PARAMS, 3.2, 0.3, 400, track="certified", max_prec=128)
    assert e.value.sequence.certified["complete"] is False and len(e.value.sequence.tau) == k


def test_the_flight_horizon_is_the_map_tracks():
    import inspect

    from gear_rattle.core.horizons import T_MAX
    from gear_rattle.mapimpl.finder import first_impact

    assert inspect.signature(certified_orbit).parameters["t_max"].default == T_MAX
    assert inspect.signature(first_impact).parameters["t_max"].default == T_MAX


def test_the_certified_flight_horizon_is_a_fifth_of_the_orbit_horizon():
    import inspect

    from gear_rattle.core.horizons import CERTIFIED_FLIGHT_T_MAX, T_MAX
    from gear_rattle.mapimpl.certified import certified_flight, certified_step, certify_orbit

    assert CERTIFIED_FLIGHT_T_MAX == T_MAX / 5 == 400.0  # the golden cases were certified with 400
    for f in (certified_flight, certified_step, certify_orbit):
        assert inspect.signature(f).parameters["t_max"].default == CERTIFIED_FLIGHT_T_MAX, f.__name__


def test_a_time_budget_stops_the_schedule_with_a_certified_prefix():
    run = certified_orbit(PAPER_PARAMS, 3.2, 0.3, 5000, time_budget_s=0.3, progress=False)
    assert not run.complete and run.status == "uncertified" and "the time budget is spent (0.3 s)" in run.reason
    k = run.first_uncertified
    assert k == run.impacts_certified and list(run.rows["n"]) == list(range(k)) and k < 5000
    assert run.seconds < 5.0  # one step past the deadline at most, and no further attempt
    with pytest.raises(ValueError, match="time_budget_s=0"):
        certified_orbit(FIG3, 0.0, 0.5, 3, time_budget_s=0)


def test_working_precision_follows_the_bits_left():
    assert working_precision(2048, math.inf) == 2048
    assert working_precision(2048, 1000.0) == 1088
    assert working_precision(2048, 10.0) == 128
    assert working_precision(256, 1000.0) == 256
    assert working_precision(2048, 1000.0, cap=500) == 500 and working_precision(2048, math.inf, cap=64) == 128
    assert working_precision(64, 1000.0) == 64 and working_precision(64, math.inf) == 64


def test_free_flight_start():
    """Golden case 0003's start: (tau0, s0, sdot0) = (1, -0.3, 0.2) at Fig. 2; impact 0 is the first wall."""
    run = certified_orbit(FIG2, 1.0, 0.2, 5, s0=-0.3, progress=False)
    seq = gr.orbit(FIG2, 1.0, 0.2, 5, track="map", s0=-0.3)
    assert run.complete and len(run.rows["tau"]) == 6 and run.rows["tau"][0] > 1.0
    assert np.abs(seq.tau - run.rows["tau"]).max() < 1e-13


@pytest.mark.parametrize(
    "params, s0, status",
    [
        (Params(0.0, 0.1, 0.5, 0.9), 0.0, "stuck_forever"),  # pressed into s = 0 at rest, never released
        (Params(1.0, 0.1, 0.5, 0.9), 0.0, "active"),  # pressed into s = 0: sticks at once, released
        (Params(1.0, 0.1, -0.5, 0.9), 0.0, "active"),  # pulled away from s = 0: a flight from rest
        (Params(1.0, 0.1, 0.5, 0.9), -1.0, "active"),  # pulled away from s = -1
    ],
)
def test_a_start_at_rest_on_a_wall_is_the_map_tracks(params, s0, status):
    """Both failed before (the departure from rest was not certified): impact 0 at once where the force
    presses (sdot 0, then the policy), a flight from rest where it pulls; the map lies within 1e-13
    (measured 2.1e-14)."""
    run = certified_orbit(params, 0.0, 0.0, 6, s0=s0, progress=False)
    seq = gr.orbit(params, 0.0, 0.0, 6, s0=s0, track="map")
    assert run.complete and run.status == status == seq.status
    assert list(run.rows["kind"]) == list(seq.kind) and list(run.rows["wall"]) == list(seq.wall)
    assert np.nanmax(np.abs(run.rows["tau"] - seq.tau)) < 1e-13


def test_sticking_stuck_forever_and_no_impact_endings():
    chatter = certified_orbit(Params(2.0, 0.1, 1.0, 0.5), 0.0, 0.5, 40, progress=False)
    kinds = list(chatter.rows["kind"])
    assert chatter.complete and chatter.status == "active" and "stick" in kinds and "release" in kinds
    i = kinds.index("stick")
    assert np.isnan(chatter.rows["sdot"][i]) and np.isnan(chatter.rows["sdot_lo"][i])
    assert chatter.rows["tau_lo"][i] <= chatter.rows["tau"][i] <= chatter.rows["tau_hi"][i]
    stuck = certified_orbit(Params(0.5, 0.1, 0.9, 0.5), 0.0, 0.5, 40, progress=False)
    assert stuck.complete and stuck.status == "stuck_forever" and stuck.rows["kind"][-1] == "stick"
    assert "stuck forever" in stuck.reason
    # no forcing: a slow bounce off s = 0 stops short of s = -1; gamma = 0: proven for all time
    none = certified_orbit(Params(0.0, 0.1, 0.0, 0.9), 0.0, 0.01, 5, progress=False)
    assert none.complete and none.status == "no_impact" and len(none.rows["tau"]) == 1
    assert "T_MAX=2000" in none.reason and "for all t > 0" in none.reason
    # the map's flight horizon: gamma = 1e-6 drifts back to s = 0 only after ~9000 time units, beyond
    # T_MAX = 2000 (no_impact on the map track too)
    horizon = certified_orbit(Params(0.0, 0.1, 1e-6, 0.9), 0.0, 0.01, 3, progress=False)
    assert horizon.status == "no_impact" == gr.orbit(Params(0.0, 0.1, 1e-6, 0.9), 0.0, 0.01, 3).status
    assert "within T_MAX=2000 (certified)" in horizon.reason and "for all t" not in horizon.reason
    # a free-flight start that reaches no wall: no rows at all (the map's header-only file)
    free = certified_orbit(Params(0.0, 0.1, 0.0, 0.9), 0.0, 0.0, 5, s0=-0.5, progress=False)
    assert free.complete and free.status == "no_impact" and len(free.rows["tau"]) == 0
    assert gr.orbit(Params(0.0, 0.1, 0.0, 0.9), 0.0, 0.0, 5, s0=-0.5, track="certified").status == "no_impact"


def test_the_golden_cases_are_reproduced_by_the_certified_track():
    """Every golden case but the grazes' excursions is an orbit of the certified track: the same events, the
    expected values inside the bounds (they are the float64 nearest to the same exact numbers), and the case
    passes with the certified values."""
    for case in load_suite():
        seq = run_case(case, "certified")
        exp = case.expected
        assert isinstance(seq, CertifiedSequence) and seq.status == case.settings["expected_status"], case.id
        assert list(seq.kind) == list(exp.kind) and list(seq.wall) == list(exp.wall), case.id
        for col, e in (("tau", exp.tau), ("tau_mod_2pi", exp.tau_mod_2pi), ("sdot", exp.sdot)):
            lo, hi = seq.bounds[col + "_lo"], seq.bounds[col + "_hi"]
            ok = ~np.isnan(e)
            assert np.all(lo[ok] <= e[ok]) and np.all(e[ok] <= hi[ok]), (case.id, col)
        assert score_sequence(case, sequence_from_impacts(seq)).passed, case.id


def test_bad_input_names_the_parameter():
    with pytest.raises(ValueError, match="n_impacts=-1"):
        certified_orbit(FIG3, 0.0, 0.5, -1)
    with pytest.raises(ValueError, match="sdot0=0.0"):
        certified_orbit(FIG3, 0.0, 0.0, 3)
    with pytest.raises(ValueError, match="s0=0.5"):
        certified_orbit(FIG3, 0.0, 0.1, 3, s0=0.5)
    with pytest.raises(ValueError, match="max_prec=32"):
        certified_orbit(FIG3, 0.0, 0.5, 3, max_prec=32)
    with pytest.raises(ValueError, match="option rtol=1e-09 is out of range: the certified track takes"):
        gr.orbit(FIG3, 0.0, 0.5, 3, track="certified", rtol=1e-9)
    with pytest.raises(ValueError, match="track='euler' is out of range"):
        gr.orbit(FIG3, 0.0, 0.5, 3, track="euler")


def test_progress_reports_impacts_and_the_bar_shows_the_precision(monkeypatch, capsys):
    seen = []
    certified_orbit(FIG3, 0.0, 0.5, 5, progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1] == (5, 5)
    from gear_rattle.core import progress as P
    from gear_rattle.validation import progress as display

    monkeypatch.setattr(display, "stderr_is_terminal", lambda: True)
    with P.Bar("certified orbit") as bar:
        certified_orbit(FIG3, 0.0, 0.5, 5, progress=bar)
    err = capsys.readouterr().err
    assert "certified orbit" in err and "5.00/5.00" in err and "320 bits" in err


def test_cli_csv_columns_and_json(tmp_path, capsys):
    assert main(["simulate", "--track", "certified", "--impacts", "4"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split(",") == list(COLUMNS) + list(BOUND_COLUMNS)
    assert len(lines) == 6
    row = dict(zip(lines[0].split(","), lines[2].split(",")))
    assert float(row["tau_lo"]) <= float(row["tau"]) <= float(row["tau_hi"])
    out = tmp_path / "o.json"
    assert main(["simulate", "--track", "certified", "--impacts", "4", "--output", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["track"] == "certified" and d["certified"]["complete"] is True and len(d["events"]) == 5
    assert set(BOUND_COLUMNS) <= set(d["events"][1])


def test_cli_uncertified_writes_the_certified_prefix_and_one_line(tmp_path, capsys):
    out = tmp_path / "o.csv"
    args = [
        "simulate",
        "--alpha",
        "1.245",
        "--beta",
        "0.1",
        "--gamma",
        "0.1",
        "--r",
        "0.9",
        "--tau0",
        "3.2",
        "--sdot0",
        "0.3",
        "--impacts",
        "300",
        "--track",
        "certified",
        "--max-precision",
        "128",
    ]
    assert main(args + ["--output", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not certified" in err[0] and "precision limit (128 bits)" in err[0]
    k = int(err[0].split("impact ")[1].split()[0])
    rows = out.read_text().splitlines()
    assert rows[0].split(",") == list(COLUMNS) + list(BOUND_COLUMNS) and len(rows) == 1 + k
    assert rows[-1].split(",")[0] == str(k - 1)
    js = tmp_path / "o.json"
    assert main(args + ["--output", str(js)]) == 1
    d = json.loads(js.read_text())
    assert d["certified"]["complete"] is False and d["certified"]["first_uncertified"] == k
    # --max-precision belongs to the certified track: a usage error elsewhere
    assert main(["simulate", "--max-precision", "128"]) == 2


def test_cli_a_tangency_stops_with_one_line_and_the_certified_prefix(tmp_path, capsys):
    """A flight tangent to a wall: from s = -1 with v0 = -r sdot0 = beta = 0.5 (alpha = gamma = 0) the tooth
    approaches s = 0 as -exp(-beta t), touching it only at infinity, so within T_MAX the gap falls to
    e^-1000 ~ 2^-1443: at most 640 bits the track cannot separate the flight from the wall (the schedule
    certifies it, no_impact, at 2560 bits).  Exit 1, one line naming impact 1 and the reason, and the
    certified prefix (impact 0) written: the CSV's rows, the JSON marked incomplete.  (The float64 map
    reports a graze there, at tau = 76.3 with sdot = 1.3e-17.)"""
    args = [
        "simulate",
        "--alpha",
        "0",
        "--beta",
        "0.5",
        "--gamma",
        "0",
        "--r",
        "0.5",
        "--tau0",
        "0",
        "--sdot0",
        "-1",
        "--impacts",
        "3",
        "--track",
        "certified",
        "--max-precision",
        "640",
    ]
    out, js = tmp_path / "o.csv", tmp_path / "o.json"
    capsys.readouterr()
    assert main(args + ["--output", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("gear-rattle simulate: error: impact 1 not certified:")
    assert "cannot separate the flight from the walls" in err[0] and "tangential" in err[0], err
    rows = out.read_text().splitlines()
    assert rows[0].split(",") == list(COLUMNS) + list(BOUND_COLUMNS) and len(rows) == 2 and rows[1].startswith("0,")
    assert main(args + ["--output", str(js)]) == 1
    c = json.loads(js.read_text())["certified"]
    assert c["complete"] is False and c["first_uncertified"] == 1 and "cannot separate" in c["reason"]
    assert [a["prec"] for a in c["attempts"]] == [320, 640]


def test_json_gives_decimal_intervals_inside_the_float64_bounds(tmp_path):
    """The JSON rows carry decimal intervals (20 significant digits, rounded outward from the balls, as the
    orbit records print theirs): both contain the exact value, so they meet, and the decimal one is far
    narrower (the balls are ~1e-90 wide; its ends are the ball's rounded to 20 digits, so an exact float64
    such as sdot0 = 0.0004 lies one digit inside them); on a stick row ``sdot_decimal`` is None."""
    from decimal import Decimal

    out = tmp_path / "o.json"
    assert (
        main(
            [
                "simulate",
                "--track",
                "certified",
                "--alpha",
                "0.5",
                "--gamma",
                "0.3",
                "--r",
                "0.5",
                "--sdot0",
                "0.0004",
                "--impacts",
                "14",
                "--output",
                str(out),
            ]
        )
        == 0
    )
    events = json.loads(out.read_text())["events"]
    assert any(e["kind"] == "stick" and e["sdot_decimal"] is None for e in events)
    for e in events:
        for col in ("tau", "tau_mod_2pi", "sdot"):
            if e[col] is None:
                continue
            lo, hi = (Decimal(x) for x in e[col + "_decimal"])
            assert lo <= hi and lo <= Decimal(e[col + "_hi"]) and Decimal(e[col + "_lo"]) <= hi, (e, col)
            assert hi - lo <= Decimal("2e-19") * max(1, abs(lo)), (e, col)  # one unit of digit 20 per end
