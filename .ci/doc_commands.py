"""Run the commands that the quick starts and the how-to guides show (docs/start/, docs/howto/).

    python .ci/doc_commands.py [--quick | --slow] [--report DIR] [--list] [PAGE.md ...]

Every fenced block of those pages in a shell (``bash``, ``sh``, ``shell``, ``console``) or ``python`` is
preceded by one comment -- on the line before its fence, blank lines allowed -- saying how CI runs it:

``<!-- ci: run -->``
    run as written: a shell block by ``bash -euo pipefail -c``, a python block by ``python -``;
``<!-- ci: run quick -->``
    likewise, and quick enough for the default test suite (tests/test_doc_commands.py runs it);
``<!-- ci: shrink OLD => NEW; OLD2 => NEW2 -->``
    a paper-scale command, run with each ``OLD`` (which must occur in the block) replaced by ``NEW``:
    the mechanical, documented shrink of its sizes;
``<!-- ci: in .ci/run -->``
    each command of the block is run, as written, by .ci/run (in its text or as one of the README's
    three commands that it runs): checked here, not run a second time;
``<!-- ci: skip REASON -->``
    not run; the reason is required and says why (a cluster of other machines, a command that
    only names a placeholder).

A ``report`` word after ``run`` or ``shrink`` (``<!-- ci: run report -->``) says that the block reads the
quick report in ``./report``: the runner copies the report given by ``--report`` (in .ci/run, the
README main job's ``report/``) into the page's folder first, and without ``--report`` leaves the block
out, saying so.  A ``repo`` word says that the block works on the clone (a developer's command: the
tests) and runs in the repository's root; it must write nothing there.  The other blocks of a page
run in order in one fresh temporary folder, so that a block may use what an earlier block of its page
wrote.  ``--quick`` runs the quick blocks only, ``--slow`` the others; the default is all.  A block
that exits non-zero fails the run (exit status 1), with the end of its output.  What a block leaves
running is ended with it.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGE_DIRS = ("docs/start", "docs/howto")
SHELLS = ("bash", "sh", "shell", "console")
#: fenced blocks in these languages are output or data, not commands: they need no marker
INERT = ("text", "json", "csv", "toml", "yaml", "output", "")
MARKER = re.compile(r"<!--\s*ci:\s*(.*?)\s*-->", re.S)
FENCE = re.compile(r"^(```+|~~~+)\s*\{?([\w-]*)\}?.*$")
MODES = ("run", "shrink", "in .ci/run", "skip")
BLOCK_TIMEOUT_S = 1200


@dataclass
class Block:
    page: Path
    line: int  # 1-based line of the opening fence
    lang: str
    text: str
    marker: str | None  # the comment's text after "ci:", None when there is none
    mode: str = ""
    quick: bool = False
    report: bool = False
    repo: bool = False
    shrinks: list[tuple[str, str]] = field(default_factory=list)
    reason: str = ""

    @property
    def where(self) -> str:
        page = self.page.relative_to(ROOT) if self.page.is_relative_to(ROOT) else self.page
        return f"{page}:{self.line}"

    @property
    def command(self) -> bool:
        return self.lang in SHELLS or self.lang == "python"

    def script(self) -> str:
        """The text that runs: the block with its shrinks applied."""
        text = self.text
        for old, new in self.shrinks:
            text = text.replace(old, new)
        return text


def pages() -> list[Path]:
    return sorted(p for d in PAGE_DIRS for p in (ROOT / d).glob("*.md"))


def parse_marker(block: Block) -> None:
    """Fill in ``mode``, ``quick``, ``report``, ``shrinks`` and ``reason`` from the block's marker; a
    marker that says none of the modes leaves ``mode`` empty (an error for :func:`problems`)."""
    m = (block.marker or "").strip()
    if m.startswith("in .ci/run"):
        block.mode = "in .ci/run"
        return
    if m.startswith("skip"):
        block.mode, block.reason = "skip", m[len("skip") :].strip()
        return
    head, _, rest = m.partition(" ")
    if head not in ("run", "shrink"):
        return
    block.mode = head
    words = rest.split()
    while words and words[0] in ("quick", "report", "repo"):
        setattr(block, words.pop(0), True)
    if head == "shrink":
        spec = " ".join(words)
        for part in filter(None, (p.strip() for p in spec.split(";"))):
            old, sep, new = part.partition("=>")
            if sep:
                block.shrinks.append((old.strip(), new.strip()))
    elif words:
        block.mode = ""  # `run` takes no more words than its flags


def blocks(page: Path) -> list[Block]:
    """The fenced blocks of a page, each with the marker comment that precedes it (if any)."""
    lines = page.read_text(encoding="utf-8").splitlines()
    out: list[Block] = []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i].strip())
        if not m:
            i += 1
            continue
        fence, lang = m.group(1), m.group(2).lower()
        j = i + 1
        while j < len(lines) and not lines[j].strip().startswith(fence):
            j += 1
        k = i - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        marker = MARKER.fullmatch(lines[k].strip()) if k >= 0 else None
        block = Block(page, i + 1, lang, "\n".join(lines[i + 1 : j]) + "\n", marker.group(1) if marker else None)
        parse_marker(block)
        out.append(block)
        i = j + 1
    return out


def ci_texts() -> list[str]:
    """What .ci/run runs as written: its own text and the README's three commands it extracts."""
    sys.path.insert(0, str(ROOT / ".ci"))
    try:
        import readme_command
    finally:
        sys.path.pop(0)
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    return [(ROOT / ".ci" / "run").read_text()] + [readme_command.command(readme, w) for w in readme_command.LABELS]


