"""The fuzzer's scenarios (validation/golden/scenarios.py; docs/reference/golden_commands.md, "Fuzzing an implementation"): a
registry of objects, each drawing its own numbers and building an input at its hard place, over the model's
whole input box (issue 36 item 4)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from gear_rattle.core.horizons import CERTIFIED_FLIGHT_T_MAX, T_MAX
from gear_rattle.core.params import Params
from gear_rattle.mapimpl.sticking import MAX_STICK_TIME, STICK_TIME
from gear_rattle.validation.cli import main
from gear_rattle.validation.golden.rules.decisions import forcing_in
from gear_rattle.validation.golden.oracle.inputs import case_input
from gear_rattle.validation.golden.oracle.ondemand import build_user_case, write_user_case
from gear_rattle.validation.golden.fuzzing import scenarios as S

DOCS = Path(__file__).resolve().parents[1] / "docs" / "reference" / "golden_commands.md"


def _first_input(name: str, seeds=range(6), count: int = 6):
    """The first input the scenario builds over a few seeds (``None`` if none)."""
    for seed in seeds:
        for k, rec in enumerate(S.draw_recipes(seed, count, [name])):
            inp = S.construct(rec, f"{name}-{seed}-{k}")
            if inp is not None:
                return inp
    return None


@pytest.mark.parametrize("name", sorted(S.SCENARIOS))
def test_every_scenario_builds_a_case(name):
    """Each scenario of the registry constructs an input for some seed, and the oracle builds its case."""
    inp = _first_input(name)
    assert inp is not None, name
    case = build_user_case(inp)
    assert case.settings["stick_time"] == inp.stick_time and case.settings["n_impacts"] <= inp.impacts


def test_the_registry_is_objects_with_their_draws_and_why():
    """One object per scenario (name, weight, why, draws, build), every draw a distribution, every recipe
    drawing impacts and stick_time; the registry holds the old scenarios and the new box's."""
    old = {"generic", "paper", "free-flight", "graze", "near-miss", "chatter-upper", "chatter-lower"}
    old |= {"stick-threshold", "release-delay", "elastic-r1", "small-beta", "negative-gamma", "stuck-forever"}
    assert old | {"no-impact", "wide-generic", "wide-graze", "wide-chatter", "long-orbit", "long-flight"} == set(
        S.SCENARIOS
    )
    for name, s in S.SCENARIOS.items():
        assert s.name == name and s.weight >= 1 and len(s.why) > 20 and callable(s.build)
        assert {"impacts", "stick_time"} <= set(s.draws)
        assert all(hasattr(d, "strategy") for d in s.draws.values())


def test_the_docs_show_the_registry_and_the_box():
    """The fuzz reference (docs/reference/golden_commands.md) holds the registry's table (name, weight, why) and the box, as :func:`describe` writes
    them: the page says what the code draws."""
    text = DOCS.read_text()
    missing = [line for line in S.describe() if line not in text]
    assert not missing, missing


def test_draws_are_reproducible_and_each_scenario_draws_its_own_numbers(monkeypatch):
    """The same seed draws the same recipes, another seed others; restricting the scenarios restricts the draws;
    a scenario's numbers do not change when another scenario joins the registry."""
    a, b, c = S.draw_recipes(3, 8), S.draw_recipes(3, 8), S.draw_recipes(4, 8)
    assert a == b and a != c
    assert len({r["scenario"] for r in a + c}) >= 5
    assert {r["scenario"] for r in S.draw_recipes(0, 4, ["graze", "elastic-r1"])} <= {"graze", "elastic-r1"}
    graze = S.draw_recipes(5, 4, ["graze"])
    extra = S.Scenario("extra", 5, "a scenario added later, for this test", {"x": S.Uniform(0, 1)}, lambda g, i: None)
    monkeypatch.setitem(S.SCENARIOS, "extra", extra)
    assert S.draw_recipes(5, 4, ["graze"]) == graze
    assert all(set(r) == {"scenario", *S.SCENARIOS["graze"].draws} for r in graze)


