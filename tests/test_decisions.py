"""The sticking-decision rule of ``gear-rattle case`` (validation/golden/decisions.py; docs/golden.md, "Asking
the oracle"): a case does not ask a sticking decision that an output within its own tolerances could take the
other way."""

from __future__ import annotations

import pytest

from gear_rattle.validation.golden import ondemand
from gear_rattle.validation.golden.suite import load_case, run_settings, score_file
from gear_rattle.validation.io import write_csv

#: Found by ``gear-rattle fuzz`` (diffrax, seed 44, stick-threshold): a chatter on s = -1 stopped by
#: stick_time = 8.38e-8; without the rule the case kept 16 impacts and its last decision (a bounce at speed
#: 6.6e-8, t_acc within 1 % of the threshold, the case's sdot tolerance 1.5 % of the speed) went the other
#: way on our diffrax track: "wrong number of events: 19 rows, expected 21".
FOUND = ("found", 3.606, 0.003, 1.25, 0.3, 0.0, 1e-7, 16)


def test_a_doubtful_decision_ends_the_case(tmp_path):
    """The case stops at the first impact whose decision is in doubt (the note says so); its last decision is
    stable under its tolerances; our tracks pass it (on the old code the case kept all 16 impacts)."""
    inp = ondemand.case_input(*FOUND, stick_time=8.38e-8)
    case = ondemand.build_user_case(inp)
    t = case.truncation
    assert t is not None and "sticking-decision rule" in t["reason"] and t["kept_impacts"] < 16
    folder = ondemand.write_user_case(tmp_path, case)
    for track in ("map", "scipy"):
        write_csv(tmp_path / f"{track}.csv", *run_settings(case.settings, track).table())
        assert score_file(load_case(folder), tmp_path / f"{track}.csv").passed, track


@pytest.mark.parametrize("stick_time", [None, 1e-4])
def test_a_clear_chatter_is_not_cut(stick_time):
    """Case 0007's chatter (default threshold, and 1e-4) keeps its 40 impacts: its decisions are clear."""
    inp = ondemand.case_input("c", 2.0, 0.1, 1.0, 0.5, 0.0, 0.5, 40, stick_time=stick_time)
    case = ondemand.build_user_case(inp)
    assert case.truncation is None and case.settings["n_impacts"] == 40


def test_an_exact_start_is_asked_whatever_its_margin():
    """A pre-impact initial state is exact: its decision is asked even at t_acc = (1 + 1e-4) stick_time (the
    stick-threshold scenario's hard place); the case keeps its impacts."""
    from gear_rattle.core.params import Params
    from gear_rattle.validation.golden import generate

    p = Params(2.0, 0.1, 1.0, 0.5)
    for ratio in (1.0001, 0.9999):
        sdot0 = generate.stick_ratio_sdot0(p, 0.0, 0, ratio)
        case = ondemand.build_user_case(ondemand.case_input("t", 2.0, 0.1, 1.0, 0.5, 0.0, sdot0, 5))
        assert case.truncation is None and case.settings["n_impacts"] == 5
        assert ("stick" in case.expected.splitlines()[2]) == (ratio < 1)  # the row after impact 0
