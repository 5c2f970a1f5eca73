"""Rules of ``gear-rattle case`` found by ``gear-rattle fuzz`` on the whole input box (issue 36 item 4;
docs/reference/golden_commands.md, "Asking the oracle"): the sticking-decision rule (validation/golden/rules/decisions.py: a case does not
ask a sticking decision that an output within its own tolerances could take the other way) and the near-miss
rule's search for turning points right after a slow departure."""

from __future__ import annotations

import pytest

from gear_rattle.core.params import Params

from gear_rattle.validation.golden.oracle.inputs import case_input

from gear_rattle.validation.golden.oracle.ondemand import build_user_case, write_user_case

from gear_rattle.validation.golden.rules.near_miss import turning_gap
from gear_rattle.validation.golden.formats.cases import load_case
from gear_rattle.validation.golden.self_check import run_settings
from gear_rattle.validation.golden.scoring.cases import score_file
from gear_rattle.validation.io import write_csv

#: Found by ``gear-rattle fuzz`` (diffrax, seed 44, stick-threshold): a chatter on s = -1 stopped by
#: stick_time = 8.38e-8; without the rule the case kept 16 impacts and its last decision (a bounce at speed
#: 6.6e-8, t_acc within 1 % of the threshold, the case's sdot tolerance 1.5 % of the speed) went the other
#: way on our diffrax track: "wrong number of events: 19 rows, expected 21".
FOUND = ("found", 3.606, 0.003, 1.25, 0.3, 0.0, 1e-7, 16)


def test_a_doubtful_decision_ends_the_case(tmp_path):
    """The case stops at the first impact whose decision is in doubt (the note says so); its last decision is
    stable under its tolerances; our tracks pass it (on the old code the case kept all 16 impacts)."""
    inp = case_input(*FOUND, stick_time=8.38e-8)
    case = build_user_case(inp)
    t = case.truncation
    assert t is not None and "sticking-decision rule" in t["reason"] and t["kept_impacts"] < 16
    folder = write_user_case(tmp_path, case)
    for track in ("map", "scipy"):
        write_csv(tmp_path / f"{track}.csv", *run_settings(case.settings, track).table())
        assert score_file(load_case(folder), tmp_path / f"{track}.csv").passed, track


@pytest.mark.parametrize("stick_time", [None, 1e-4])
def test_a_clear_chatter_is_not_cut(stick_time):
    """Case 0007's chatter (default threshold, and 1e-4) keeps its 40 impacts: its decisions are clear."""
    inp = case_input("c", 2.0, 0.1, 1.0, 0.5, 0.0, 0.5, 40, stick_time=stick_time)
    case = build_user_case(inp)
    assert case.truncation is None and case.settings["n_impacts"] == 40


def test_an_exact_start_is_asked_whatever_its_margin():
    """A pre-impact initial state is exact: its decision is asked even at t_acc = (1 + 1e-4) stick_time (the
    stick-threshold scenario's hard place); the case keeps its impacts."""
    from gear_rattle.core.params import Params
    from gear_rattle.validation.golden.rules.thresholds import stick_ratio_sdot0

    p = Params(2.0, 0.1, 1.0, 0.5)
    for ratio in (1.0001, 0.9999):
        sdot0 = stick_ratio_sdot0(p, 0.0, 0, ratio)
        case = build_user_case(case_input("t", 2.0, 0.1, 1.0, 0.5, 0.0, sdot0, 5))
        assert case.truncation is None and case.settings["n_impacts"] == 5
        assert ("stick" in case.expected.splitlines()[2]) == (ratio < 1)  # the row after impact 0


@pytest.mark.parametrize(
    "params, tau0, sdot0",
    [
        ((2.789, 0.00102, -1.28, 0.4), 3.6194199, -2e-12),  # seed 53: turns back at 5.8e-7, 1.1e-6
        ((2.622, 0.033, -1.09, 0.333), 3.603058748, -3.58e-14),  # seed 56: a dip of sdot to -1.8e-17 near 1e-7
    ],
)
def test_a_near_miss_right_after_a_slow_departure_ends_the_case(params, tau0, sdot0):
    """Found by ``gear-rattle fuzz`` (diffrax, seeds 53 and 56, release-delay, shrunk): just before the force
    stops pressing into s = -1 the flight leaves at ``r |sdot0|`` (8e-13, 1.2e-14), turns back twice within
    1e-6 of its start, 1.6e-19 and 4e-22 above the wall (certified: it lands on s = 0 at 5.1); our diffrax
    track took it for a contact.  The near-miss rule's 257-point grid saw neither turning point (on the old
    code the cases kept their impact 1); its grid now has ``dt 2^-k`` samples near the start, and a dip of
    ``sdot`` through 0 and back between two samples is found where the acceleration changes sign: the case
    stops before impact 1."""
    p = Params(*params)
    inp = case_input("nm", *params, tau0, sdot0, 1, stick_time=1.97e-6)
    assert turning_gap(p, tau0, p.r * abs(sdot0), -1.0, 1.5) < 1e-15
    case = build_user_case(inp)
    assert case.settings["n_impacts"] == 0 and "turns back" in case.truncation["reason"]


def test_the_turning_point_grid_follows_a_long_flight():
    """A flight of 2000 time units oscillates with the forcing (period 2 pi): the first round samples it at
    64 per unit of time, not 257 in all (one every 7.8)."""
    from gear_rattle.validation.golden.rules.near_miss import turn_grid

    grid = turn_grid(2000.0)
    assert len(grid) >= 64 * 2000 and grid[0] == 0.0 and grid[-1] == 2000.0 and grid[1] < 1e-15
