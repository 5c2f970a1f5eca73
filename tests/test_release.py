"""The canonical release and its certified post-release duration T_post (issue 10; Figs. 9-11 setting).

Every orbit that sticks is released at a phase that depends on the parameters alone
(:func:`mapimpl.sticking.release_phase`), so all sticking initial conditions of the Fig. 11 mesh share
one post-release orbit; :mod:`mapimpl.certified` certifies its duration in ball arithmetic.
"""

from __future__ import annotations

import json
import math

import jax
import numpy as np
import pytest

from gear_rattle.mapimpl.impact_map import step
from gear_rattle.core.state import make_state
from gear_rattle.core.params import Params
from gear_rattle.mapimpl.sticking import STICK_TIME, decide_stick, release_phase
from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.formats.cases import load_case

flint = pytest.importorskip("flint")
from flint import arb  # noqa: E402

from gear_rattle.core.paper import DELTA, PAPER_DECIMAL  # noqa: E402
from gear_rattle.mapimpl import certified as C  # noqa: E402
from gear_rattle.validation.commands import release as CLI  # noqa: E402
from gear_rattle.mapimpl import float64_release as F  # noqa: E402

FIG11 = Params(1.245, 0.1, 0.1, 0.9)
CASE = "0012-release-orbit-fig11"


def _f(p: Params, tau):
    return -p.alpha * np.sin(tau) + p.alpha * p.beta * np.cos(tau) + p.gamma


# ---------------------------------------------------------------------------------------------
# the canonical release (mapimpl)


@pytest.mark.parametrize("wall, phases", [(0, (3.2, 3.45, 4.9, 6.1)), (-1, (0.3, 1.0, 1.67, 3.1))])
def test_orbits_stuck_at_different_phases_continue_bit_identically(wall, phases):
    """Pre-impact states that stick at once at different phases of one driving period leave the wall
    from the same state: the next pre-impact states through mapimpl.impact_map.step are identical
    bit for bit (phase, turns, velocity, wall)."""
    p = FIG11.arrays()
    step_jit = jax.jit(step)
    out = []
    for th in phases:
        tau0, sdot0 = F.stick_at_once_state(FIG11, wall, tau0=th)
        st = make_state(tau0, sdot0)
        assert bool(decide_stick(st.theta, st.wall, st.sdot, *p).stick)
        new, info = step_jit(st, p)
        assert bool(info.stuck)
        out.append((float(new.theta), int(new.cycles), float(new.sdot), int(new.wall)))
        # the release row sits at the canonical phase of the same driving period
        ph, _ = release_phase(wall, FIG11.alpha, FIG11.beta, FIG11.gamma)
        assert math.isclose(float(info.release_tau) % (2 * math.pi), float(ph), abs_tol=1e-13)
    assert len(set(out)) == 1, out


@pytest.mark.parametrize("wall", [0, -1])
def test_release_phase_is_a_zero_of_the_contact_force(wall):
    """float64 release_phase: the contact force vanishes there to rounding, presses into the wall just
    before and pulls away just after; it lies within a few ulps of the certified zero (Arb)."""
    ph, never = release_phase(wall, FIG11.alpha, FIG11.beta, FIG11.gamma)
    ph = float(ph)
    assert not bool(never) and 0.0 <= ph < 2 * math.pi
    d = 1.0 if wall == 0 else -1.0
    R_amp = FIG11.alpha * math.hypot(1.0, FIG11.beta)
    assert abs(_f(FIG11, ph)) <= 8 * np.finfo(float).eps * R_amp
    for h in (1e-9, 1e-6, 1e-3, 0.5):
        assert d * _f(FIG11, ph - h) > 0 > d * _f(FIG11, ph + h)
    with C.precision(256):
        m = C.Model(FIG11)
        ball = C.release_phase(m, wall)
        lo, hi = C.certify_zero(m, ball, wall, 256)  # certified simple zero, pressing before it
        assert float(ball.rad()) < 1e-70
        assert abs(float((ball - arb(ph)).mid())) <= 4 * math.ulp(ph)


def test_release_phase_reduces_the_closed_form():
    """Both walls: phi + asin(gamma/R) and phi + pi - asin(gamma/R) (docs/model.md)."""
    R_amp = FIG11.alpha * math.hypot(1.0, FIG11.beta)
    phi, c = math.atan(FIG11.beta), FIG11.gamma / R_amp
    up, _ = release_phase(0, FIG11.alpha, FIG11.beta, FIG11.gamma)
    lo, _ = release_phase(-1, FIG11.alpha, FIG11.beta, FIG11.gamma)
    assert math.isclose(float(up), phi + math.asin(c), rel_tol=1e-15)
    assert math.isclose(float(lo), phi + math.pi - math.asin(c), rel_tol=1e-15)


