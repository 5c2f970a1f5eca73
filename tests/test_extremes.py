"""Extreme inputs (issue 23, items 2 and 5): every parameter set the library accepts runs to an
orbit status on every track, and subnormal numbers do not change a decision.

* The parameter box (:data:`core.params.PARAM_MAX`, docs/model.md "Parameter range"): its corners
  -- 0, the smallest subnormal, the paper's values and 1e10 for alpha, beta, gamma; r from the smallest
  subnormal to 1; tau0 at +-1e6 -- through the engine, the map track, the scipy track and the command
  line.  Beyond the box one line names the parameter and the range.
* Subnormal inputs: XLA on the CPU flushes subnormals to zero; the wall a subnormal pre-impact
  velocity points to is decided on its bits (:func:`core.jax_config.positive`), and the tracks agree.

Tolerance of the track comparisons: a velocity error ``eps M / |v|`` is the conditioning of the
impact velocity, ``v^2 = v_0^2 - 2 (work of a force of size M)``, where the orbit slows down to
``|v|`` against a force ``M = alpha (1 + beta) + |gamma|`` (``gamma = -1e10`` with ``r = 1``: the tooth
climbs the gap at ``1.4e5`` and arrives at ``0.55``); the map and the engine agree to 1e-3 of
``1e-12 M / |v| + 1e-9 |v|``, the map and scipy to 6e-6 of ``1e-9 M / |v| + 1e-6 |v|`` on the grids below.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from gear_rattle.mapimpl.engine.options import Execution
from gear_rattle.mapimpl.engine.driver import max_kernel_calls, run
from gear_rattle.mapimpl.engine.observers import Sample
from gear_rattle.mapimpl.orbit import map_orbit
from gear_rattle.core.params import PARAM_MAX, Params, validate_arrays
from gear_rattle.core.status import Status
from gear_rattle.validation.cli import main
from gear_rattle.mapimpl.tracks import orbit

TINY = 5e-324  # the smallest subnormal
SUBNORMALS = (TINY, 1e-320, 2e-308)  # 2e-308 is below the smallest normal, 2.2e-308
#: Pre-impact velocity of the grid orbits (0.5 would make alpha = gamma = 0, r = 1 a tangency at
#: infinity: each crossing loses exactly beta = 0.1 of velocity, and 0.1 is then lost in an infinite time).
SDOT0 = 0.55


def _work(p) -> float:
    return abs(p[0]) * (1.0 + p[1]) + abs(p[2]) + 1.0


def _close(v_ref, v, p, scale) -> bool:
    v_ref, v = np.asarray(v_ref), np.asarray(v)
    tol = scale[0] * _work(p) / np.abs(v_ref) + scale[1] * np.abs(v_ref)
    return bool(np.all(np.abs(v - v_ref) <= tol))


# ---------------------------------------------------------------------------------- the parameter box


@pytest.mark.parametrize(
    "name,value",
    [
        ("alpha", 1e308),
        ("alpha", PARAM_MAX * (1 + 2e-16)),
        ("alpha", -TINY),
        ("beta", 1e300),
        ("beta", 0.0),
        ("beta", -TINY),
        ("gamma", -1e11),
        ("gamma", 1.7976931348623157e308),
        ("r", 1 + 2e-16),
        ("r", 0.0),
    ],
)
def test_params_outside_the_box_are_refused_naming_the_range(name, value):
    base = dict(alpha=3.0, beta=0.1, gamma=0.1, r=0.9)
    with pytest.raises(ValueError, match=rf"parameter {name}=.* out of range: allowed .*{name}"):
        Params(**{**base, name: value})
    arrays = {k: np.full(3, v) for k, v in base.items()}
    arrays[name][1] = value
    with pytest.raises(ValueError, match=rf"parameter {name}=.* out of range"):
        validate_arrays(*arrays.values())


def test_params_box_edges_are_accepted():
    for name, value in (
        ("alpha", 0.0),
        ("alpha", PARAM_MAX),
        ("beta", TINY),
        ("beta", PARAM_MAX),
        ("gamma", -PARAM_MAX),
        ("gamma", PARAM_MAX),
        ("r", TINY),
        ("r", 1.0),
    ):
        assert getattr(Params(**{**dict(alpha=3.0, beta=0.1, gamma=0.1, r=0.9), name: value}), name) == value


GRID = list(
    itertools.product(
        [0.0, TINY, 3.0, PARAM_MAX], [TINY, 0.1, PARAM_MAX], [-PARAM_MAX, -TINY, 0.1, PARAM_MAX], [TINY, 0.9, 1.0]
    )
)


def test_engine_runs_every_corner_of_the_box_like_the_map():
    """144 corners, tau0 at -1e6, 1 and 1e6: every orbit ends with a status, none fails, and each
    agrees with the map track (status, number of impacts, walls, velocities to the conditioning)."""
    n, keep = len(GRID), 6
    tau0 = np.resize([-1e6, 1.0, 1e6], n)
    P = tuple(np.array(GRID).T)
    res = run(tau0, np.full(n, SDOT0), np.zeros(n, np.int32), P, Sample(keep=keep, n_start=1), cap=keep, progress=False)
    for i, p in enumerate(GRID):
        seq = map_orbit(Params(*p), tau0[i], SDOT0, keep)
        imp = seq.kind == "impact"
        sd, wall = seq.sdot[imp][1:], seq.wall[imp][1:]
        status = Status(int(res.status[i])).label
        assert (status in ("stopped", "capped")) == (seq.status == "active"), (p, status, seq.status)
        if seq.status != "active":
            assert status == seq.status, (p, status, seq.status)
        assert res.n[i] == sd.size, (p, res.n[i], sd.size)
        assert np.all(np.isfinite(sd)), p
        assert _close(sd, res.obs[0]["sdot"][i][: sd.size], p, (1e-12, 1e-9)), (p, sd, res.obs[0]["sdot"][i])
        assert np.array_equal(np.where(res.obs[0]["sdot"][i][: sd.size] > 0, 0, -1), wall), p


@pytest.mark.parametrize("p", [p for p in GRID if p[1] < 1.0 and p[0] != TINY and p[2] != -TINY])
def test_map_agrees_with_scipy_at_the_corners(p):
    """The certified map against an ODE solver at the corners (beta = 1e10 is stiff for scipy's
    explicit method and left out): same statuses, walls and impacts -- no impact skipped."""
    m = orbit(Params(*p), 1.0, SDOT0, 6, track="map")
    s = orbit(Params(*p), 1.0, SDOT0, 6, track="scipy")
    mi, si = m.kind == "impact", s.kind == "impact"
    assert m.status == s.status
    assert np.array_equal(m.wall[mi], s.wall[si])
    assert np.all(np.abs(m.tau[mi] - s.tau[si]) <= 1e-9)
    assert _close(m.sdot[mi], s.sdot[si], p, (1e-9, 1e-6))


def test_engine_guard_counts_the_longest_flights():
    """Long flights (alpha = 1e-3: each flight searches to T_MAX, ~1000 safe steps) used to trip the
    engine's guard, a guess of 200 micro-steps per impact: "engine made no progress (bug)".  The guard
    is now derived from the finder's caps (max_kernel_calls), and the run ends."""
    m = 600
    res = run(
        np.linspace(0, 6, m),
        np.full(m, 0.05),
        np.zeros(m, np.int32),
        (1e-3, 0.1, 0.0, 0.9),
        cap=1,
        progress=False,
        execution=Execution(devices=1),
    )
    assert set(Status(int(s)).label for s in res.status) == {"no_impact"}
    # the bound: every orbit's cap + 1 flights of at most 2 max_steps + 86 micro-steps, one after another
    assert max_kernel_calls(m, 1, 32, 4000) * 32 * 64 >= m * 2 * (2 * 4000 + 80)


