"""Every command the quick starts and the how-to guides show runs in CI (.ci/doc_commands.py).

Each fenced command block of docs/start/ and docs/howto/ carries a ``<!-- ci: ... -->`` comment saying
how CI runs it: as written, with a documented shrink of its sizes, as one of the commands .ci/run runs
literally, or not at all with a reason.  These tests check the marks, run the blocks marked ``quick``,
and check that .ci/run runs them all (``--report report``, after the README main job wrote its report)."""

from __future__ import annotations

import importlib.util
import os
import signal
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("doc_commands", ROOT / ".ci" / "doc_commands.py")
dc = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("doc_commands", dc)  # its dataclasses look their module up there
_spec.loader.exec_module(dc)


@pytest.fixture
def scratch_page(tmp_path):
    def make(text: str) -> Path:
        page = tmp_path / "page.md"
        page.write_text(text, encoding="utf-8")
        return page

    return make


def test_the_quick_starts_and_how_tos_are_there():
    names = {p.relative_to(ROOT).as_posix() for p in dc.pages()}
    assert {"docs/start/reproduce.md", "docs/start/extend.md", "docs/start/ci.md"} <= names
    assert sum(n.startswith("docs/howto/") for n in names) >= 5


def test_every_command_block_says_how_ci_runs_it():
    found = [b for p in dc.pages() for b in dc.blocks(p)]
    commands = [b for b in found if b.command]
    assert len(commands) >= 20, len(commands)
    problems = [msg for b in found for msg in dc.problems(b)]
    assert not problems, "\n".join(problems)
    # most of what the pages show really runs: skips are the exception, each with its reason
    skipped = [b for b in commands if b.mode == "skip"]
    assert len(skipped) <= 3 and all(len(b.reason) > 20 for b in skipped), [(b.where, b.reason) for b in skipped]
    assert sum(b.mode in ("run", "shrink") for b in commands) >= 15


def test_the_marks_are_checked(scratch_page):
    """A block without a mark, a mark that says no mode, a shrink of text the block lacks, a skip without
    a reason and an `in .ci/run` command that .ci/run does not run are each refused."""
    page = scratch_page(
        "```bash\necho unmarked\n```\n\n"
        "<!-- ci: sometimes -->\n```bash\necho bad mark\n```\n\n"
        "<!-- ci: shrink --big => --small -->\n```bash\necho --huge\n```\n\n"
        "<!-- ci: skip -->\n```python\nprint(1)\n```\n\n"
        "<!-- ci: in .ci/run -->\n```bash\ngear-rattle report --profile paper --out elsewhere\n```\n\n"
        "<!-- ci: in .ci/run -->\n```bash\nruff check .\n```\n\n"
        "```text\noutput needs no mark\n```\n"
    )
    found = dc.blocks(page)
    problems = [dc.problems(b) for b in found]
    assert [bool(p) for p in problems] == [True, True, True, True, True, False, False], problems
    assert "without a `<!-- ci: ... -->` comment" in problems[0][0]
    assert "'--big' is not in the block" in problems[2][0]
    assert "not run by .ci/run as written" in problems[4][0]


def test_a_shrink_is_applied_literally(scratch_page):
    page = scratch_page(
        "<!-- ci: shrink quick --nx 400 => --nx 8; paper => quick -->\n"
        "```bash\ngear-rattle transients --profile paper --nx 400\n```\n"
    )
    (block,) = dc.blocks(page)
    assert block.mode == "shrink" and block.quick and not block.report
    assert block.script() == "gear-rattle transients --profile quick --nx 8\n"


def test_blocks_run_in_order_in_one_folder_and_failures_are_reported(scratch_page):
    page = scratch_page(
        "<!-- ci: run quick -->\n```bash\necho 41 > n.txt\n```\n\n"
        "<!-- ci: run quick -->\n```python\nprint(int(open('n.txt').read()) + 1)\n```\n\n"
        '<!-- ci: run quick -->\n```bash\ntest "$(cat n.txt)" = 42\n```\n'
    )
    lines: list[str] = []
    failures = dc.run_page(page, "quick", None, log=lines.append)
    assert len(failures) == 1 and ":12: exit status 1" in failures[0], failures
    assert [ln.split()[-4] for ln in lines] == ["ok", "ok", "FAILED"], lines


def test_what_a_block_starts_is_ended_with_it(tmp_path):
    """A block that leaves a process running (a Dask scheduler in the background) does not leave it
    behind: its process group is ended when the block ends."""
    block = dc.Block(ROOT / "docs" / "howto" / "x.md", 1, "bash", "sleep 300 &\necho $! > pid\n", "run")
    t0 = time.monotonic()
    p = dc.run_block(block, tmp_path)
    assert p.returncode == 0 and time.monotonic() - t0 < 60
    pid = int((tmp_path / "pid").read_text())
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return
        if Path(f"/proc/{pid}/stat").exists() and Path(f"/proc/{pid}/stat").read_text().split()[2] == "Z":
            return  # ended, not yet reaped by its new parent
        time.sleep(0.1)
    os.kill(pid, signal.SIGKILL)
    pytest.fail("the block's background process outlived it")


@pytest.mark.parametrize("page", [p for p in dc.pages() if any(b.quick for b in dc.blocks(p))], ids=lambda p: p.name)
def test_quick_blocks_run(page):
    failures = dc.run_page(page, "quick", None, log=lambda line: None)
    assert not failures, "\n".join(failures)


def test_ci_runs_the_other_blocks():
    """.ci/run runs every block, with the README main job's report for those that read one, after that
    report exists."""
    ci = (ROOT / ".ci" / "run").read_text()
    assert "python .ci/doc_commands.py --report report" in ci
    assert ci.index("python .ci/doc_commands.py") > ci.index('bash -euo pipefail -c "$MAIN_CMD"')
