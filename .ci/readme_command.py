"""Print one of the README's two set-up commands, verbatim, for .ci/run to execute literally.

    python3 .ci/readme_command.py main|tests|docs [README.md]

The README has three labelled fenced ``bash`` blocks: ``**Main job**`` and ``**Tests**`` at the top,
``**Docs**`` in its section on the documentation site.  The
command is the single line of the first fenced block after its label; anything else (no label, no
block, a block of several lines) is an error, so that CI fails if the README's layout changes
instead of running something else.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

LABELS = {"main": "**Main job**", "tests": "**Tests**", "docs": "**Docs**"}


def command(readme: str, which: str) -> str:
    label = LABELS[which]
    at = readme.find("\n" + label)
    if at < 0:
        raise SystemExit(f"readme_command: no line starting with {label!r} in README.md")
    m = re.compile(r"^```(?:bash|sh)\n(.*?)^```", re.M | re.S).search(readme, at)
    if not m:
        raise SystemExit(f"readme_command: no fenced bash block after {label!r}")
    lines = [ln for ln in m.group(1).splitlines() if ln.strip()]
    if len(lines) != 1:
        raise SystemExit(f"readme_command: the block after {label!r} has {len(lines)} lines, expected one command")
    return lines[0]


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3) or sys.argv[1] not in LABELS:
        raise SystemExit("usage: readme_command.py main|tests|docs [README.md]")
    path = Path(sys.argv[2] if len(sys.argv) == 3 else Path(__file__).resolve().parents[1] / "README.md")
    print(command(path.read_text(encoding="utf-8"), sys.argv[1]))
