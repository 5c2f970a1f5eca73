"""The Track protocol and the registry (mapimpl/tracks.py), and the shared result types
(core/results.py): every track -- the closed-form map (Eqs. 12-13) and Eq. (3) integrated by
scipy and by diffrax -- offers ``orbit`` and ``step_jacobian`` with the same signatures, result
types and conventions."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import gear_rattle  # noqa: F401  (float64: importing the package switches JAX to it)
import jax

from gear_rattle.mapimpl.impact_map import step
from gear_rattle.core.state import make_state
from gear_rattle.mapimpl.orbit import map_orbit
from gear_rattle.core.params import Params
from gear_rattle.core.results import COLUMNS, KINDS, ImpactSequence, StepJacobian, Track
from gear_rattle.core.status import TRACK_STATUSES
from gear_rattle.mapimpl import tracks as T
from refhelpers import JAC_TOL

PAPER = Params(3.0, 0.1, 0.1, 0.9)  # Fig. 3's chaotic attractor
CHATTER = Params(2.0, 0.1, 1.0, 0.5)  # golden case 0007: chatter, sticking, release
STUCK = Params(0.5, 0.1, 0.9, 0.5)  # golden case 0008: stuck forever


@pytest.mark.parametrize("name", T.TRACKS)
def test_every_track_implements_the_protocol(name):
    track = T.get(name)
    assert isinstance(track, Track)
    assert track.name == name


def test_something_without_the_methods_is_not_a_track():
    assert not isinstance(object(), Track)
    assert not isinstance(map_orbit, Track)


def test_registry_errors():
    with pytest.raises(ValueError, match="track='euler' is out of range"):
        T.get("euler")
    with pytest.raises(ValueError, match="option rtol=1e-05 is out of range"):
        T.orbit(PAPER, 0.0, 0.5, 3, track="map", rtol=1e-5)
    for name in T.TRACKS:
        with pytest.raises(ValueError, match="wall=2 is out of range"):
            T.step_jacobian(name, PAPER, 0.0, 0.5, wall=2)


def test_the_registry_imports_diffrax_lazily():
    code = "import sys, gear_rattle.mapimpl.tracks as T; T.get('map'); T.get('scipy'); print('diffrax' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize("name", ["map", "scipy"])
def test_orbit_through_the_registry_is_the_track_orbit(name):
    seq = T.orbit(PAPER, 0.0, 0.5, 6, track=name)
    assert isinstance(seq, ImpactSequence) and seq.track == name and seq.status in TRACK_STATUSES
    if name == "map":
        assert seq.to_csv() == map_orbit(PAPER, 0.0, 0.5, 6).to_csv()
    assert seq.to_csv().splitlines()[0] == ",".join(COLUMNS)
    assert set(seq.kind) <= set(KINDS)


def test_map_step_jacobian_is_the_analytic_jacobian_of_the_map_step():
    new, info = jax.jit(step)(make_state(0.0, 0.5), PAPER.arrays())
    sj = T.step_jacobian("map", PAPER, 0.0, 0.5)
    assert isinstance(sj, StepJacobian)
    assert np.array_equal(sj.jac, np.asarray(info.jac)) and sj.tau == float(new.tau) and sj.sdot == float(new.sdot)
    assert (sj.wall, sj.stuck, sj.status) == (int(new.wall), False, "active")


def test_step_jacobian_of_map_and_scipy_agree_through_the_protocol():
    """One step at the paper's Fig. 3 parameters, map (Eqs. 12-13) and Eq. (3) integrated: measured
    1.5e-14 (tau), 3.6e-14 (sdot), 4.8e-15 (1 + |J|) (Jacobian); bounds 1e-13 and JAC_TOL (refhelpers)."""
    m, s = (T.get(t).step_jacobian(PAPER, 0.0, 0.5) for t in ("map", "scipy"))
    assert m.wall == s.wall and m.status == s.status == "active"
    assert abs(m.tau - s.tau) < 1e-13 and abs(m.sdot - s.sdot) < 1e-13
    assert np.abs(m.jac - s.jac).max() <= JAC_TOL * (1.0 + np.abs(m.jac).max())


def _before_first_stick(p: Params) -> tuple[float, float]:
    seq = map_orbit(p, 0.0, 0.5, 40)
    i = list(seq.kind).index("stick") - 1
    assert seq.kind[i] == "impact"
    return float(seq.tau[i]), float(seq.sdot[i])


@pytest.mark.parametrize("name", T.TRACKS)
def test_a_sticking_step_forgets_its_input_on_every_track(name):
    """A sticking step forgets its input (J = 0) and continues like the map's step: the impact after the
    release agrees to 5.3e-15 (tau ~ 8.7) and 1.0e-14 (sdot) (measured, scipy; diffrax and map closer);
    bound 1e-13."""
    # golden case 0007: the step sticks, is released and flies on to the next impact (J = 0)
    tau, sd = _before_first_stick(CHATTER)
    ref = map_orbit(CHATTER, tau, sd, 1)
    sj = T.step_jacobian(name, CHATTER, tau, sd)
    assert sj.stuck and sj.status == "active" and np.array_equal(sj.jac, np.zeros((2, 2)))
    assert sj.wall == int(ref.wall[-1]) and abs(sj.tau - ref.tau[-1]) < 1e-13 and abs(sj.sdot - ref.sdot[-1]) < 1e-13
    # golden case 0008: stuck forever, no next state
    tau, sd = _before_first_stick(STUCK)
    sj = T.step_jacobian(name, STUCK, tau, sd)
    assert sj.stuck and sj.status == "stuck_forever" and np.isnan(sj.tau) and np.array_equal(sj.jac, np.zeros((2, 2)))


@pytest.mark.parametrize("name", T.TRACKS)
def test_a_flight_without_impact_ends_the_step_on_every_track(name):
    # no forcing, a slow bounce off s = 0: the damped flight stops short of s = -1 (r sdot / beta < 1)
    sj = T.step_jacobian(name, Params(0.0, 0.1, 0.0, 0.9), 0.0, 0.01)
    assert sj.status == "no_impact" and not sj.stuck and np.isnan(sj.tau) and np.isnan(sj.jac).all()


def test_status_names_come_from_one_place():
    """Every track's status names are the labels of the one status enum (core.status.Status), each
    code has a message, and a label maps back to its code (the names in files are unchanged)."""
    from gear_rattle.core.status import FlightOutcome, Status

    assert TRACK_STATUSES == ("active", "stuck_forever", "no_impact", "step_cap")
    assert all(Status.from_label(s).label == s for s in TRACK_STATUSES)
    assert [int(Status[s.upper()]) for s in TRACK_STATUSES] == [0, 1, 2, 3]
    for enum in (Status, FlightOutcome):
        assert all(isinstance(m.message, str) and len(m.message) > 10 for m in enum)
    assert int(FlightOutcome.NO_IMPACT) == int(Status.NO_IMPACT) and int(FlightOutcome.STEP_CAP) == int(Status.STEP_CAP)
    with pytest.raises(ValueError, match="hit"):
        Status.from_label("hit")


def test_the_golden_suite_file_format_is_the_result_type_layout():
    from gear_rattle.validation.golden.formats import cases

    assert cases.COLUMNS == COLUMNS and cases.KINDS == KINDS