def test_an_unknown_scenario_is_refused_naming_the_allowed_ones(tmp_path, capsys):
    with pytest.raises(ValueError, match=r"scenario 'bogus' is unknown: allowed chatter-lower, .*wide-graze"):
        S.draw_recipes(0, 1, ["graze", "bogus"])
    with pytest.raises(SystemExit) as e:
        main(["fuzz", "--impl", "x", "--out", str(tmp_path), "--scenarios", "graze", "bogus"])
    err = capsys.readouterr().err.strip().splitlines()
    assert e.value.code == 2 and len(err) == 1
    assert "scenario 'bogus' is unknown: allowed" in err[0] and all(n in err[0] for n in S.SCENARIOS)


def test_the_draws_cover_the_box_and_other_thresholds():
    """Over many recipes: stick_time both the default and log-uniform others within the library's range;
    the wide scenarios' parameters reach alpha >= 1e3, beta >= 10 and <= 1e-5, |gamma| >= 1e3, r <= 0.01;
    long orbits ask for hundreds of impacts."""
    recipes = S.draw_recipes(7, 80)
    times = [r["stick_time"] for r in recipes]
    assert STICK_TIME in times and sum(t != STICK_TIME for t in times) >= 10
    assert all(1e-8 <= t <= MAX_STICK_TIME for t in times)
    wide = [r for n in ("wide-generic", "wide-chatter") for r in S.draw_recipes(8, 40, [n])]
    assert max(r["alpha"] for r in wide) >= 1e3 and max(r["gamma"] for r in wide) >= 1e3
    assert max(r["beta"] for r in wide) >= 10 and min(r["beta"] for r in wide) <= 1e-5
    assert min(r["r"] for r in wide) <= 0.01
    assert max(r["impacts"] for r in S.draw_recipes(9, 10, ["long-orbit"])) >= 300


def _recipe(name: str, **numbers) -> dict:
    """A recipe of ``name`` with the numbers given and the simplest value of every other draw."""
    simple = {"impacts": 4, "stick_time": STICK_TIME, "sign": 1.0, "gsign": 1.0, "paper": 1, "frac": 0.5}
    rec = {"scenario": name, **simple}
    for k, d in S.SCENARIOS[name].draws.items():
        if k not in rec:
            rec[k] = d.lo if isinstance(d, S.Uniform) else None
    return {**rec, **numbers}


def test_constructed_hard_places():
    """A graze reaches the other wall with a small normal speed; a near miss turns back short of it (the first
    contact is on the start wall); stuck-forever has |gamma| >= R; a stick threshold at another stick_time has
    t_acc within 10 % of it; a long flight lasts about the time drawn."""
    base = dict(alpha=3.0, beta=0.1, gamma=0.1, r=0.9, tau0=2.5, speed=0.3, target=1e-3, depth=1e-9)
    g = S.construct(_recipe("graze", **base), "g")
    wall, _, v = S.first_contact(g.params, g.tau0, g.sdot0)
    assert wall == -1 and 1e-5 < abs(v) < 1e-2
    m = S.construct(_recipe("near-miss", **base), "m")
    assert S.first_contact(m.params, m.tau0, m.sdot0)[0] == 0
    s = S.construct(_recipe("stuck-forever", **base, excess=0.01), "s")
    assert abs(s.params.gamma) >= s.params.alpha * math.hypot(1, s.params.beta)
    th = dict(alpha=3.0, beta=0.1, press=0.8, r=0.6, frac=0.3, side=-1.0, near1=1e-3, stick_time=3.3e-4)
    t = S.construct(_recipe("stick-threshold", **th), "t")
    p, wall = t.params, 0 if t.sdot0 > 0 else -1
    t_acc = 2 * p.r * abs(t.sdot0) / ((1 - p.r) * forcing_in(p, t.tau0, wall))
    assert t.stick_time == 3.3e-4 and abs(t_acc / t.stick_time - 1) < 0.1
    lf = dict(t_flight=800.0, push=0.5, weak=1e-5, damp=1e-7, r=0.8, tau0=1.0)
    f = S.construct(_recipe("long-flight", **lf), "f")
    assert 600 < S.first_contact(f.params, f.tau0, f.sdot0)[1] < 1000