def _cli(args, capsys):
    try:
        rc = main(args)
    except SystemExit as e:
        rc = e.code
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_cli_refuses_parameters_outside_the_box_in_one_line(capsys):
    """The issue's command: alpha up to 1e308 made the engine raise "no progress (bug)", exit 1."""
    rc, out, err = _cli(
        "bifurcation --param alpha --lo 1 --hi 1e308 --values 3 --transient 5 --impacts 5".split(), capsys
    )
    assert rc == 2 and out == ""
    assert err.strip().count("\n") == 0 and "--hi=1e+308" in err and "0 <= alpha <= 1e10" in err
    # the spelling (--keep, now --impacts): the rename note, then the same one-line error
    rc, out, err = _cli("bifurcation --param alpha --lo 1 --hi 1e308 --values 3 --transient 5 --keep 5".split(), capsys)
    lines = err.strip().splitlines()
    assert (
        rc == 2 and out == "" and len(lines) == 2 and "--keep is deprecated" in lines[0] and "--hi=1e+308" in lines[1]
    )
    rc, _, err = _cli("simulate --beta 1e308 --impacts 2".split(), capsys)
    assert rc == 2 and "0 < beta <= 1e10" in err and err.strip().count("\n") == 0


def test_cli_runs_at_the_corners(capsys):
    rc, out, err = _cli(
        "bifurcation --param alpha --lo 0 --hi 1e10 --values 3 --transient 5 --keep 5 --quiet".split(), capsys
    )
    assert rc == 0, err
    rows = out.strip().splitlines()[1:]
    assert len(rows) == 15 and all(len(r.split(",")) == 4 for r in rows)
    for args in (
        "--alpha 1e10 --beta 5e-324 --gamma -1e10 --r 1",
        "--alpha 0 --beta 1e10 --gamma 1e10 --r 5e-324",
        "--alpha 5e-324 --gamma -5e-324 --tau0 -1e6",
    ):
        rc, out, err = _cli(["simulate", *args.split(), "--impacts", "4"], capsys)
        assert rc == 0, err
        assert out.startswith("n,tau,") and "nan" not in out.split("\n", 2)[1]


