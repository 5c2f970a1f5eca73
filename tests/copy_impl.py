"""A fast implementation under the fuzzer's protocol, for tests/test_fuzz_triage.py: no JAX, no numerics.
``python tests/copy_impl.py DEFECTS CASES_DIR OUT_DIR`` answers every case of CASES_DIR with the certified
reference that the fuzzer keeps beside it (``CASES_DIR/../reference/<id>/expected.csv``: the runner's work
layout, validation/golden/fuzz_runner.py -- a test's shortcut, not part of the protocol) and plants the
defects named (joined by ``+``):

* ``right``: the reference as it is (a correct implementation);
* ``crash-alpha-2``: a panic (a line on stderr, exit status 101) at the first case with ``alpha > 2``, in
  sorted order (the cases before it are written);
* ``sdot-off``: every impact's ``sdot`` times ``1 + 1e-6`` (one defect that fails every input with an
  impact after impact 0);
* ``wall-last-blank``: blank lines between the rows and the wall of the last row flipped (a wrong wall, on
  a line that is not ``row + 2``);
* ``hang-alpha-2``: never ends on a case with ``alpha > 2``;
* ``fifo-alpha-2``: ``<id>.csv`` a named pipe for a case with ``alpha > 2``, nothing written into it;
* ``grandchild``: starts a grandchild (``sleep``) and writes both pids, one a line, to the file named by
  ``$COPY_IMPL_PIDS``, then sleeps.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path


def answer(defects: list[str], settings: dict, reference: str) -> str:
    """The output text for a case (the process may end or hang before it writes one)."""
    alpha = settings["params"]["alpha"]
    lines = reference.splitlines()
    if "crash-alpha-2" in defects and alpha > 2:
        sys.stderr.write(f"thread 'main' panicked at 'alpha {alpha} > 2 not supported', src/main.rs:7:5\n")
        sys.exit(101)
    if "hang-alpha-2" in defects and alpha > 2:
        time.sleep(3600)
    if "sdot-off" in defects:
        rows = [lines[0]]
        for line in lines[1:]:
            f = line.split(",")
            if f[5] == "impact" and f[0] != "0":
                f[4] = repr(float(f[4]) * (1 + 1e-6))
            rows.append(",".join(f))
        lines = rows
    if "wall-last-blank" in defects and len(lines) > 2:
        f = lines[-1].split(",")
        f[3] = "0" if f[3] == "-1" else "-1"
        lines = [lines[0], *[x for line in lines[1:-1] for x in (line, "")], ",".join(f)]
    return "\n".join(lines) + "\n"


def main(argv: list[str]) -> int:
    names, cases, out = argv
    defects = names.split("+")
    reference = Path(cases).parent / "reference"
    if "grandchild" in defects:
        child = subprocess.Popen(["sleep", "300"])
        Path(os.environ["COPY_IMPL_PIDS"]).write_text(f"{os.getpid()}\n{child.pid}\n")
        time.sleep(300)
    for folder in sorted(p for p in Path(cases).iterdir() if (p / "settings.json").is_file()):
        settings = json.loads((folder / "settings.json").read_text())
        target = Path(out) / f"{settings['id']}.csv"
        if "fifo-alpha-2" in defects and settings["params"]["alpha"] > 2:
            os.mkfifo(target)
            continue
        text = answer(defects, settings, (reference / settings["id"] / "expected.csv").read_text())
        target.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
