"""Fuzz another implementation against certified cases on demand (docs/golden.md, "Fuzzing an implementation").

COMMAND is called as `COMMAND CASES_DIR OUT_DIR`: it must run every case folder of CASES_DIR (settings.json in
the golden suite's layout; expected.csv is not given) and write OUT_DIR/<case-id>.csv, as for the shipped
suite. The fuzzer draws inputs with Hypothesis from a registry of scenarios (grazes, near misses, chatter and
sticking on both walls, thresholds at any stick_time, release delays, r = 1, small beta, negative gamma,
free-flight starts, orbits that end stuck or with no_impact, the whole parameter box, long orbits and long
flights), builds each certified case as `gear-rattle case` does, runs the implementation on batches
of cases (one process per batch), scores them as `gear-rattle check` does, and shrinks every failure
(fewer impacts, simpler numbers, the paper's parameters) to a small failing case written to --out as a
golden-format case folder: keep it as a regression test (`gear-rattle check OUT --suite DIR`).

Stops at the first failure (after shrinking it) unless --keep-going; reproducible by --seed; the search is
bounded by --budget (shrinking each failure takes at most 90 s more, or the budget if smaller). A JSON summary goes to
stdout. Exit status: 0 nothing found, 1 failures found (each written), 2 usage error, or an implementation
that crashes, times out or writes a missing or malformed file (named in one line). Needs Hypothesis (the
`test` extra)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..cliutil import CliError, int_range, progress_arg, real, seed_int, to_stdout

NAME = "fuzz"
HELP = "differential fuzzing of another implementation against certified cases (finds and shrinks failures)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..golden.fuzz import BATCH, TIMEOUT
    from ..golden.scenarios import SCENARIOS, check_scenarios

    def scenario(text: str) -> str:
        """argparse type: a name of the registry (one line naming the allowed ones otherwise)."""
        try:
            return check_scenarios([text])[0]
        except ValueError as e:
            raise argparse.ArgumentTypeError(str(e)) from None

    p.add_argument(
        "--impl",
        required=True,
        metavar="COMMAND",
        help="the implementation, called as COMMAND CASES_DIR OUT_DIR (shell words; required, no default)",
    )
    p.add_argument(
        "--seed", type=seed_int(), default=0, help="random seed of the draws, 0 <= SEED <= 2**32 - 1 (default 0)"
    )
    p.add_argument(
        "--budget",
        type=real("--budget", lo=0.0, lo_open=True, hi=1e6),
        default=60.0,
        metavar="SECONDS",
        help="seconds of search, 0 < SECONDS <= 1e6 (default %(default)s)",
    )
    p.add_argument(
        "--out",
        default="fuzz-failures",
        metavar="DIR",
        help="where failing cases are written (default fuzz-failures; created only if one is found)",
    )
    p.add_argument("--keep-going", action="store_true", help="go on after a failure until the budget is spent")
    p.add_argument(
        "--timeout",
        type=real("--timeout", lo=0.0, lo_open=True, hi=1e5),
        default=TIMEOUT,
        metavar="SECONDS",
        help="seconds one batch of the implementation may take, 0 < SECONDS <= 1e5 (default %(default)s)",
    )
    p.add_argument(
        "--batch",
        type=int_range("--batch", 1, 1000),
        default=BATCH,
        metavar="N",
        help=f"cases per run of the implementation, 1 <= N <= 1000 (default {BATCH})",
    )
    p.add_argument(
        "--scenarios",
        nargs="+",
        type=scenario,
        default=None,
        metavar="NAME",
        help="draw only these scenarios (default: all): " + ", ".join(sorted(SCENARIOS)),
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    from ...core.progress import Bar
    from ..cliutil import check_output_dir
    from ..extras import require
    from ..golden.fuzz import fuzz, split_command
    from ..io.atomic import commit_pending, write_text_atomic

    require("hypothesis", "test", "gear-rattle fuzz")
    command = split_command(args.impl)
    check_output_dir(args.out, "--out")
    out = Path(args.out)
    with Bar("fuzz", total=None, unit="cases", enabled=progress_arg(args) is not False) as bar:

        def progress(cases: int, failures: int) -> None:
            bar.postfix(f"{failures} failing")
            bar(cases)

        # each shrunk case is moved into place as soon as it is written (io.atomic): an interrupted
        # --keep-going run keeps the failures it has found
        res = fuzz(
            command,
            seed=args.seed,
            budget=args.budget,
            out=out,
            keep_going=args.keep_going,
            timeout=args.timeout,
            batch=args.batch,
            scenarios=args.scenarios,
            progress=progress,
            write=write_text_atomic,
            written=commit_pending,
        )
    summary = {
        "implementation": args.impl,
        "seed": args.seed,
        "budget_s": args.budget,
        "elapsed_s": round(res.elapsed, 2),
        "cases": res.cases,
        "batches": res.batches,
        "inputs_drawn": res.drawn,
        "inputs_skipped": res.skipped,
        "scenarios": res.scenarios,
        "failures": [f.summary() for f in res.failures],
        "out": str(out) if res.failures else None,
        "status": "error" if res.error else ("failures" if res.failures else "clean"),
        "error": res.error or None,
    }
    to_stdout(json.dumps(summary, indent=1, allow_nan=False) + "\n")
    if res.error:
        raise CliError(res.error)
    return 1 if res.failures else 0
