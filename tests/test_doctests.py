"""The Examples sections of the entry points' docstrings run as doctests (issue 24: the ~15 real entry points
have numpydoc Parameters/Returns/Examples, and the examples run in CI).

One test per docstring with examples in :data:`MODULES`, run by :mod:`doctest` on the installed module (the
repository's folders are the ``gear_rattle`` namespace, which ``pytest --doctest-modules`` would import under
other names).  Each example is small (seconds, mostly JIT compilation); the examples of one module share its
globals, as in ``python -m doctest``.  :func:`test_entry_points_are_documented` checks that every entry point
has the three sections, so an entry point cannot lose its example unnoticed.
"""

from __future__ import annotations

import doctest
import importlib
import io

import pytest

#: Modules whose docstrings' examples run here.
MODULES = (
    "gear_rattle.mapimpl.tracks",
    "gear_rattle.mapimpl.finder",
    "gear_rattle.mapimpl.orbit",
    "gear_rattle.mapimpl.periodic",
    "gear_rattle.mapimpl.lyapunov",
    "gear_rattle.mapimpl.engine.driver",
    "gear_rattle.mapimpl.engine.exponents",
    "gear_rattle.mapimpl.engine.transients",
    "gear_rattle.mapimpl.certified.contact",
    "gear_rattle.mapimpl.certified.orbit",
    "gear_rattle.mapimpl.certified.track",
    "gear_rattle.mapimpl.certified.duration",
    "gear_rattle.mapimpl.certified.periodic",
    "gear_rattle.validation.dynamics.crises.r2",
    "gear_rattle.validation.dynamics.crises.r1",
    "gear_rattle.validation.dynamics.crises.alpha1",
    "gear_rattle.validation.atlas.compute",
    "gear_rattle.validation.atlas.run",
)

#: The entry points (module, function) that must have Parameters, Returns and Examples sections.
ENTRY_POINTS = (
    ("gear_rattle", "orbit"),
    ("gear_rattle", "find_periodic"),
    ("gear_rattle", "transient_times"),
    ("gear_rattle.mapimpl.finder", "first_impact"),
    ("gear_rattle.mapimpl.orbit", "map_orbit"),
    ("gear_rattle.mapimpl.periodic", "find_periodic"),
    ("gear_rattle.mapimpl.engine.driver", "run"),
    ("gear_rattle.mapimpl.engine.transients", "transient_times"),
    ("gear_rattle.mapimpl.certified.contact", "certified_flight"),
    ("gear_rattle.mapimpl.certified.orbit", "certify_orbit"),
    ("gear_rattle.mapimpl.certified.track", "certified_orbit"),
    ("gear_rattle.mapimpl.certified.duration", "certified_release_duration"),
    ("gear_rattle.mapimpl.certified.periodic", "certify_periodic_orbit"),
    ("gear_rattle.mapimpl.certified.periodic", "certify_bifurcation"),
    ("gear_rattle.validation.dynamics.crises.r2", "locate_r2"),
    ("gear_rattle.validation.dynamics.crises.r1", "locate_r1"),
    ("gear_rattle.validation.dynamics.crises.alpha1", "locate_alpha1"),
    ("gear_rattle.validation.atlas.compute", "compute_tile"),
    ("gear_rattle.validation.atlas.run", "run_atlas"),
)

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _doctests():
    finder = doctest.DocTestFinder(exclude_empty=True)
    out = []
    for name in MODULES:
        module = importlib.import_module(name)
        # the module's own docstrings only (not those of the names it imports), in source order
        tests = [t for t in finder.find(module, name) if t.examples and t.filename == module.__file__]
        out += sorted(tests, key=lambda t: t.lineno or 0)
    return out


@pytest.fixture(scope="module")
def globs():
    """One namespace per module, shared by its docstrings' examples in source order."""
    return {}


@pytest.mark.parametrize("test", _doctests(), ids=lambda t: t.name)
def test_examples(test, globs, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # an example that writes files writes them here
    test.globs = globs.setdefault(test.filename, dict(test.globs))
    buf = io.StringIO()
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    result = runner.run(test, out=buf.write, clear_globs=False)
    assert result.attempted > 0
    assert result.failed == 0, buf.getvalue()


@pytest.mark.parametrize("module,name", ENTRY_POINTS, ids=lambda x: x)
def test_entry_points_are_documented(module, name):
    doc = getattr(importlib.import_module(module), name).__doc__ or ""
    for section in ("Parameters\n", "Returns\n", "Examples\n"):
        assert section in doc, f"{module}.{name}: no numpydoc section {section.strip()!r}"
    assert ">>> " in doc