@pytest.mark.parametrize("params", [Params(0.1, 0.1, 0.5, 0.9), Params(0.0, 0.1, 0.1, 0.9)])
def test_lead_state_needs_a_release_phase(params):
    """The golden suite's state before a release (rules.thresholds.release_lead_state) where the contact force never
    stops pressing into the wall (|gamma| >= alpha sqrt(1 + beta^2), or alpha = 0): a ValueError naming the
    parameters (it subtracted the lead from the certified phase's None: a TypeError)."""
    from gear_rattle.validation.golden.rules.thresholds import release_lead_state

    with pytest.raises(ValueError, match=r"params=.* never stops pressing"):
        release_lead_state(params, 0, 0.5, 0.5)


# ---------------------------------------------------------------------------------------------
# certification


def test_decimal_parameters_are_exact_decimal_balls():
    with C.precision(256):
        m = C.Model(PAPER_DECIMAL)
        assert m.alpha.contains(arb("1.245")) and float(m.alpha.rad()) < 1e-70
        assert not m.alpha.contains(arb(1.245))  # the float64 rounding is another number
        m64 = C.Model(C.model_params(PAPER_DECIMAL, "float64"))
        assert m64.alpha == arb(1.245) and m64.alpha.is_exact()
    for bad, needle in (
        ({"alpha": "x", "beta": "0.1", "gamma": "0.1", "r": "0.9"}, "alpha"),
        ({"alpha": "1", "beta": "-0.1", "gamma": "0.1", "r": "0.9"}, "beta"),
        ({"alpha": "1", "beta": "0.1", "gamma": "0.1"}, "keys"),
    ):
        with pytest.raises(ValueError, match=needle):
            C.model_params(bad, "decimal")
        with pytest.raises(ValueError, match=needle), C.precision(64):
            C.Model(bad)


@pytest.fixture(scope="module")
def target():
    """The capture target as recorded in the golden case (exact float64 points; the slow test checks
    that it is the engine's 4-impact orbit)."""
    t = load_case(DEFAULT_SUITE / CASE).settings["notes"]["capture_target"]
    return C.Target(tuple(float(x) for x in t["theta"]), tuple(float(x) for x in t["sdot"]), tuple(t["wall"]))


def test_certified_prefix_contains_the_float64_orbit(target):
    """A cheap certified prefix (40 post-release impacts at 256 bits): no capture, balls tiny; the
    float64 map orbit from a state that sticks at once agrees with the certified balls to ~1e-12
    over the first 15 post-release impacts (its error then grows at the Lyapunov rate)."""
    from gear_rattle.mapimpl.orbit import map_orbit

    a = C.certify_post_release(
        C.model_params(PAPER_DECIMAL, "float64"), 0, prec=256, target=target, max_impacts=40, record=True
    )
    assert a.status == "no_capture" and a.impacts == 40 and float(a.radius) < 1e-50
    assert 0.8 < a.growth < 1.1  # bits lost per impact (chaos), cf. the transient Lyapunov exponent
    tau0, sdot0 = F.stick_at_once_state(FIG11, 0, tau0=3.25)
    seq = map_orbit(FIG11, tau0, sdot0, 15)
    _, th, sd, wl = seq.impact_arrays()
    for n in range(1, 16):
        th_c, sd_c, w_c = a.orbit[n - 1]
        assert wl[n] == w_c
        dth = abs(th[n] - th_c)
        assert min(dth, 2 * math.pi - dth) < 1e-10 and abs(sd[n] - sd_c) < 1e-10