def command_lines(text: str) -> list[str]:
    """The commands of a shell block: continuation lines joined, comments and blank lines left out."""
    joined = re.sub(r"\\\n\s*", " ", text)
    out = []
    for line in joined.splitlines():
        line = re.sub(r"\s+#\s.*$", "", line).strip()
        if line and not line.startswith("#"):
            out.append(line)
    return out


def problems(block: Block) -> list[str]:
    """Why a block breaks the rules above (empty when it does not)."""
    if not block.command:
        if block.lang in INERT:
            return []
        return [f"{block.where}: a ```{block.lang} block is neither a command ({', '.join(SHELLS)}, python) nor output"]
    if block.marker is None:
        return [f"{block.where}: a ```{block.lang} block without a `<!-- ci: ... -->` comment"]
    if not block.mode:
        return [f"{block.where}: `<!-- ci: {block.marker} -->` is none of: {', '.join(MODES)}"]
    if block.mode == "skip" and not block.reason:
        return [f"{block.where}: `ci: skip` without a reason"]
    if block.mode == "shrink":
        if not block.shrinks:
            return [f"{block.where}: `ci: shrink` without `OLD => NEW`"]
        return [
            f"{block.where}: shrink {old!r} is not in the block" for old, _ in block.shrinks if old not in block.text
        ]
    if block.mode == "in .ci/run":
        if block.lang not in SHELLS:
            return [f"{block.where}: `ci: in .ci/run` on a ```{block.lang} block"]
        texts = ci_texts()
        return [
            f"{block.where}: not run by .ci/run as written: {c}"
            for c in command_lines(block.text)
            if not any(c in t for t in texts)
        ]
    return []


