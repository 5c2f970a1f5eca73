"""What a user installs is what the code imports (issue 20).

A default code path imports only the core dependencies of ``pyproject.toml``; the optional extras
(``atlas``: zarr, dask[distributed]; ``bench``: numba) are imported through
:func:`gear_rattle.validation.extras.require` only, and a command whose extra is missing prints one
line naming it and exits 2.  The extras are blocked here by ``sys.modules[name] = None`` in a fresh
interpreter (an ``import`` of a blocked name raises ImportError, as for a package never installed).
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import gear_rattle
from gear_rattle.validation.extras import EXTRAS, MissingExtra, require

REPO = Path(__file__).resolve().parents[1]
PACKAGE_DIRS = ("gear_rattle", "mapimpl", "reference", "validation")
#: Import names of the core dependencies (distribution name -> module name where they differ).
MODULE_OF = {"python-flint": "flint"}
#: Test-only packages and every extra's modules: none may be imported on a default path.
BLOCKED = ("zarr", "dask", "distributed", "numba", "hypothesis", "pytest", "mpmath")


def _core_modules() -> set[str]:
    deps = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["dependencies"]
    names = set()
    for d in deps:
        dist = d.split(";")[0].split("[")[0]
        for op in "<>=!~ ":
            dist = dist.split(op)[0]
        names.add(MODULE_OF.get(dist, dist.replace("-", "_")))
    return names


def _type_checking_only(tree: ast.AST) -> set[int]:
    """``id`` of every node under an ``if TYPE_CHECKING:`` block: imports there name types for the type
    checker and never run."""
    out: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", getattr(node.test, "attr", None)) == "TYPE_CHECKING":
            out |= {id(n) for b in node.body for n in ast.walk(b)}
    return out


def _imports(path: Path):
    """Top-level names of every absolute import statement in ``path`` that runs (module level or inside
    functions; not those under ``if TYPE_CHECKING:``)."""
    tree = ast.parse(path.read_text(), str(path))
    skip = _type_checking_only(tree)
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            for a in node.names:
                yield node.lineno, a.name.split(".")[0]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            yield node.lineno, node.module.split(".")[0]


def test_the_package_imports_only_core_dependencies_and_the_standard_library():
    """Every import statement of the installed package names the standard library, a core dependency of
    pyproject.toml or the package itself; an extra is reached through ``extras.require`` only."""
    allowed = _core_modules() | set(sys.stdlib_module_names) | {"gear_rattle", "__future__"}
    bad = []
    for d in PACKAGE_DIRS:
        for f in sorted((REPO / d).rglob("*.py")):
            bad += [f"{f.relative_to(REPO)}:{line}: import {name}" for line, name in _imports(f) if name not in allowed]
    assert not bad, "imports outside the core dependencies:\n" + "\n".join(bad)
    assert set(BLOCKED) >= {m for mods in EXTRAS.values() for m in mods}


def _blocked_python(code: str, blocked=BLOCKED, cwd=None) -> subprocess.CompletedProcess:
    prelude = f"import sys\nfor _m in {tuple(blocked)!r}:\n    sys.modules[_m] = None\n"
    env = {**os.environ, "MPLBACKEND": "Agg"}
    return subprocess.run(
        [sys.executable, "-c", prelude + code], capture_output=True, text=True, cwd=cwd, env=env, timeout=300
    )


def test_every_module_imports_with_the_extras_and_test_tools_missing():
    """Import every module of the package in an interpreter where the extras, pytest, hypothesis and
    mpmath cannot be imported."""
    code = (
        "import importlib, pkgutil\n"
        "names = ['gear_rattle.__main__']\n"
        "for top in ('mapimpl', 'reference', 'validation'):\n"
        "    pkg = importlib.import_module('gear_rattle.' + top)\n"
        "    names += [m.name for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + '.')\n"
        "              if not m.name.endswith('.__main__')]\n"
        "for n in names:\n    importlib.import_module(n)\n"
        "print(len(names))\n"
    )
    p = _blocked_python(code)
    assert p.returncode == 0, p.stderr
    assert int(p.stdout) > 40


@pytest.mark.parametrize(
    "blocked, scheduler, module", [(("zarr",), "serial", "zarr"), (("distributed", "dask"), "local", "distributed")]
)
def test_atlas_without_its_extra_is_one_line_naming_the_extra(tmp_path, blocked, scheduler, module):
    """``gear-rattle atlas`` with its extra missing: one line naming the extra, exit 2, nothing written."""
    out = tmp_path / "atlas-out"
    code = (
        "from gear_rattle.validation.cli import main\n"
        f"sys.exit(main(['atlas', '--n-alpha', '2', '--n-r', '2', '--scheduler', {scheduler!r}, "
        f"'--transient', '5', '--impacts', '5', '--out', {str(out)!r}]))\n"
    )
    p = _blocked_python(code, blocked)
    assert p.returncode == 2, p.stderr
    assert p.stderr.count("\n") == 1 and "Traceback" not in p.stderr
    assert p.stderr.startswith("gear-rattle atlas: error: ")
    assert module in p.stderr and 'pip install "gear-rattle[atlas]"' in p.stderr
    assert p.stdout == "" and not out.exists()


def test_require_names_the_extra_and_refuses_a_module_outside_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "zarr", None)
    with pytest.raises(
        MissingExtra, match=r'the atlas needs the optional dependency zarr: pip install "gear-rattle\[atlas\]"'
    ):
        require("zarr", "atlas", "the atlas")
    with pytest.raises(ValueError, match="not in the extra"):
        require("numpy", "atlas", "the atlas")


def test_version_and_python_dash_m():
    """``gear-rattle --version`` and ``python -m gear_rattle`` (from outside the repository)."""
    v = subprocess.run(
        [sys.executable, "-m", "gear_rattle", "--version"],
        capture_output=True,
        text=True,
        cwd=Path("/").resolve(),
        timeout=120,
    )
    from gear_rattle.validation.golden.formats.version import SUITE_VERSION

    assert (
        v.returncode == 0
        and v.stdout.strip() == f"gear-rattle {gear_rattle.__version__} (golden suite {SUITE_VERSION})"
    )
    assert gear_rattle.__version__ != "0+unknown"
    h = subprocess.run([sys.executable, "-m", "gear_rattle", "--help"], capture_output=True, text=True, timeout=120)
    assert h.returncode == 0 and h.stdout.startswith("usage: gear-rattle")


def test_plain_pytest_collects_every_module():
    """``pytest`` (the console script: the working directory is not on sys.path, unlike ``python -m
    pytest``) collects the suite without errors: test helpers are found through pytest's ``pythonpath``."""
    exe = Path(sys.executable).with_name("pytest")
    if not exe.exists():
        pytest.skip(f"no pytest console script beside {sys.executable}")
    p = subprocess.run(
        [str(exe), "--collect-only", "-q", "-p", "no:cacheprovider"],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=300,
        env={**os.environ, "PYTHONPATH": ""},
    )
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    assert "error" not in p.stdout.splitlines()[-1]


def test_ci_runs_the_readme_commands_literally():
    """.ci/run executes the README's three commands as extracted by .ci/readme_command.py: the main job
    (install + quick report), the tests (install with the test extra + pytest) and the docs (install with
    the docs extra + the strict Sphinx build)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("readme_command", REPO / ".ci" / "readme_command.py")
    rc = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rc)
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    main_cmd, test_cmd = rc.command(readme, "main"), rc.command(readme, "tests")
    assert "pip install -e ." in main_cmd and "gear-rattle report --profile quick" in main_cmd
    assert 'pip install -e ".[test]"' in test_cmd and "pytest" in test_cmd
    docs_cmd = rc.command(readme, "docs")
    assert "docs" in docs_cmd and "python -m sphinx -W -n -b html docs" in docs_cmd
    ci = (REPO / ".ci" / "run").read_text()
    assert 'bash -euo pipefail -c "$MAIN_CMD"' in ci and 'bash -euo pipefail -c "$TEST_CMD"' in ci
    assert 'bash -euo pipefail -c "$DOCS_CMD"' in ci
    with pytest.raises(SystemExit, match="expected one command"):
        rc.command(readme.replace(main_cmd, main_cmd + "\necho more"), "main")