def test_capture_is_decided_at_the_first_impact_within_delta(target):
    """With a target placed at the float64 map's post-release impact 7, the certified T_post is the
    first impact that the float64 orbit puts within delta of it (margins far above float64 errors)."""
    from gear_rattle.mapimpl.orbit import map_orbit

    tau0, sdot0 = F.stick_at_once_state(FIG11, 0, tau0=3.25)
    _, th, sd, wl = map_orbit(FIG11, tau0, sdot0, 10).impact_arrays()
    tg = C.Target((float(th[7]),), (float(sd[7]),), (int(wl[7]),))
    delta = 1e-3
    dist = [
        max(min(abs(th[n] - th[7]), 2 * math.pi - abs(th[n] - th[7])), abs(sd[n] - sd[7]))
        if wl[n] == wl[7]
        else math.inf
        for n in range(1, 8)
    ]
    expect = 1 + next(i for i, d in enumerate(dist) if d < delta)
    assert all(abs(d - delta) > 1e-6 for d in dist[:expect])
    res = C.certified_release_duration(
        PAPER_DECIMAL, 0, delta, rounding="float64", precisions=(128, 256), target=tg, max_impacts=20
    )
    assert res.status == "captured" and res.value == expect and res.confirmed
    assert res.precision == 128 and [a.prec for a in res.attempts] == [128, 256]
    assert res.lower_bound == expect - 1
    assert json.loads(json.dumps(res.to_dict()))["value"] == expect


def _same_attempt(a, b) -> bool:
    """Equal in every field but the wall time (a slope of fewer than two radii is nan in both)."""
    for k in a.__dataclass_fields__:
        x, y = getattr(a, k), getattr(b, k)
        if (
            k == "seconds"
            or x == y
            or (isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y))
        ):
            continue
        return False
    return True


def _straddle_setting():
    """A target that puts the certified distance at post-release impact 30 within a 64-bit ball of
    ``D = 2^-20`` (the orbit's sdot shifted by D), so that at 64 bits ``D`` is undecided there while
    ``D / 2`` is decided; 0.5 is captured at once."""
    p = C.model_params(PAPER_DECIMAL, "float64")
    ref = C.certify_post_release(
        p, 0, prec=64, target=C.Target((), (), ()), max_impacts=30, record=True, radius_limit=1e-3
    )
    th, sd, w = ref.orbit[-1]
    D = 2.0**-20
    return p, C.Target((th,), (sd + D,), (w,)), (0.5, D, D / 2)


def test_one_run_decides_every_delta_as_a_run_for_each_alone():
    """certify_post_release_deltas: one certified orbit, each capture distance its own outcome --
    captured, undecided (the distance ball straddles delta: that delta fails, the others go on) or not
    captured -- each identical to the run for that delta alone."""
    p, tg, deltas = _straddle_setting()
    runs = C.certify_post_release_deltas(
        p, 0, prec=64, target=tg, deltas=deltas, max_impacts=40, radius_limit=1e-3, record=True
    )
    assert [runs[d].status for d in deltas] == ["captured", "failed", "no_capture"]
    assert runs[deltas[1]].impacts == 29 and "straddles" in runs[deltas[1]].reason
    assert runs[deltas[2]].impacts == 40 and len(runs[deltas[2]].orbit) == 40
    for d in deltas:
        alone = C.certify_post_release(
            p, 0, prec=64, target=tg, delta=d, max_impacts=40, radius_limit=1e-3, record=True
        )
        assert _same_attempt(runs[d], alone), d


def test_schedule_for_several_deltas_is_the_schedule_for_each_alone():
    """certified_release_durations: the runs are shared, but each delta gets exactly the attempts, value,
    precision and confirmation of its own schedule (D undecided at 64 bits is decided at 128 and
    confirmed at twice the last precision)."""
    p, tg, deltas = _straddle_setting()
    kw = dict(rounding="float64", precisions=(64, 128), target=tg, max_impacts=40, radius_limit=1e-3)
    res = C.certified_release_durations(PAPER_DECIMAL, 0, deltas, **kw)
    assert [a.prec for a in res[deltas[1]].attempts] == [64, 128, 256]
    assert all(r.confirmed and r.status != "undecided" for r in res.values())
    for d in deltas:
        alone = C.certified_release_duration(PAPER_DECIMAL, 0, d, **kw)
        a, b = res[d].to_dict(), alone.to_dict()
        assert [_same_attempt(x, y) for x, y in zip(res[d].attempts, alone.attempts)] == [True] * len(b["attempts"])
        for k in ("status", "value", "precision", "confirmed", "lower_bound", "delta", "target", "release_phase"):
            assert a[k] == b[k], (d, k)
    with pytest.raises(ValueError, match="deltas is empty"):
        C.certified_release_durations(PAPER_DECIMAL, 0, (), **kw)
    with pytest.raises(ValueError, match="delta"):
        C.certified_release_durations(PAPER_DECIMAL, 0, (1e-3, -1.0), **kw)


