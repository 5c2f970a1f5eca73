"""Each rule written once (issue 32 items 1 and 6): guards that scan the package's sources for a second,
hand-written copy of a rule that has one home -- an integer check (``core.checks.check_int``), the
parameter names (``core.params.PARAM_NAMES``), the flight horizons (``core.horizons``) and the paper's
settings (``core.paper``, ``validation.paper``).  Each guard has a test that shows it finds a copy.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
FOLDERS = ("gear_rattle", "core", "mapimpl", "reference", "validation")


def _sources(repo: Path):
    """``(relative path, parsed tree)`` of every module of the package."""
    for folder in FOLDERS:
        for path in sorted((repo / folder).rglob("*.py")):
            rel = path.relative_to(repo).as_posix()
            yield rel, ast.parse(path.read_text(), rel)


def _text(node: ast.AST) -> str:
    """The literal text of a str constant or an f-string (its formatted parts left out)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.JoinedStr):
        return "".join(v.value for v in node.values if isinstance(v, ast.Constant) and isinstance(v.value, str))
    return ""


# ------------------------------------------------------------------------------------------------
# integers are checked by core.checks.check_int

#: Where an integer's message may be written by hand: the helper itself; text parsed into an integer
#: (an argparse option, a CSV field, an environment variable) before check_int's kind of check applies;
#: the atlas tile, whose message is about the shape (an int or a pair).
INT_TEXT_ALLOWED = {
    "core/checks.py",
    "validation/cliutil.py",
    "validation/golden/formats/csvformat.py",
    "validation/commands/release.py",
    "core/jax_config.py",
    "validation/atlas/store.py",
}
_INTEGER_WORDS = re.compile(r"allowed (an |a positive |positive )?integers?\b|is not an integer")


def hand_written_int_checks(repo: Path = REPO) -> list[str]:
    """``path:line`` of every hand-written integer check: a ``raise`` whose message says "allowed an
    integer" / "is not an integer", or an integrality test ``int(x) != x``, outside INT_TEXT_ALLOWED."""
    out = []
    for rel, tree in _sources(repo):
        if rel in INT_TEXT_ALLOWED:
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Raise) and node.exc is not None:
                if any(_INTEGER_WORDS.search(_text(n)) for n in ast.walk(node.exc)):
                    out.append(f"{rel}:{node.lineno}: raise with an integer's message")
            elif isinstance(node, ast.Compare) and len(node.ops) == 1 and isinstance(node.ops[0], ast.NotEq):
                left, right = node.left, node.comparators[0]
                if (
                    isinstance(left, ast.Call)
                    and isinstance(left.func, ast.Name)
                    and left.func.id == "int"
                    and len(left.args) == 1
                    and ast.dump(left.args[0]) == ast.dump(right)
                ):
                    out.append(f"{rel}:{node.lineno}: int(x) != x")
    return sorted(out, key=lambda s: (s.split(":")[0], int(s.split(":")[1])))


def test_every_integer_is_checked_by_check_int():
    bad = hand_written_int_checks()
    assert not bad, "integers checked by hand, not by core.checks.check_int:\n" + "\n".join(bad)


def test_the_integer_guard_finds_a_hand_written_check(tmp_path):
    for sub in FOLDERS:
        (tmp_path / sub).mkdir()
    (tmp_path / "validation" / "x.py").write_text(
        "def f(n, m):\n"
        "    if int(n) != n or n < 1:\n"
        "        raise ValueError(f'n={n!r} is out of range: allowed an integer >= 1')\n"
        "    if m < 0:\n"
        "        raise ValueError('m is out of range: allowed integers >= 0')\n"
        "    raise ValueError('x is out of range: allowed a real')\n"
    )
    assert hand_written_int_checks(tmp_path) == [
        "validation/x.py:2: int(x) != x",
        "validation/x.py:3: raise with an integer's message",
        "validation/x.py:5: raise with an integer's message",
    ]


# ------------------------------------------------------------------------------------------------
# one definition of each paper constant (moved here from test_layers.py and extended, issue 32 item 1)