# ---------------------------------------------------------------------------------- subnormal inputs


def _agree(a, b, p):
    ai, bi = a.kind == "impact", b.kind == "impact"
    assert a.status == b.status, (a.status, b.status)
    assert list(a.kind) == list(b.kind)
    assert np.array_equal(a.wall[ai], b.wall[bi]), (a.wall, b.wall)
    assert np.all(np.abs(a.tau - b.tau) <= 1e-9), (a.tau, b.tau)
    pp = (p.alpha, p.beta, p.gamma)
    assert _close(a.sdot[ai][1:], b.sdot[bi][1:], pp, (1e-9, 1e-6))


@pytest.mark.parametrize("sdot0", [x * sign for x in SUBNORMALS for sign in (1, -1)])
@pytest.mark.parametrize("tau0", [0.0, 2.0, 4.0])
def test_subnormal_sdot0_tracks_agree(sdot0, tau0):
    """``simulate --sdot0 1e-320`` put the orbit on wall -1 on the map track (XLA compared 1e-320 > 0
    as false) while scipy put it on wall 0; the wall is now decided on the bits."""
    p = Params(3.0, 0.1, 0.1, 0.9)
    m, s = orbit(p, tau0, sdot0, 4, track="map"), orbit(p, tau0, sdot0, 4, track="scipy")
    assert m.wall[0] == (0 if sdot0 > 0 else -1) and m.sdot[0] == sdot0
    _agree(m, s, p)


@pytest.mark.parametrize(
    "s0,sdot0", [(s0, sd) for s0 in (0.0, -1.0, -1e-320, -TINY) for sd in (1e-320, -1e-320, 0.5, -0.5, 0.0)]
)
@pytest.mark.parametrize("tau0", [0.0, 2.0, 4.0])
def test_subnormal_free_starts_tracks_agree(s0, sdot0, tau0):
    """Free-flight starts on a wall or a subnormal distance from it, with subnormal velocities: a start
    on a wall moving into it is a pre-impact state on every track (decided on the host)."""
    p = Params(3.0, 0.1, 0.1, 0.9)
    _agree(orbit(p, tau0, sdot0, 4, s0=s0, track="map"), orbit(p, tau0, sdot0, 4, s0=s0, track="scipy"), p)


@pytest.mark.parametrize("name", ["alpha", "beta", "gamma", "r"])
@pytest.mark.parametrize("value", [TINY, 1e-310])
def test_subnormal_parameters_tracks_agree(name, value):
    for tau0, sign in ((0.0, 1), (2.0, -1), (4.0, 1)):
        for v in (value, -value) if name == "gamma" else (value,):
            p = Params(**{**dict(alpha=3.0, beta=0.1, gamma=0.1, r=0.9), name: v})
            _agree(orbit(p, tau0, sign * SDOT0, 4, track="map"), orbit(p, tau0, sign * SDOT0, 4, track="scipy"), p)


def test_subnormal_sdot0_engine_agrees_with_map():
    sd = np.array([TINY, -TINY, 1e-320, -1e-320, 2e-308, -2e-308])
    tau0 = np.resize([0.0, 2.0, 4.0], sd.size)
    res = run(
        tau0, sd, np.where(sd > 0, 0, -1), Params(3.0, 0.1, 0.1, 0.9), Sample(keep=4, n_start=1), cap=4, progress=False
    )
    for i in range(sd.size):
        seq = map_orbit(Params(3.0, 0.1, 0.1, 0.9), tau0[i], sd[i], 4)
        ref = seq.sdot[seq.kind == "impact"][1:]
        assert np.allclose(res.obs[0]["sdot"][i], ref, rtol=1e-9, atol=0), (sd[i], res.obs[0]["sdot"][i], ref)


def test_cli_simulate_subnormal_sdot0_starts_on_the_upper_wall(capsys):
    rc, out, err = _cli("simulate --sdot0 1e-320 --impacts 3".split(), capsys)
    assert rc == 0, err
    first = out.splitlines()[1].split(",")
    assert first[3] == "0" and math.isclose(float(first[4]), 1e-320, rel_tol=1e-3)