def test_sticking_again_is_certified_periodic():
    """Case 0007's parameters (alpha=2, gamma=1, r=0.5): the orbit released from the upper wall chatters
    and sticks to it again, so it repeats from the release and is never captured (status periodic)."""
    a = C.certify_post_release(Params(2.0, 0.1, 1.0, 0.5), 0, prec=256, target=C.Target((), (), ()), max_impacts=200)
    assert a.status == "periodic" and a.walls_stuck == [0] and 1 < a.impacts < 200
    # the float64 map from case 0007's initial state sticks to the same wall every a.impacts impacts
    from gear_rattle.mapimpl.orbit import map_orbit

    seq = map_orbit(Params(2.0, 0.1, 1.0, 0.5), 0.0, 0.5, 2 * a.impacts + 30)
    n_stick = seq.n[seq.kind == "stick"]
    assert len(n_stick) >= 2 and np.all(np.diff(n_stick) == a.impacts)
    assert np.all(seq.wall[seq.kind == "stick"] == 0)


def test_undecided_schedule_keeps_a_certified_lower_bound(target):
    """A radius limit too tight for the schedule: every attempt fails, the result is 'undecided' and
    reports how many impacts were certified not captured."""
    res = C.certified_release_duration(
        PAPER_DECIMAL, 0, precisions=(128,), radius_limit=1e-30, target=target, max_impacts=200
    )
    assert res.status == "undecided" and res.value is None and res.precision is None and not res.confirmed
    assert 0 < res.lower_bound < 200 and res.attempts[0].status == "failed"


def test_bad_arguments_raise_value_errors(target):
    with pytest.raises(ValueError, match="wall"):
        C.certify_post_release(FIG11, 1, prec=128, target=target)
    with pytest.raises(ValueError, match="max_impacts"):
        C.certify_post_release(FIG11, 0, prec=128, target=target, max_impacts=0)
    with pytest.raises(ValueError, match="precisions"):
        C.certified_release_duration(PAPER_DECIMAL, precisions=(512, 256), target=target)
    with pytest.raises(ValueError, match="rounding"):
        C.certified_release_duration(PAPER_DECIMAL, rounding="float32", target=target)
    with pytest.raises(ValueError, match="never presses"):
        C.certify_post_release(Params(0.5, 0.1, 0.9, 0.5), -1, prec=128, target=target)
    with pytest.raises(ValueError, match="lam"):
        F.float64_horizon(-0.1)


def test_cli_prints_results_and_rejects_bad_input(tmp_path, capsys, monkeypatch, target):
    monkeypatch.setattr(CLI, "float64_target", lambda params: target)  # skip the 4-cycle search
    out = tmp_path / "r.json"
    assert (
        CLI.main(
            ["--max-impacts", "5", "--precisions", "128,256", "--rounding", "float64", "--quiet", "--json", str(out)]
        )
        == 0
    )
    o = capsys.readouterr().out
    assert "T_post > 5" in o and "128 bits" in o
    data = json.loads(out.read_text())
    assert data["results"][0]["status"] == "no_capture" and data["results"][0]["rounding"] == "float64"
    for argv, needle in (
        (["--alpha", "x"], "alpha"),
        (["--precisions", "512,256"], "precisions"),
        (["--max-impacts", "0"], "max-impacts"),
        (["--wall", "2"], "wall"),
    ):
        with pytest.raises(SystemExit) as ex:
            CLI.main(argv)
        assert ex.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and needle in err[0] and "Traceback" not in err[0]


def test_float64_horizon_follows_from_the_exponent():
    """The float64 horizon is computed from lambda1, not typed: ln(distance / 2^-53) / lambda1."""
    assert math.isclose(F.float64_horizon(0.5), 53 * math.log(2) / 0.5)
    assert F.float64_horizon(0.5, 1e-3) < F.float64_horizon(0.5) < F.float64_horizon(0.25)


# ---------------------------------------------------------------------------------------------
# the golden case of the release orbit


