"""The documentation names code that exists.

The docs site (``python -m sphinx -W -n -b html docs OUT``, CI) fails on a dangling cross-reference in the
docstrings of the modules it documents.  These tests cover the rest: a name of the code written as code in
the Markdown pages and READMEs (```mapimpl.engine.observers.orbit_distance```, ```validation/golden/```)
and the cross-references (``:func:`score_file```) in every module, the command line's and the golden
suite's included.  They run without Sphinx."""

from __future__ import annotations

import functools
import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("core", "mapimpl", "reference", "validation")
PACKAGE_DIRS = {"gear_rattle": ROOT / "gear_rattle", **{f: ROOT / f for f in FOLDERS}}

# ``mapimpl.orbit.map_orbit``, ``gear_rattle.core.params``, ``validation/golden/cases/``, ``tests/conftest.py``
CODE_NAME = re.compile(
    r"(`{1,2})((?:gear_rattle\.)?(?:core|mapimpl|reference|validation|tests|benchmarks|docs)"
    r"(?:[./][A-Za-z_]\w*)+(?:\.py|\.md|\.json|/)?)\1"
)
# :func:`name`, :class:`~.results.R1Result`, :mod:`.krawczyk` (a role's target)
ROLE = re.compile(r":(?:py:)?(func|class|meth|mod|data|attr|obj|exc):`~?([\w.]+)`")


def _lookup(dotted: str):
    """The object named ``gear_rattle.a.b.c`` (imported as far as it is a module, then attributes), or None."""
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        try:
            for attr in parts[i:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None
        return obj
    return None


def _exists(name: str) -> bool:
    if "/" in name or name.endswith((".py", ".md", ".json")):
        return (ROOT / name).exists()
    if name.split(".")[0] in ("tests", "benchmarks", "docs"):
        return (ROOT / name.replace(".", "/")).exists() or (ROOT / (name.replace(".", "/") + ".py")).exists()
    dotted = name if name.startswith("gear_rattle.") else "gear_rattle." + name
    return _lookup(dotted) is not None


def _module_name(path: Path) -> str:
    for pkg, folder in PACKAGE_DIRS.items():
        if folder in path.parents:
            rel = path.relative_to(folder).with_suffix("")
            parts = [p for p in rel.parts if p != "__init__"]
            return ".".join(["gear_rattle"] + ([] if pkg == "gear_rattle" else [pkg]) + parts)
    raise ValueError(path)


@functools.cache
def _index() -> frozenset[str]:
    """Full names of every module, class, function and constant of the package, and of the members and
    fields of its classes (``gear_rattle.validation.dynamics.crises.r2.CertifiedR2.decimal``)."""
    names = set()
    for path in _sources():
        if path.name == "__main__.py":
            continue
        mod = importlib.import_module(_module_name(path))
        names.add(mod.__name__)
        for attr, obj in vars(mod).items():
            names.add(f"{mod.__name__}.{attr}")
            if isinstance(obj, type) and obj.__module__ == mod.__name__:
                members = set(vars(obj)) | set(getattr(obj, "__annotations__", {}))
                names.update(f"{mod.__name__}.{attr}.{m}" for m in members)
    return frozenset(names)


def _resolves(target: str, module: str) -> bool:
    """A role's target as the code reads it: absolute, by folder, relative to the module or a package above
    it, or as the end of one name of the package (``Status`` in ``core/__init__.py``, ``label`` in a
    class) -- the way the docs site resolves it (docs/conf.py)."""
    name = target.lstrip(".")
    candidates = [name, "gear_rattle." + name]
    parts = module.split(".")
    candidates += [".".join(parts[:i]) + "." + name for i in range(len(parts), 0, -1)]
    if any(_lookup(c) is not None for c in candidates if c.startswith("gear_rattle")):
        return True
    return any(n.endswith("." + name) for n in _index())


def _sources() -> list[Path]:
    return sorted(p for d in PACKAGE_DIRS.values() for p in d.rglob("*.py") if "__pycache__" not in p.parts)


def _pages() -> list[Path]:
    """Every Markdown page of docs/ (its subfolders too), but not what a command or the build writes: the
    published report (docs/report/), the build and the generated command reference."""
    generated = ("docs/report/", "docs/_build/", "docs/api/generated/", "docs/reference/commands.md")
    pages = [p for p in ROOT.glob("docs/**/*.md") if not str(p.relative_to(ROOT)).startswith(generated)]
    return sorted(pages) + [ROOT / "README.md", ROOT / "validation/golden/README.md"]


@pytest.mark.parametrize("path", _pages() + _sources(), ids=lambda p: str(p.relative_to(ROOT)))
def test_code_names_exist(path):
    missing = sorted({m.group(2) for m in CODE_NAME.finditer(path.read_text()) if not _exists(m.group(2))})
    assert not missing, f"{path.relative_to(ROOT)} names code that does not exist: {', '.join(missing)}"


@pytest.mark.parametrize("path", _sources(), ids=lambda p: str(p.relative_to(ROOT)))
def test_cross_references_resolve(path):
    module = _module_name(path)
    text = path.read_text()
    external = (
        "np.",
        "numpy.",
        "jax.",
        "scipy.",
        "flint.",
        "diffrax.",
        "optimistix.",
        "matplotlib.",
        "dask.",
        "distributed.",
        "zarr.",
        "mpmath.",
        "json.",
        "math.",
        "os.",
        "sys.",
        "argparse.",
        "pathlib.",
        "Figure.",
    )
    missing = sorted({t for _, t in ROLE.findall(text) if not t.startswith(external) and not _resolves(t, module)})
    assert not missing, f"{path.relative_to(ROOT)}: cross-references to nothing: {', '.join(missing)}"


def test_the_checks_catch_what_they_are_for():
    """The names issue 24 found dangling are caught (and real ones pass)."""
    assert not _exists("mapimpl.engine.kernel.distance") and not _exists("validation/dynamics/crises.py")
    assert _exists("mapimpl.engine.observers.orbit_distance") and _exists("validation/dynamics/crises/")
    assert not _resolves("score_case", "gear_rattle.validation.golden.scoring.cases")
    assert _resolves("score_file", "gear_rattle.validation.golden.scoring.cases")
    assert _resolves(".krawczyk", "gear_rattle.mapimpl.certified.periodic")
    assert not _resolves("advance", "gear_rattle.validation.dynamics.bifurcation")