def test_a_flight_longer_than_the_certified_search_horizon_is_a_row():
    """A flight of ~500 time units (beyond one certified flight's CERTIFIED_FLIGHT_T_MAX = 400, within the
    orbit horizon T_MAX = 2000) lands: the case has its impact, as the certified track and every float64 track
    (on the old code the case's certificate searched 400 and the input was refused: CaseError)."""
    inp = case_input("lf", 0.0, 1e-3, 5e-6, 0.9, 0.0, -0.001, 1)
    fl = S.first_contact(inp.params, inp.tau0, inp.sdot0)
    assert fl[0] == 0 and CERTIFIED_FLIGHT_T_MAX < fl[1] < T_MAX
    case = build_user_case(inp)
    assert case.settings["n_impacts"] == 1 and case.settings["expected_rows"] == 2


@pytest.mark.parametrize(
    "name, seed",
    [("wide-generic", 1), ("wide-chatter", 1), ("long-orbit", 2), ("long-flight", 1)],
)
def test_draws_of_the_whole_box_give_valid_cases_our_map_track_passes(name, seed, tmp_path):
    """Large parameters, hundreds of impacts, long flights and other thresholds: the cases build (truncated
    honestly where the horizon rule says so) and our map track passes them."""
    from gear_rattle.validation.golden.formats.cases import load_case
    from gear_rattle.validation.golden.self_check import run_settings
    from gear_rattle.validation.golden.scoring.cases import score_file
    from gear_rattle.validation.io import write_csv

    built = 0
    for k, rec in enumerate(S.draw_recipes(seed, 3, [name])):
        inp = S.construct(rec, f"c{k}")
        if inp is None:
            continue
        case = build_user_case(inp)
        folder = write_user_case(tmp_path, case)
        write_csv(tmp_path / f"c{k}.csv", *run_settings(case.settings, "map").table())
        assert score_file(load_case(folder), tmp_path / f"c{k}.csv").passed, inp.as_dict()
        assert case.truncation is None or case.settings["n_impacts"] < inp.impacts
        built += 1
    assert built >= 2


def test_velocity_scale():
    assert S.velocity_scale(Params(3.0, 0.1, 0.1, 0.9)) == 3.0
    assert S.velocity_scale(Params(0.0, 1e4, 0.0, 0.9)) == 1e4
    assert S.velocity_scale(Params(0.0, 0.1, -2e6, 0.9)) == 2e3


def test_the_wide_scenarios_draw_no_stiff_long_flight():
    """Heavy damping and a slow drift: a first flight of 781 time units at beta = 3010 (our scipy track took
    189 s on it, found by a fuzz run) is stiff; the wide scenarios skip such inputs, and build others."""
    slow = case_input("s", 0.01259, 3010.0, -0.02913, 0.464, 2.3071071, -191.0, 36, stick_time=3.03e-6)
    assert S.stiff(slow)
    assert not S.stiff(case_input("f", 3.0, 1e4, 0.1, 0.9, 1.0, 5e4, 40))
    built = [S.construct(r, f"w{k}") for k, r in enumerate(S.draw_recipes(4500137, 12, ["wide-chatter"]))]
    assert any(b is not None for b in built) and not any(S.stiff(b) for b in built if b is not None)


@pytest.mark.slow
@pytest.mark.parametrize("track, seed", [("map", 61), ("scipy", 62), ("diffrax", 63)])
def test_our_tracks_are_never_blamed_on_the_whole_box(track, seed, tmp_path, capsys):
    """Our tracks under the fuzz protocol, 120 s each, on the scenarios of the whole box and of other sticking
    thresholds (the long runs: benchmarks/results/fuzz_whole_box_2026-12-04.json): no failure."""
    import json
    import shlex
    import sys

    impl = f"{shlex.quote(sys.executable)} -m gear_rattle.validation.commands.trackimpl --track {track}"
    scen = [
        "wide-generic",
        "wide-graze",
        "wide-chatter",
        "long-orbit",
        "long-flight",
        "stick-threshold",
        "release-delay",
    ]
    capsys.readouterr()
    rc = main(
        ["fuzz", "--quiet", "--impl", impl, "--budget", "120", "--seed", str(seed), "--keep-going"]
        + ["--scenarios", *scen, "--out", str(tmp_path / "f")]
    )
    s = json.loads(capsys.readouterr().out)
    assert rc == 0 and s["failures"] == [] and s["cases"] > 0, s