def test_release_golden_case_is_well_formed():
    """Case 0012: impact 0 sticks at once, the release row is the canonical phase (float64 value within
    its certified radius), n_impacts follows the horizon rule from the transient exponent, and the notes
    carry the oracle values (certified T_post for both roundings, delta, target)."""
    from gear_rattle.validation.golden.catalog.specs import CHAOS_ERR0, CHAOS_SAFETY, CHAOS_TOL, horizon

    case = load_case(DEFAULT_SUITE / CASE)
    s, e = case.settings, case.expected
    assert s["params"] == {"alpha": 1.245, "beta": 0.1, "gamma": 0.1, "r": 0.9}
    ini = s["initial_state"]
    assert ini["kind"] == "pre-impact" and 3.0 < ini["tau0"] < 3.5 and 0.0 < ini["sdot0"] < 0.5  # Fig. 11 box
    assert (ini["tau0"], ini["sdot0"]) == F.stick_at_once_state(FIG11, 0, tau0=3.25)
    assert list(e.kind[:4]) == ["impact", "stick", "release", "impact"] and list(e.n[:4]) == [0, 0, 0, 1]
    assert np.all(e.kind[3:] == "impact")
    ph, _ = release_phase(0, FIG11.alpha, FIG11.beta, FIG11.gamma)
    assert abs(e.tau[2] - (float(ph) + 2 * math.pi)) <= e.extra["tau_radius"][2] + 4e-15
    assert abs(_f(FIG11, e.tau[2])) < 1e-14
    assert e.tau[1] - e.tau[0] <= STICK_TIME
    notes = s["notes"]
    lam = notes["lyapunov_lambda1_per_impact"]
    assert 0.3 < lam < 0.8 and s["n_impacts"] == horizon(lam)
    assert math.isclose(CHAOS_ERR0 * CHAOS_SAFETY * math.exp(lam * s["n_impacts"]), CHAOS_TOL, rel_tol=math.exp(lam))
    tp = notes["T_post_certified"]
    assert set(tp) == {"decimal", "float64"}
    for v in tp.values():
        assert isinstance(v["T_post"], int) and v["T_post"] > s["n_impacts"]
        assert v["confirmed_at_bits"] > v["precision_bits"] >= 256
    assert notes["capture_delta"] == DELTA
    tg = notes["capture_target"]
    assert len(tg["theta"]) == len(tg["sdot"]) == len(tg["wall"]) == 4 and sorted(tg["wall"]) == [-1, -1, 0, 0]


def test_release_golden_case_recertifies():
    """Re-certifying case 0012 from its settings reproduces its expected.csv byte for byte."""
    from gear_rattle.validation.golden.catalog.build import build_case
    from gear_rattle.validation.golden.formats.spec import spec_from_settings

    folder = DEFAULT_SUITE / CASE
    settings = json.loads((folder / "settings.json").read_text())
    s, text, prov = build_case(spec_from_settings(settings), tracks=False)
    assert text == (folder / "expected.csv").read_text() and s == settings


@pytest.mark.slow
@pytest.mark.parametrize("rounding", ["decimal", "float64"])
def test_full_certified_release_duration_matches_the_golden_notes(rounding):
    """Paper-scale: the whole schedule certifies T_post (confirmed at the next precision) and gives the
    value the golden case carries."""
    all_notes = load_case(DEFAULT_SUITE / CASE).settings["notes"]
    notes = all_notes["T_post_certified"][rounding]
    from gear_rattle.mapimpl.engine.t_post import float64_target

    res = C.certified_release_duration(PAPER_DECIMAL, 0, rounding=rounding, target=float64_target(FIG11))
    assert res.status == "captured" and res.confirmed
    assert res.value == notes["T_post"] and res.precision == notes["precision_bits"]
    # the recorded target is the engine's float64 4-impact orbit: its Newton solution is determined to
    # its residual (~1e-13), and compilations of the map (XLA options, arithmetic changes) move it by
    # up to 5e-13 (measured 2026-11-24): equal walls, the numbers to 1e-11
    rec = all_notes["capture_target"]
    assert res.target["wall"] == rec["wall"]
    for k in ("theta", "sdot"):
        assert np.allclose(np.asarray(res.target[k], float), np.asarray(rec[k], float), rtol=0, atol=1e-11), k


def test_sticking_walls_names_the_first_wall():
    """The per-wall diagnostic (the transient engine, stopped at the first sticking): states that stick at
    once to the upper and to the lower wall, and one that never sticks within the cap."""
    ics = [F.stick_at_once_state(FIG11, 0, tau0=3.25), F.stick_at_once_state(FIG11, -1), (3.25, 0.4)]
    w = F.sticking_walls([t for t, _ in ics], [s for _, s in ics], FIG11, cap=60)
    assert w["first_wall"].tolist()[:2] == [0, -1]
    assert w["first_stick"].tolist()[:2] == [0, 0]
    assert (w["first_wall"][2] == 1) == (w["first_stick"][2] == -1)