#: The only modules that may spell the paper's numbers: the settings the library uses, and the values
#: the paper reports (with its quotes).
PAPER_MODULES = {"core/paper.py", "validation/paper.py"}
#: Distinctive numbers of the paper (Figs. 9-11 alpha, <n>, kappa, r2, r1, alpha1): a literal equal to
#: one of these, or a string that spells one, outside PAPER_MODULES is a second definition.
PAPER_NUMBERS = (1.245, 2272.0, 0.893, 0.82144, 0.82145, 0.74001, 1.2437)
PAPER_TEXTS = ("1.245", "2272", "0.893", "0.82144", "0.74001")
#: Names that only PAPER_MODULES may assign at module level.
PAPER_NAMES = (
    "PAPER_PARAMS",
    "PAPER_DECIMAL",
    "PAPER_FIG2_DECIMAL",
    "PAPER_FIG2",
    "PAPER_FIG3_DECIMAL",
    "PAPER_FIG3",
    "PAPER_BOX",
    "DELTA",
    "DELTAS",
    "PAPER",
)
#: The paper's parameter sets (Figs. 2, 3-7 and 9-11), as the printed decimals of core/paper.py.
#: Common numbers (3.0, 0.1, 0.9) are a paper constant only together: three or more literal values of
#: alpha, beta, gamma, r that all equal one of these sets (a ``Params(...)``, a ``.replace(...)``, a
#: function's defaults, an option's ``default=``) re-type it.
PAPER_SETS = {
    "Figs. 9-11 (PAPER_PARAMS)": {"alpha": 1.245, "beta": 0.1, "gamma": 0.1, "r": 0.9},
    "Figs. 3-7 (PAPER_FIG3)": {"alpha": 3.0, "beta": 0.1, "gamma": 0.1, "r": 0.9},
    "Fig. 2 (PAPER_FIG2)": {"alpha": 0.5, "beta": 0.1, "gamma": 0.1, "r": 0.9},
}
PARAM_ORDER = ("alpha", "beta", "gamma", "r")
#: The capture distances (core.paper.DELTA, DELTAS) and the paper's box (PAPER_BOX): ``delta=1e-3`` (an
#: argument's default, a keyword, an option's ``default=``), a sequence of two or more literal
#: distances, or the box's four numbers are a second definition.
PAPER_DELTA = 1e-3
PAPER_DELTAS = (1e-2, 1e-3, 1e-4, 1e-6)
PAPER_BOX_VALUES = (3.0, 3.5, 0.0, 0.5)
#: Where the paper's words may be quoted in text written to files (the golden cases' descriptions).
TEXT_ALLOWED = {"validation/golden/catalog/specs.py"}


def _grid_points(tree: ast.AST) -> set:
    """Numbers that are points of a scan grid (a list or tuple of three or more numbers)."""
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.List, ast.Tuple)) and len(node.elts) >= 3:
            ids.update(id(e) for e in node.elts if isinstance(e, ast.Constant))
    return ids


def _docstrings(tree: ast.AST) -> set:
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                ids.add(id(first.value))
    return ids


def _number(node) -> float | None:
    """The value of a numeric literal (``-0.5`` included), else None."""
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        v = _number(node.operand)
        return None if v is None else -v
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return float(node.value)
    return None


def _literal_settings(node: ast.AST) -> dict[str, float]:
    """The literal values a call or a function definition gives to named settings: keywords
    (``alpha=3.0``), the positional arguments of ``...Params(...)``, an option's ``default=`` under its
    name (``add_argument("--delta", default=1e-3)``), a function's defaults."""
    out: dict[str, float] = {}
    if isinstance(node, ast.Call):
        name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
        if name.endswith("Params"):
            out.update({k: v for k, a in zip(PARAM_ORDER, node.args) if (v := _number(a)) is not None})
        for kw in node.keywords:
            if kw.arg is not None and (v := _number(kw.value)) is not None:
                out[kw.arg] = v
        if name == "add_argument" and node.args and _text(node.args[0]).startswith("--") and "default" in out:
            out[_text(node.args[0])[2:]] = out.pop("default")
    elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
        args = node.args.posonlyargs + node.args.args
        pairs = list(zip(args[len(args) - len(node.args.defaults) :], node.args.defaults))
        pairs += [(a, d) for a, d in zip(node.args.kwonlyargs, node.args.kw_defaults) if d is not None]
        out.update({a.arg: v for a, d in pairs if (v := _number(d)) is not None})
    return out


