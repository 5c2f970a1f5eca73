"""Exponents from the Tangent observer's output: one function (:func:`mapimpl.engine.exponents.exponents`)
with one rule for sticking steps and for orbits that ended early, used by ``lyapunov``, the atlas and the
r1 analysis."""

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

from gear_rattle.core.params import Params
from gear_rattle.core.status import Status
from gear_rattle.mapimpl.engine.driver import run
from gear_rattle.mapimpl.engine.exponents import exponents, ran_to_end
from gear_rattle.mapimpl.engine.observers import Tangent
from gear_rattle.mapimpl.lyapunov import lyapunov
from gear_rattle.validation.atlas.compute import compute_tile
from gear_rattle.validation.atlas.spec import AtlasSpec
from gear_rattle.validation.dynamics.crises.r1 import lyapunov_at

#: Three orbits from (0, 0.5): stuck forever (alpha = 0.05, r = 0.5: an orbit that ends), one with free
#: and sticking steps (alpha = 3, r = 0.5) and one whose every step sticks (beta = 1e10).
ALPHA, BETA, R = [0.05, 3.0, 3.0], [0.1, 0.1, 1e10], [0.5, 0.5, 0.9]
TRANSIENT, N = 20, 200


@pytest.fixture(scope="module")
def three():
    p = {"alpha": np.array(ALPHA), "beta": np.array(BETA), "gamma": 0.1, "r": np.array(R)}
    return run(
        np.zeros(3),
        np.full(3, 0.5),
        np.zeros(3, np.int32),
        p,
        Tangent(n_start=TRANSIENT),
        cap=TRANSIENT + N,
        progress=False,
    )


def test_the_rule(three):
    """Ended early: NaN in both; a sticking step: lam = -inf and lam_free over the free steps (NaN: none)."""
    ex = exponents(three)
    assert three.status[0] == Status.STUCK_FOREVER and ex.ran.tolist() == [False, True, True] and ex.ended == 1
    assert np.all(np.isnan(ex.lam[0])) and np.all(np.isnan(ex.lam_free[0]))
    assert ex.n_stuck[1] > 0 and ex.n_free[1] > 0 and ex.n_free[1] + ex.n_stuck[1] == N
    assert np.all(np.isneginf(ex.lam[1])) and np.all(np.isfinite(ex.lam_free[1]))
    assert ex.n_stuck[2] == N and np.all(np.isneginf(ex.lam[2])) and np.all(np.isnan(ex.lam_free[2]))
    assert ran_to_end([Status.CAPPED, Status.STOPPED, Status.NO_IMPACT, Status.STEP_CAP]).tolist() == [
        True,
        True,
        False,
        False,
    ]


def test_bad_input(three):
    with pytest.raises(TypeError, match="res"):
        exponents(three.obs[0])
    with pytest.raises(ValueError, match="obs=1"):
        exponents(three, 1)
    sampled = dataclasses.replace(three, obs=({"sdot": three.sdot[:, None]},))  # a Sample observer's output
    with pytest.raises(ValueError, match="obs=0"):
        exponents(sampled)


def test_tangent_data_is_read_in_one_place():
    """The observer's sums (``log_r``, ``n_free``) are read only by the one function (and the observer and
    its own test): lyapunov, the atlas and r1 had each divided them themselves, by different rules."""
    root = Path(__file__).resolve().parents[1]
    own = {
        Path("mapimpl/engine/observers.py"),
        Path("mapimpl/engine/exponents.py"),
        Path("tests/test_engine.py"),
        Path("tests/test_exponents.py"),
    }
    readers = [
        p.relative_to(root)
        for d in ("core", "mapimpl", "reference", "validation", "gear_rattle", "tests")
        for p in (root / d).rglob("*.py")
        if re.search(r"""["'](log_r|n_free)["']""", p.read_text())
    ]
    assert readers and set(readers) <= own, sorted(map(str, set(readers) - own))


@pytest.mark.slow
def test_lyapunov_and_the_atlas_give_the_functions_values(three):
    """The same orbits through ``lyapunov`` and the atlas's ``compute_tile``: bit-identical exponents.
    Slow: two more engine compilations (~10 s each on a loaded 2-core machine)."""
    ex = exponents(three)
    res = lyapunov(Params(0.05, 0.1, 0.1, 0.5), "alpha", ALPHA[:2], n=N, transient=TRANSIENT, progress=False)
    assert np.array_equal(res.lam, ex.lam[:2], equal_nan=True)
    assert np.array_equal(res.lam_free, ex.lam_free[:2], equal_nan=True)
    assert res.active.tolist() == ex.ran[:2].tolist()
    tile = compute_tile(np.array(ALPHA[:2]), np.array(R[:2]), AtlasSpec(transient=TRANSIENT, impacts=N, period_max=2))
    assert np.array_equal(tile["lambda1"], ex.lam[:2, 0], equal_nan=True)
    assert np.array_equal(tile["lambda2"], ex.lam[:2, 1], equal_nan=True)


def test_r1_gives_no_exponent_to_orbits_that_ended():
    """r1's ``lyapunov_at`` averaged over the impacts an orbit made before it ended (lam1_min = -0.0131
    on these stuck-forever orbits, and no count of them): now NaN by the one rule, with ``ended``."""
    ics = {"theta": np.zeros(2), "sdot": np.full(2, 0.5), "wall": np.zeros(2, np.int32)}
    d = lyapunov_at(0.5, ics, 2, N, base=Params(0.05, 0.1, 0.1, 0.5), transient=TRANSIENT)
    assert d["ended"] == 2 and np.isnan(d["lam1_min"]) and np.isnan(d["lam1_max"]) and not d["chaotic"]
