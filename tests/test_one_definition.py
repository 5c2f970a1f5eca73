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
INT_TEXT_ALLOWED = {"core/checks.py", "validation/cliutil.py", "validation/golden/csvformat.py",
                    "validation/commands/release.py", "core/_jax.py", "validation/atlas/store.py"}
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
                if (isinstance(left, ast.Call) and isinstance(left.func, ast.Name) and left.func.id == "int"
                        and len(left.args) == 1 and ast.dump(left.args[0]) == ast.dump(right)):
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
        "    raise ValueError('x is out of range: allowed a real')\n")
    assert hand_written_int_checks(tmp_path) == ["validation/x.py:2: int(x) != x",
                                                 "validation/x.py:3: raise with an integer's message",
                                                 "validation/x.py:5: raise with an integer's message"]