def _settings_violations(node: ast.AST) -> list[str]:
    """What a call or a definition re-types: a paper parameter set or the capture distance."""
    got, out = _literal_settings(node), []
    params = {k: v for k, v in got.items() if k in PARAM_ORDER}
    if len(params) >= 3:
        figs = [fig for fig, ref in PAPER_SETS.items() if all(ref[k] == v for k, v in params.items())]
        out += [f"re-types the parameters of {' / '.join(figs)}"] if figs else []
    if got.get("delta") == PAPER_DELTA:
        out.append("re-types the capture distance DELTA")
    return out


def paper_constant_violations(repo: Path = REPO) -> list[str]:
    """Every literal or module-level assignment that re-types a paper constant outside PAPER_MODULES."""
    out = []
    for rel, tree in _sources(repo):
        if rel in PAPER_MODULES:
            continue
        docs, grid = _docstrings(tree), _grid_points(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and id(node) not in docs:
                v = node.value
                if isinstance(v, (int, float)) and not isinstance(v, bool) and float(v) in PAPER_NUMBERS:
                    if id(node) not in grid:
                        out.append(f"{rel}:{node.lineno}: literal {v!r}")
                elif isinstance(v, str) and rel not in TEXT_ALLOWED and any(t in v for t in PAPER_TEXTS):
                    out.append(f"{rel}:{node.lineno}: string {v[:60]!r}")
            elif isinstance(node, (ast.Call, ast.FunctionDef, ast.AsyncFunctionDef)):
                out += [f"{rel}:{node.lineno}: {what}" for what in _settings_violations(node)]
            elif isinstance(node, (ast.Tuple, ast.List)):
                nums = [_number(e) for e in node.elts]
                given = [v for v in nums if v is not None]
                if len(given) >= 2 and all(v in PAPER_DELTAS for v in given):
                    out.append(f"{rel}:{node.lineno}: re-types the capture distances DELTAS")
                elif tuple(nums) == PAPER_BOX_VALUES:
                    out.append(f"{rel}:{node.lineno}: re-types the box PAPER_BOX")
        for node in tree.body:
            targets = (
                node.targets
                if isinstance(node, ast.Assign)
                else [node.target]
                if isinstance(node, ast.AnnAssign)
                else []
            )
            for t in targets:
                for n in ast.walk(t):
                    if isinstance(n, ast.Name) and n.id in PAPER_NAMES:
                        out.append(f"{rel}:{node.lineno}: defines {n.id}")
    return sorted(out, key=lambda s: (s.split(":")[0], int(s.split(":")[1])))


def test_every_paper_constant_is_defined_once():
    """The paper's settings (core/paper.py) and reported values (validation/paper.py) are typed in one
    module each; every other module imports them (issue 24 item 2, issue 32 item 1)."""
    bad = paper_constant_violations()
    assert not bad, "paper constants re-typed outside core/paper.py, validation/paper.py:\n" + "\n".join(bad)


def test_the_guard_finds_a_retyped_constant(tmp_path):
    for sub in FOLDERS:
        (tmp_path / sub).mkdir()
    (tmp_path / "core" / "paper.py").write_text("DELTA = 1e-3\n")
    (tmp_path / "mapimpl" / "x.py").write_text(
        '"""alpha = 1.245 in a docstring is prose."""\nA = 1.245\n'
        'DELTA = 1e-3\nT = f"kappa = 0.893"\nGRID = [1.2437, 1.244, 1.245]\n'
    )
    bad = paper_constant_violations(tmp_path)
    assert len(bad) == 3 and all(b.startswith("mapimpl/x.py") for b in bad), bad


def test_the_guard_finds_the_places_it_missed(tmp_path):
    """The re-typings issue 32 found where the old guard did not look: a figure's parameters as an
    option's defaults or a ``replace``, the capture distances as a tuple and a default, Fig. 2's set."""
    for sub in FOLDERS:
        (tmp_path / sub).mkdir()
    (tmp_path / "validation" / "y.py").write_text(
        "def add_param_args(p, alpha=3.0, beta=0.1, gamma=0.1, r=0.9):\n"  # 1 cliutil.py:43
        "    p.add_argument('--delta', type=float, default=1e-3)\n"  # 2 transient_common
        "    run(deltas=(1e-2, p.delta, 1e-4, 1e-6))\n"  # 3 transients.py:48
        "    base = p.replace(alpha=3.0, beta=0.1, gamma=0.1, r=FIGURE_R[p.figure])\n"  # 4 timeseries.py:39
        "FIG2 = Params(0.5, 0.1, 0.1, 0.9)\n"  # 5 catalog/specs.py
        "BOX = (3.0, 3.5, 0.0, 0.5)\n"  # 6
        "def ok(delta=1e-2, alpha=0.5, beta=0.2):\n"  # 7 not paper values
        "    return Params(0.5, 0.1, 0.1, 1.0), Params(alpha, 0.1, 0.1, 0.9), (1e-2, 0.5)\n"
    )  # 8: r=1, 3 of FIG3
    bad = paper_constant_violations(tmp_path)
    assert bad == [
        "validation/y.py:1: re-types the parameters of Figs. 3-7 (PAPER_FIG3)",
        "validation/y.py:2: re-types the capture distance DELTA",
        "validation/y.py:3: re-types the capture distances DELTAS",
        "validation/y.py:4: re-types the parameters of Figs. 3-7 (PAPER_FIG3)",
        "validation/y.py:5: re-types the parameters of Fig. 2 (PAPER_FIG2)",
        "validation/y.py:6: re-types the box PAPER_BOX",
        "validation/y.py:8: re-types the parameters of Figs. 9-11 (PAPER_PARAMS) / Figs. 3-7 (PAPER_FIG3) / "
        "Fig. 2 (PAPER_FIG2)",
    ], bad


# ------------------------------------------------------------------------------------------------
# the parameter names: core.params.PARAM_NAMES (and Params.as_dict)


def spelled_parameter_names(repo: Path = REPO) -> list[str]:
    """``path:line`` of every literal sequence that spells the four names alpha, beta, gamma, r (in this
    order, with anything around them), or dict that copies them from a Params (``{"alpha": p.alpha, ...}``),
    outside core/params.py.  A dict that gives each name its own data (a domain, a strategy, a printed
    decimal) is data about the parameters, not a copy of the list."""
    out = []
    for rel, tree in _sources(repo):
        if rel == "core/params.py":
            continue
        for node in ast.walk(tree):
            elts = node.elts if isinstance(node, (ast.Tuple, ast.List, ast.Set)) else []
            if isinstance(node, ast.Dict):  # a Params' fields copied by hand: {"alpha": p.alpha, ...}
                elts = [
                    k
                    for k, v in zip(node.keys, node.values)
                    if isinstance(k, ast.Constant) and isinstance(v, ast.Attribute) and v.attr == k.value
                ]
            names = [e.value for e in elts if isinstance(e, ast.Constant) and isinstance(e.value, str)]
            if any(names[i : i + 4] == ["alpha", "beta", "gamma", "r"] for i in range(len(names))):
                out.append(f"{rel}:{node.lineno}")
    return out


def test_the_parameter_names_are_spelled_once():
    """``core.params.PARAM_NAMES`` lists the names and ``Params.as_dict()`` gives the values: no module
    spells the four names again (issue 32: 16 times in 11 files)."""
    bad = spelled_parameter_names()
    assert not bad, "the parameter names spelled outside core/params.py:\n" + "\n".join(bad)


def test_the_names_guard_finds_a_spelling(tmp_path):
    for sub in FOLDERS:
        (tmp_path / sub).mkdir()
    (tmp_path / "validation" / "z.py").write_text(
        'A = ("id", "alpha", "beta", "gamma", "r", "tau0")\n'
        'B = {"alpha": p.alpha, "beta": p.beta, "gamma": p.gamma, "r": p.r}\n'
        'C = ("alpha", "r")\nD = {"alpha": (0, 5), "beta": (0, 1), "gamma": (-1, 1), "r": (0, 1)}\n'
    )
    assert spelled_parameter_names(tmp_path) == ["validation/z.py:1", "validation/z.py:2"]


# ------------------------------------------------------------------------------------------------
# tests use public APIs (issue 32 item 6)

#: The private names tests still reach, each with why no public API serves (test file -> names).  A private
#: name counts when a test imports it (``from gear_rattle.x import _y``, or from a private module
#: ``gear_rattle.x._m``), reads it as an attribute of an imported gear_rattle name, or sets or reads it by
#: its string (``monkeypatch.setattr(module, "_y", ...)``).  The list shrinks (issue 39: 10 files before).
PRIVATE_ALLOWED = {
    "test_case_ondemand.py": {"_spec", "_certify", "_loosest"},  # steps of build_user_case, tested alone
    "test_cli_check.py": {"_digits"},  # the digits rule of docs/golden.md, not exported
    "test_cli_long_runs.py": {"_iterate_jit", "_cache_size", "_flight_block"},  # compile counts: jax's
    # cache of a jitted function has only the private _cache_size, and the jitted kernels are private
    "test_fuzz.py": {"_digits"},  # the shrinker's simplicity measure
    "test_progress_lines.py": {"_DISPLAY"},  # the display registered for the session, replaced for one test
    "test_registry.py": {"_LOADERS"},  # the registry's table, emptied to test registration from nothing
}


def _string_names(n: ast.Call, names: set[str]) -> set[str]:
    """The private names a ``setattr``/``getattr`` call (``monkeypatch.setattr`` included) names by string
    on an imported gear_rattle name: ``monkeypatch.setattr(module, "_x", ...)``."""
    f = n.func
    name = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else ""
    if name not in ("setattr", "getattr", "delattr") or len(n.args) < 2:
        return set()
    target, attr = n.args[0], n.args[1]
    if isinstance(target, ast.Name) and target.id in names and isinstance(attr, ast.Constant):
        text = attr.value
        if isinstance(text, str) and text.startswith("_") and not text.startswith("__"):
            return {text}
    return set()


def private_names_in_tests(root: Path = REPO) -> dict[str, set[str]]:
    """Per test file, the private names (``_x``, not dunder) it imports from gear_rattle (names and module
    path parts), reads as an attribute of an imported gear_rattle name, or names by string in a
    ``setattr``/``getattr`` on one."""
    out: dict[str, set[str]] = {}
    for f in sorted((root / "tests").glob("*.py")):
        tree = ast.parse(f.read_text())
        names: set[str] = set()
        found: set[str] = set()
        for n in ast.walk(tree):
            if isinstance(n, ast.ImportFrom) and n.module and n.module.startswith("gear_rattle"):
                found |= {p for p in n.module.split(".") if p.startswith("_") and not p.startswith("__")}
                for a in n.names:
                    found |= {a.name} if a.name.startswith("_") else set()
                    names.add(a.asname or a.name)
            elif isinstance(n, ast.Import):
                for a in n.names:
                    if a.name.startswith("gear_rattle"):
                        names.add(a.asname or a.name.split(".")[0])
                        found |= {p for p in a.name.split(".") if p.startswith("_")}
        for n in ast.walk(tree):
            if (
                isinstance(n, ast.Attribute)
                and n.attr.startswith("_")
                and not n.attr.startswith("__")
                and isinstance(n.value, ast.Name)
                and n.value.id in names
            ):
                found.add(n.attr)
            elif isinstance(n, ast.Call):
                found |= _string_names(n, names)
        if found:
            out[f.name] = found
    return out


def test_tests_use_public_names():
    """A test reaches a private name only where no public API serves, each listed with its reason."""
    extra = {f: sorted(v - PRIVATE_ALLOWED.get(f, set())) for f, v in private_names_in_tests().items()}
    extra = {f: v for f, v in extra.items() if v}
    assert not extra, f"private names used by tests (use the public API, or list them with a reason): {extra}"


def test_the_private_names_guard_finds_each_way_in(tmp_path):
    """A private module in a from-import, a private name by string in ``monkeypatch.setattr`` (issue 39:
    the guard missed both), besides the imported name and the attribute it found before."""
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_x.py").write_text(
        "from gear_rattle.validation.commands._helpers import lines\n"
        "from gear_rattle.core import params as P, _private\n"
        "def test(monkeypatch):\n"
        "    monkeypatch.setattr(P, '_TABLE', {})\n"
        "    return P._hidden, P.public, getattr(P, '__doc__'), setattr(lines, 'ok', 1)\n"
    )
    assert private_names_in_tests(tmp_path) == {"test_x.py": {"_helpers", "_private", "_TABLE", "_hidden"}}
