"""No import cycles among the package's modules, the imports inside functions counted (issue 32 item 3).

An import inside a function runs later than one at the top of a module, but it is an import all the
same: two modules that import each other that way are one module split in two, and the cycle is only
hidden (``lint-imports`` checks the direction of every import, function-level ones included, between
the layers of pyproject.toml, but not the modules within one layer).  The graph is built from the
source (the AST of every module of the ``gear_rattle`` namespace: the repository's top-level folders);
``if TYPE_CHECKING:`` imports, which never run, are left out, and so is a module's import of a package
that contains it (Python imports the parents of every module first: not a dependency of its own).
"""

from __future__ import annotations

import ast
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
#: The installed namespace's packages and the folders they come from (pyproject.toml's package-dir).
FOLDERS = {
    "gear_rattle": "gear_rattle",
    "gear_rattle.core": "core",
    "gear_rattle.mapimpl": "mapimpl",
    "gear_rattle.reference": "reference",
    "gear_rattle.validation": "validation",
}


def modules(repo: Path = REPO) -> dict[str, Path]:
    """Every module of the namespace: ``{dotted name: file}`` (a package is its ``__init__.py``)."""
    out = {}
    for pkg, folder in FOLDERS.items():
        root = repo / folder
        for path in sorted(root.rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            if pkg == "gear_rattle" and parts:  # the facade's own modules only (no sub-packages there)
                parts = parts[-1:]
            out[".".join([pkg, *parts])] = path
    return out


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    """ids of the import nodes under ``if TYPE_CHECKING:`` (never executed)."""
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            ids.update(id(n) for stmt in node.body for n in ast.walk(stmt))
    return ids


def imports_of(name: str, path: Path, known: set[str]) -> set[str]:
    """The namespace's modules that module ``name`` imports, anywhere in its body (functions included)."""
    tree = ast.parse(path.read_text(), str(path))
    is_pkg = path.name == "__init__.py"
    skip = _type_checking_nodes(tree)
    found = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name in known)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_pkg else name.split(".")[:-1]
                base = base[: len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            for a in node.names:
                sub = f"{mod}.{a.name}"
                if sub in known:
                    found.add(sub)
                elif mod in known:
                    found.add(mod)
    return {m for m in found if m != name and not name.startswith(m + ".")}


def import_graph(repo: Path = REPO) -> dict[str, set[str]]:
    """``{module: modules it imports}`` over the whole namespace."""
    mods = modules(repo)
    known = set(mods)
    return {m: imports_of(m, p, known) for m, p in mods.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm, iterative), each
    sorted, in sorted order: every module of one of them is reachable from every other."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out = []
    counter = 0
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return sorted(out)


def test_no_import_cycles():
    """No two modules of the package import each other, directly or through others, at any level."""
    graph = import_graph()
    assert len(graph) > 100 and "gear_rattle.validation.cli" in graph
    found = cycles(graph)
    assert not found, "import cycles (imports inside functions counted):\n" + "\n".join(" <-> ".join(c) for c in found)


def test_the_cycle_finder_sees_imports_inside_functions(tmp_path):
    """A cycle closed by an import inside a function is found; the same pair under ``TYPE_CHECKING`` or a
    module importing its own package is not a cycle."""
    for folder in FOLDERS.values():
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "__init__.py").write_text("")
    v = tmp_path / "validation"
    (v / "a.py").write_text("from .b import g\n\ndef f():\n    return g()\n")
    (v / "b.py").write_text("def g():\n    from .a import f  # hidden\n    return f\n")
    (v / "c.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .d import x\n")
    (v / "d.py").write_text("from . import c\nfrom .. import validation\n")
    (v / "__init__.py").write_text("from .d import c\n")
    graph = import_graph(tmp_path)
    assert graph["gear_rattle.validation.b"] == {"gear_rattle.validation.a"}
    assert graph["gear_rattle.validation.c"] == set()
    assert cycles(graph) == [["gear_rattle.validation.a", "gear_rattle.validation.b"]]
