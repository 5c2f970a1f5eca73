"""The registry of tracks finds the numerical tracks without importing a module named in a string
(issue 32 item 3): the package's facade registers a loader per track (gear_rattle/_tracks.py,
core/registry.py), whose import statements the import contract and tests/test_import_cycles.py see."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from gear_rattle.core import registry
from gear_rattle.core.results import TRACKS

REPO = Path(__file__).resolve().parent.parent


def test_every_numerical_track_is_registered_by_importing_the_package():
    assert registry.registered_tracks() == tuple(t for t in TRACKS if t != "map")


def test_the_registry_loads_the_reference_modules_track():
    from gear_rattle.mapimpl.tracks import get
    from gear_rattle.reference import scipy_track

    assert get("scipy") is scipy_track.TRACK


def test_register_track_checks_its_arguments(monkeypatch):
    monkeypatch.setattr(registry, "_LOADERS", {})
    with pytest.raises(ValueError, match="name='rk4' is out of range"):
        registry.register_track("rk4", lambda: None)
    with pytest.raises(ValueError, match="name='map' is out of range"):
        registry.register_track("map", lambda: None)
    with pytest.raises(TypeError, match="load=.* is not callable"):
        registry.register_track("scipy", "gear_rattle.reference.scipy_track")
    with pytest.raises(LookupError, match="track 'scipy' has no registered loader"):
        registry.load_track("scipy")
    sentinel = object()
    registry.register_track("scipy", lambda: sentinel)
    assert registry.load_track("scipy") is sentinel and registry.registered_tracks() == ("scipy",)


def string_imports(folders=("core", "mapimpl", "reference"), repo: Path = REPO) -> list[str]:
    """``path:line`` of every ``importlib.import_module(...)`` or ``__import__(...)`` call in the library."""
    out = []
    for folder in folders:
        for path in sorted((repo / folder).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(), str(path))):
                if isinstance(node, ast.Call):
                    f = node.func
                    name = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else ""
                    if name in ("import_module", "__import__"):
                        out.append(f"{path.relative_to(repo).as_posix()}:{node.lineno}")
    return out


def test_the_library_imports_no_module_by_name(tmp_path):
    assert string_imports() == []
    (tmp_path / "mapimpl").mkdir()
    (tmp_path / "mapimpl" / "t.py").write_text("import importlib\nM = importlib.import_module('x.y')\n")
    assert string_imports(("mapimpl",), tmp_path) == ["mapimpl/t.py:2"]


#: The package's calls that import a module named in a string: each imports an external package (never a
#: module of gear_rattle, so it hides no edge of the import contract), and why it is not an import statement.
EXTERNAL_BY_NAME = {
    "validation/extras.py": "an optional extra (zarr, dask) through extras.require: the light install lacks it",
    "validation/report/builder.py": "each dependency's __version__ for the report's provenance (a loop)",
}


def test_the_package_imports_its_own_modules_by_statement():
    """Issue 32 item 3: the subcommands (validation.cli.command_modules) and the report's sections
    (validation.report.builder.section_modules) are imported by import statements, which lint-imports and
    tests/test_import_cycles.py see; what is left imports external packages alone (docs/architecture.md)."""
    found = string_imports(("gear_rattle", "core", "mapimpl", "reference", "validation"))
    assert sorted(f.split(":")[0] for f in found) == sorted(EXTERNAL_BY_NAME), found


def test_the_command_and_section_lists_are_the_modules_themselves():
    from gear_rattle.validation import cli, commands
    from gear_rattle.validation.report import builder

    mods = cli.command_modules()
    assert all(m.__name__.startswith(commands.__name__ + ".") for m in mods) and len({m.NAME for m in mods}) == 13
    # the light table the parser lists the commands from is the modules' names, in order (issue 39): a
    # module that still states its own help says the table's
    assert [m.NAME for m in mods] == list(cli.SUBCOMMANDS)
    assert all(getattr(m, "HELP", cli.SUBCOMMANDS[m.NAME]) == cli.SUBCOMMANDS[m.NAME] for m in mods)
    secs = builder.section_modules()
    assert [m.KEY for m in secs] == builder.SECTION_KEYS == [m.__name__.rsplit(".sec_", 1)[1] for m in secs]
