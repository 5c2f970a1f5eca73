"""Fuzz another implementation against certified cases on demand (docs/reference/golden_commands.md, "Fuzzing an implementation").

COMMAND is called as `COMMAND CASES_DIR OUT_DIR`: it must run every case folder of CASES_DIR (settings.json in
the golden suite's layout; expected.csv is not given) and write OUT_DIR/<case-id>.csv, as for the shipped
suite. The fuzzer draws inputs with Hypothesis from a registry of scenarios (grazes, near misses, chatter and
sticking on both walls, thresholds at any stick_time, release delays, r = 1, small beta, negative gamma,
free-flight starts, orbits that end stuck or with no_impact, the whole parameter box, long orbits and long
flights), builds each certified case as `gear-rattle case` does, runs the implementation on batches
of cases (one process per batch), scores them as `gear-rattle check` does, and shrinks every failure
(fewer impacts, simpler numbers, the paper's parameters) to a small failing case written to --out as a
golden-format case folder: keep it as a regression test (`gear-rattle check OUT --suite DIR`).

Failures are triaged: each gets a signature (a value of a column beyond its tolerance, a wrong wall, kind or
n, a different number of events -- with the kind of the expected row there --, a crash with its exit status,
a timeout, a malformed or missing output), and a signature is a group (one defect failing many inputs is
one group, its count per scenario): one folder per group in --out holding its smallest
member (shrunk) and fuzz/ -- group.json (signature, how many inputs failed with it, their inputs, the exit
status), the implementation's output.csv, stdout.txt and stderr.txt on that member. A crash, a timeout or a
missing file of one input in a batch is pinned on that input (the batch is run again in halves) and the run
goes on. Each group is written as soon as it is found, then replaced by its shrunk member.

Stops at the first group (after shrinking it) unless --keep-going; reproducible by --seed; the search is
bounded by --budget (shrinking each group, or pinning a batch's crash on its input, takes at most 90 s more,
or the budget if smaller). The implementation runs in a process group of its own: it is killed, with its
children, when its run ends, on --timeout, Ctrl-C and SIGTERM; the work folder in the temporary directory is
removed on every exit (after a SIGKILL by the run's watchdog, or by the next run). A JSON summary goes to
stdout (and --json FILE; --junit-xml FILE: one testcase per group). Exit status: 0 nothing found, 1 failures
found (or one that could not be written: one line naming the file; the summary keeps it), 2 usage error or
an implementation that cannot be started. Needs Hypothesis (the `test` extra)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..cliutil import CliError, CommandFailed, int_range, progress_arg, real, seed_int, to_stdout

NAME = "fuzz"
HELP = "differential fuzzing of another implementation against certified cases (finds and shrinks failures)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..golden.fuzzing.runner import BATCH, TIMEOUT
    from ..golden.fuzzing.scenarios import SCENARIOS, check_scenarios

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
        help="where the groups of failures are written, one case folder each (default fuzz-failures; created "
        "only if one is found)",
    )
    p.add_argument("--keep-going", action="store_true", help="go on after the first group until the budget is spent")
    p.add_argument(
        "--timeout",
        type=real("--timeout", lo=0.0, lo_open=True, hi=1e5),
        default=TIMEOUT,
        metavar="SECONDS",
        help="seconds one run of the implementation may take, then it is killed with its process group (a case "
        "that outlives it alone is a timeout failure), 0 < SECONDS <= 1e5 (default %(default)s)",
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
    p.add_argument(
        "--json",
        default=None,
        metavar="FILE",
        help="also write the JSON summary to FILE (strict JSON; it is on stdout in any case; default: none)",
    )
    p.add_argument(
        "--junit-xml",
        default=None,
        metavar="FILE",
        help="also write a JUnit XML report to FILE: one testcase per group, failing with its signature, "
        "count, message and kept files; one passing testcase when nothing is found (default: none)",
    )
    p.add_argument(
        "--hypothesis-dir",
        default=None,
        metavar="DIR",
        help="where Hypothesis keeps its files (its cache of source constants; the draws keep no example "
        "database); default: the run's work folder, removed at the end (never the current directory)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    from ...core.progress import Bar
    from ..cliutil import check_distinct, check_output_dir, check_output_file, suite_writer, write_text
    from ..extras import require
    from ..golden.fuzzing.runner import fuzz, split_command, summary
    from ..golden.fuzzing.triage import junit_xml
    from ..io.atomic import current

    require("hypothesis", "test", "gear-rattle fuzz")
    command = split_command(args.impl)
    check_output_dir(args.out, "--out")
    for option in ("--json", "--junit-xml"):
        check_output_file(getattr(args, option[2:].replace("-", "_")), option)
    check_distinct(**{"--json": args.json, "--junit-xml": args.junit_xml})
    if args.hypothesis_dir is not None:
        check_output_dir(args.hypothesis_dir, "--hypothesis-dir")
    out = Path(args.out)
    tx = current()
    if tx is not None:  # groups go in one by one: --out's manifest lists every file of the run, not the last set
        tx.merge = True
    with (
        suite_writer(out, "--out", args.out),  # the suite of found cases has one writer (as `case` holds it)
        Bar("fuzz", total=None, unit="cases", enabled=progress_arg(args) is not False) as bar,
    ):
        bar.phase("certifying the first batch of cases")  # until the first count (a batch takes seconds)

        def progress(cases: int, groups: int, doing: str | None = None) -> None:
            bar.postfix(f"{groups} failing" + (f", {doing}" if doing else ""))
            bar(cases)

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
            store=store_atomic,
            hypothesis_dir=None if args.hypothesis_dir is None else Path(args.hypothesis_dir),
        )
    doc = summary(
        res,
        implementation=args.impl,
        seed=args.seed,
        budget_s=args.budget,
        out=str(out) if res.groups else None,
    )
    text = json.dumps(doc, indent=1, allow_nan=False) + "\n"
    to_stdout(text)  # first: what was found is never lost
    if args.json not in (None, "-"):
        write_text(text, args.json, "--json")
    if args.junit_xml is not None:
        write_text(junit_xml(doc), args.junit_xml, "--junit-xml")
    if res.error:
        raise CliError(res.error)
    if res.unwritten:
        more = f" (and {len(res.unwritten) - 1} more)" if len(res.unwritten) > 1 else ""
        raise CommandFailed(f"{res.unwritten[0]}{more}; every failure found is in the JSON summary on stdout")
    return 1 if res.groups else 0


def store_atomic(files: dict) -> None:
    """Write a group's files (``{path: bytes}``) through the command line's atomic writer, moved into place
    together or not at all (validation/io/atomic.py); :class:`NotWritten` (one line naming the file) when
    one cannot be written -- the set is then discarded, the earlier files stay."""
    from ..cliutil import output_fault
    from ..golden.fuzzing.triage import NotWritten
    from ..io.atomic import commit_pending, current, write_atomic

    path = None
    try:
        for path, data in files.items():
            Path(path).parent.mkdir(parents=True, exist_ok=True)
            write_atomic(path, data)
        commit_pending()
    except OSError as e:
        tx = current()
        if tx is not None:
            tx.discard()
        raise NotWritten(str(output_fault(e, "--out", path))) from None
