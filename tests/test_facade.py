"""The public vocabulary of ``gear_rattle`` (issue 32 item 4): the facade's names are the library's own
objects, ``params`` comes first in every function, one ``progress`` default, every result type is exported
and says whether it worked through ``ok`` / ``status`` / ``message`` built on ``Status``, ``tau`` is
absolute time and ``theta`` the phase, and the old spellings still work with a DeprecationWarning that
names the new one.  Cheap: the one computation is a 3-impact periodic orbit (compiled once per session)."""

from __future__ import annotations

import inspect
import subprocess
import sys

import numpy as np
import pytest

import gear_rattle as gr

FUNCTIONS = ("orbit", "find_periodic", "lyapunov", "transient_times")
RESULTS = (
    "ImpactSequence",
    "CertifiedSequence",
    "StepJacobian",
    "PeriodicOrbit",
    "LyapunovResult",
    "TransientResult",
    "SurvivalResult",
)
FIG2 = gr.Params(0.5, 0.1, 0.1, 0.9)


@pytest.fixture(scope="module")
def fig2_orbit():
    return gr.find_periodic(FIG2, 2.034, -0.7343, period=3)


def test_dir_shows_the_public_api_only():
    """dir(gr) listed ``annotations`` and ``core`` beside the API."""
    assert dir(gr) == sorted(gr.__all__)
    assert "annotations" not in dir(gr) and "core" not in dir(gr)
    for name in gr.__all__:
        assert getattr(gr, name) is not None


def test_importing_the_facade_imports_no_jax():
    code = "import sys, gear_rattle as gr; dir(gr); print('jax' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def _loaded(code: str) -> set[str]:
    """The modules a fresh interpreter has loaded after running ``code``."""
    code += "\nimport sys; print(' '.join(sorted(sys.modules)), file=sys.stderr)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    mods = set(out.stderr.strip().splitlines()[-1].split())
    assert "gear_rattle" in mods and "sys" in mods, out.stderr[-2000:]
    return mods


def test_importing_the_facade_loads_neither_numpy_nor_the_command_line():
    """Issue 39: ``import gear_rattle`` loaded the command line's signal module first (and numpy); the
    names that need more are loaded on first use, the progress display when a bar is first drawn."""
    mods = _loaded("import gear_rattle as gr; gr.TRACKS, gr.Status, gr.use_cpu_devices")
    ours = {m for m in mods if m.startswith("gear_rattle")}
    assert "numpy" not in mods and "jax" not in mods, sorted(ours)
    assert not any(m.startswith("gear_rattle.validation") for m in ours), sorted(ours)
    assert len(ours) <= 8, sorted(ours)
    # what is loaded on first use is the library's own object, and the progress display is registered
    mods = _loaded("import gear_rattle as gr; from gear_rattle.core import progress as P; P.Bar('x', enabled=True)")
    assert "gear_rattle.validation.progress" in mods


@pytest.mark.parametrize("argv", [["--version"], ["check", "--help"], ["check", "DIR"]])
def test_the_command_line_loads_only_the_command_it_runs(argv, tmp_path):
    """Issue 39: building the parser imported every command (54 modules, the report builder among them, for
    ``gear-rattle check``); the parser lists the others from a table and imports the chosen one's module."""
    argv = [str(tmp_path) if a == "DIR" else a for a in argv]
    code = (
        f"import sys; sys.argv = ['gear-rattle', *{argv!r}]\n"
        "from gear_rattle.validation.cli import _run\n"
        "try:\n    _run(None)\nexcept SystemExit:\n    pass"
    )
    mods = _loaded(code)
    assert "gear_rattle.validation.cli" in mods
    commands = {m.rsplit(".", 1)[1] for m in mods if m.startswith("gear_rattle.validation.commands.")}
    assert commands <= ({"check", "_check_common"} if argv[0] == "check" else set()), commands
    assert not any(m.startswith("gear_rattle.validation.report") for m in mods)
    assert ("numpy" in mods) == (argv[0] == "check") and "jax" not in mods