def run_block(block: Block, folder: Path, timeout: float = BLOCK_TIMEOUT_S) -> subprocess.CompletedProcess:
    """Run one block in ``folder`` with this Python's environment first on PATH, in a process group of
    its own: whatever the block started and left running (a Dask scheduler in the background) is ended
    with it (SIGTERM, then SIGKILL)."""
    env = {**os.environ, "MPLBACKEND": "Agg", "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    if block.lang == "python":
        argv, stdin = [sys.executable, "-"], block.script()
    else:
        argv, stdin = ["bash", "-euo", "pipefail", "-c", block.script()], None
    # output to files, not pipes: a process left running in the background keeps a pipe open, and
    # reading the pipe to its end would wait for it
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(
            argv,
            stdin=subprocess.PIPE if stdin is not None else subprocess.DEVNULL,
            stdout=out,
            stderr=err,
            cwd=folder,
            env=env,
            text=True,
            start_new_session=True,
        )
        try:
            proc.communicate(stdin, timeout=timeout)
        finally:
            _end_group(proc.pid)
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        out.seek(0)
        err.seek(0)
        return subprocess.CompletedProcess(argv, proc.returncode, out.read(), err.read())


def _end_group(pgid: int) -> None:
    """SIGTERM to a block's process group, SIGKILL to what is left after 5 s."""
    for sig, wait in ((signal.SIGTERM, 5.0), (signal.SIGKILL, 0.0)):
        try:
            os.killpg(pgid, sig)
        except (ProcessLookupError, PermissionError):
            return
        deadline = time.monotonic() + wait
        while time.monotonic() < deadline:
            try:
                os.killpg(pgid, 0)
            except (ProcessLookupError, PermissionError):
                return
            time.sleep(0.1)


def selected(block: Block, which: str) -> bool:
    if block.mode not in ("run", "shrink"):
        return False
    return which == "all" or (which == "quick") == block.quick


def run_page(page: Path, which: str, report: Path | None, log=print) -> list[str]:
    """Run a page's selected blocks in order in one temporary folder; the failures, one line each."""
    chosen = [b for b in blocks(page) if selected(b, which)]
    failures: list[str] = []
    if not chosen:
        return failures
    with tempfile.TemporaryDirectory(prefix="doc-commands-") as tmp:
        folder = Path(tmp)
        for block in chosen:
            if block.report:
                if report is None:
                    log(f"{block.where}: left out (it reads ./report: give --report DIR)")
                    continue
                if not (folder / "report").exists():
                    shutil.copytree(report, folder / "report")
            t0 = time.monotonic()
            try:
                p = run_block(block, ROOT if block.repo else folder)
                ok, tail = p.returncode == 0, (p.stdout + p.stderr)[-3000:]
            except subprocess.TimeoutExpired:
                ok, tail = False, f"timed out after {BLOCK_TIMEOUT_S} s"
            log(
                f"{block.where}: {block.mode}{' (shrunk)' if block.shrinks else ''} {'ok' if ok else 'FAILED'} in {time.monotonic() - t0:.1f} s"
            )
            if not ok:
                failures.append(f"{block.where}: exit status {getattr(p, 'returncode', '?')}\n{tail}")
    return failures


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("pages", nargs="*", type=Path, help="pages (default: every page of docs/start and docs/howto)")
    group = ap.add_mutually_exclusive_group()
    group.add_argument("--quick", action="store_const", dest="which", const="quick", help="the quick blocks only")
    group.add_argument("--slow", action="store_const", dest="which", const="slow", help="the other blocks only")
    ap.add_argument("--report", type=Path, help="a quick report (report/) for the blocks that read one")
    ap.add_argument("--list", action="store_true", help="list every block and how CI runs it; run nothing")
    args = ap.parse_args(argv)
    todo = [p.resolve() for p in args.pages] or pages()
    found = [b for p in todo for b in blocks(p)]
    bad = [msg for b in found for msg in problems(b)]
    for b in found:
        if args.list and b.command:
            extra = f" ({b.reason})" if b.reason else "".join(f" [{o} => {n}]" for o, n in b.shrinks)
            flags = "".join(f" {f}" for f in ("quick", "report", "repo") if getattr(b, f))
            print(f"{b.where}: {b.mode}{flags}{extra}")
    if bad:
        print("\n".join(bad), file=sys.stderr)
        return 1
    if args.list:
        return 0
    report = args.report.resolve() if args.report else None
    failures = [f for p in todo for f in run_page(p, args.which or "all", report)]
    for f in failures:
        print(f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