@pytest.mark.parametrize("name", FUNCTIONS)
def test_functions_are_the_library_s_own_with_params_first(name):
    """No renaming shim: gr.find_periodic took ``period`` where the library took ``impacts``, gr.lyapunov
    ``n_impacts`` for ``n``, and gr.transient_times took ``params`` third."""
    f = getattr(gr, name)
    assert f.__module__.startswith("gear_rattle.mapimpl."), f.__module__
    assert getattr(sys.modules[f.__module__], name) is f
    params = list(inspect.signature(f).parameters.values())
    assert params[0].name == "params"
    if "progress" in inspect.signature(f).parameters:
        assert inspect.signature(f).parameters["progress"].default is None  # one default (was False in orbit)


def test_one_progress_default_down_the_tracks():
    from gear_rattle.mapimpl.orbit import map_orbit
    from gear_rattle.reference.scipy_track import orbit as scipy_orbit

    for f in (map_orbit, scipy_orbit):
        assert inspect.signature(f).parameters["progress"].default is None, f


@pytest.mark.parametrize("name", RESULTS)
def test_every_result_type_is_exported_and_says_whether_it_worked(name):
    cls = getattr(gr, name)
    for attr in ("ok", "message"):
        assert isinstance(inspect.getattr_static(cls, attr), property), (name, attr)
    assert "status" in getattr(cls, "__dataclass_fields__", {}) or hasattr(cls, "status") or "status" in cls._fields


def test_the_status_enum_says_what_is_an_answer():
    S = gr.Status
    assert [s for s in S if not s.ok] == [S.NOT_RUN, S.STEP_CAP, S.NOT_CONVERGED]
    assert S.CONVERGED.message and S.NOT_CONVERGED.label == "not_converged"


def test_one_and_many_results_answer_alike(fig2_orbit):
    from gear_rattle.core.outcome import describe

    orb = fig2_orbit
    assert (orb.ok, orb.status, orb.converged) == (True, "converged", True)
    assert orb.message == "converged: " + gr.Status.CONVERGED.message
    seq = gr.ImpactSequence(
        FIG2,
        *(np.zeros(1),) * 2,
        np.zeros(1),
        np.zeros(1, int),
        np.full(1, np.nan),
        np.array(["impact"]),
        status="step_cap",
    )
    assert not seq.ok and seq.message.startswith("step_cap: ")
    codes = np.array([4, 4, 5, 3], np.int32)
    assert describe(codes).startswith("4 orbits: 1 step_cap (") and "2 stopped" in describe(codes)


def test_tau_is_time_and_theta_the_phase(fig2_orbit):
    """PeriodicOrbit.tau was the phase tau mod 2 pi, where ImpactSequence.tau is absolute time."""
    orb = fig2_orbit
    assert np.all((orb.theta >= 0) & (orb.theta < 2 * np.pi)) and orb.period == 3
    with pytest.warns(DeprecationWarning, match=r"PeriodicOrbit\.tau is deprecated: use \.theta"):
        assert np.array_equal(orb.tau, orb.theta)
    with pytest.warns(DeprecationWarning, match=r"PeriodicOrbit\.impacts is deprecated: use \.period"):
        assert orb.impacts == 3


def test_old_keyword_names_warn_and_work(fig2_orbit):
    with pytest.warns(DeprecationWarning, match="impacts= is deprecated: use period="):
        old = gr.find_periodic(FIG2, 2.034, -0.7343, impacts=3)
    assert np.array_equal(old.theta, fig2_orbit.theta)
    with pytest.raises(TypeError, match="not both"):
        gr.find_periodic(FIG2, 2.034, -0.7343, period=3, impacts=3)
    with (
        pytest.warns(DeprecationWarning, match="n= is deprecated: use n_impacts="),
        pytest.raises(ValueError, match="^n_impacts="),
    ):  # refused before computing: named anew
        gr.lyapunov(FIG2, n=0)


def test_old_argument_orders_warn_and_work():
    with pytest.warns(DeprecationWarning, match=r"use orbit\(params, tau0, sdot0, n_impacts, track=track\)"):
        seq = gr.orbit("map", FIG2, 0.0, 0.5, 2)
    assert seq.track == "map" and seq.ok
    with (
        pytest.warns(DeprecationWarning, match=r"use transient_times\(params, tau0, sdot0\)"),
        pytest.raises(ValueError, match="^sdot0"),
    ):  # the old order is read as such: sdot0 = 0 is refused
        gr.transient_times([3.2], [0.0])
    with pytest.raises(TypeError, match="missing sdot0"):
        gr.transient_times(None, [3.2])
