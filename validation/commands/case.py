"""Build a golden-format case for your own input: its orbit certified by ball arithmetic, its tolerances set
by every rule of docs/reference/golden_commands.md ("Asking the oracle").

Writes SUITE/ID/ (settings.json, expected.csv, provenance.json) and updates SUITE/index.json (its other
fields kept). Score an implementation against it with `gear-rattle check OUT --suite SUITE`. No row of a
case has a tolerance of 1e-6 (--max-tolerance T) or more: where the error of a correct float64
implementation, amplified along the orbit, would need one, the case stops at the last impact within that
limit and says so (notes.truncation in settings.json, one line on stderr); so does a case that reaches
--time-limit (default 600 s) or 12000 rows. With --from FILE, one case per input of a CSV (header
id,alpha,beta,gamma,r,tau0,sdot0,impacts[,s0][,stick_time]) or a JSON list of such objects, read with
check's limits; every bad line is named (field and reason, the first 20 one by one) and nothing is written
unless --skip-bad builds the others.

The suite has one writer at a time (its lock SUITE/suite.lock: a second case or fuzz into it is refused
in one line); the cases and the updated index.json go in together, or nothing does (a full disk, an error
or a signal leaves the suite as it was). Ids follow docs/reference/golden_formats.md ("What check reads"): no separators,
no dot-names, not a name of the suite's own files.

Exit status: 0 every case written, 1 some input has no case (not even impact 0 certified within the
limit, or a bad line skipped with --skip-bad; named on stderr, the others written) or the suite is
being written by another run, 2 usage error (a bad input without --skip-bad: nothing written)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from ...core.params import PARAM_NAMES
from ..cliutil import (
    COMMAND,
    CliError,
    CommandFailed,
    add_stick_time_arg,
    nonneg_int,
    note,
    progress_arg,
    real,
    suite_writer,
    tau0_type,
)

NAME = "case"
HELP = "build a certified golden-format case (or a whole suite, --from) for your own input"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..golden.oracle.ondemand import MAX_TOLERANCE_LIMIT, MIN_TOLERANCE_LIMIT, TOLERANCE_LIMIT

    _add_input_arguments(p.add_argument_group("one input (or --from)"))
    p.add_argument(
        "--from",
        dest="from_file",
        default=None,
        metavar="FILE",
        help="build one case per input of FILE (CSV with a header, or a JSON list of objects) "
        "(default: one input, from the options above)",
    )
    p.add_argument(
        "--out", required=True, metavar="SUITE", help="suite directory to write the case(s) into (required; no default)"
    )
    p.add_argument(
        "--max-tolerance",
        type=real("--max-tolerance", lo=MIN_TOLERANCE_LIMIT, hi=MAX_TOLERANCE_LIMIT),
        default=TOLERANCE_LIMIT,
        metavar="T",
        help=f"no row of a case has a tolerance of T or more: the case stops at the last impact within it "
        f"(a smaller T, a shorter and tighter case), {MIN_TOLERANCE_LIMIT:g} <= T <= {MAX_TOLERANCE_LIMIT:g} "
        f"(default {TOLERANCE_LIMIT:g})",
    )
    p.add_argument("--replace", action="store_true", help="overwrite cases of the same id already in SUITE")
    p.add_argument(
        "--skip-bad",
        action="store_true",
        help="with --from: build the good inputs and skip the bad ones (each named on stderr; exit status 1) "
        "(default: a bad input stops the command before anything is written)",
    )
    p.add_argument(
        "--time-limit",
        type=real("--time-limit", lo=1.0, hi=1e6),
        default=None,
        metavar="S",
        help="seconds a case may take, 1 <= S <= 1e6: it stops at the last impact certified in about that "
        "time and says so (default 600)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar (notes and errors still go to stderr)")


def _add_input_arguments(g) -> None:
    """The options of one input (``g``: their argument group)."""
    from ..golden.boundary import MAX_CASE_IMPACTS
    from ..golden.oracle.ondemand import TOLERANCE_LIMIT

    g.add_argument(
        "--alpha",
        type=real("--alpha", lo=0.0, hi=1e10),
        default=None,
        help="driving amplitude, 0 <= alpha <= 1e10 (no default: required without --from)",
    )
    g.add_argument(
        "--beta",
        type=real("--beta", lo=0.0, lo_open=True, hi=1e10),
        default=None,
        help="damping, 0 < beta <= 1e10 (no default: required without --from)",
    )
    g.add_argument(
        "--gamma",
        type=real("--gamma", max_abs=1e10),
        default=None,
        help="constant torque term, |gamma| <= 1e10 (no default: required without --from)",
    )
    g.add_argument(
        "--r",
        type=real("--r", lo=0.0, lo_open=True, hi=1.0),
        default=None,
        help="restitution coefficient, 0 < r <= 1 (no default: required without --from)",
    )
    g.add_argument(
        "--tau0",
        type=tau0_type(),
        default=None,
        help="initial time, |tau0| <= 1e6 (no default: required without --from)",
    )
    g.add_argument(
        "--sdot0",
        type=real("--sdot0", max_abs=1e6),
        default=None,
        help="initial velocity just before impact 0, finite, |sdot0| <= 1e6 (> 0: upper wall s = 0, < 0: "
        "lower wall s = -1); with --s0 the velocity of the free-flight start (no default: required without --from)",
    )
    g.add_argument(
        "--s0",
        type=real("--s0", lo=-1.0, lo_open=True),
        default=None,
        help="start in free flight at -1 < s0 < 0 (default: a pre-impact start)",
    )
    g.add_argument(
        "--impacts",
        type=nonneg_int("--impacts", MAX_CASE_IMPACTS),
        default=None,
        metavar="N",
        help=f"impacts after impact 0, 0 <= N <= {MAX_CASE_IMPACTS} (the case may stop earlier: "
        f"no tolerance reaches {TOLERANCE_LIMIT:g}) (no default: required without --from)",
    )
    add_stick_time_arg(g, None)
    g.add_argument(
        "--id", default=None, help="case id: the folder name under SUITE (no default: required without --from)"
    )


ONE = (*PARAM_NAMES, "tau0", "sdot0", "impacts", "id")


#: Bad lines of a --from file named one by one (the others are counted).
MAX_REPORTED = 20


def _inputs(args: argparse.Namespace):
    """``(inputs, problems)``: the good inputs and the bad ones (:class:`golden.oracle.inputs.InputProblem`)."""
    from ..golden.oracle.inputs import case_input, read_input_file

    given = [k for k in ONE + ("s0", "stick_time") if getattr(args, k) is not None]
    if args.from_file is not None:
        if given:
            raise CliError(f"--from FILE takes the inputs from FILE: drop --{given[0].replace('_', '-')}")
        f = read_input_file(args.from_file)
        return f.inputs, f.problems
    if args.skip_bad:
        raise CliError("--skip-bad needs --from FILE (it skips the file's bad inputs)")
    missing = [f"--{k}" for k in ONE if getattr(args, k) is None]
    if missing:
        raise CliError(f"missing {', '.join(missing)} (or give --from FILE)")
    one = case_input(
        args.id,
        args.alpha,
        args.beta,
        args.gamma,
        args.r,
        args.tau0,
        args.sdot0,
        args.impacts,
        s0=args.s0,
        stick_time=args.stick_time,
    )
    return [one], []


def _report_bad(args: argparse.Namespace, inputs: list, problems: list) -> None:
    """Name every bad input (the first :data:`MAX_REPORTED` one by one); without ``--skip-bad`` stop
    before anything is written (a usage error, exit status 2)."""
    where = f"--from {args.from_file}"
    total = len(inputs) + len(problems)
    rest = f"--skip-bad builds the {len(inputs)} good one(s)" if inputs else "no input is good"
    if not args.skip_bad and len(problems) == 1:
        raise CliError(f"{where}: {problems[0]} (1 bad input of {total}: nothing written; {rest})")
    label = note if args.skip_bad else (lambda text: print(f"{COMMAND[0]}: error: {text}", file=sys.stderr))
    for p in problems[:MAX_REPORTED]:
        label(f"{where}: {'skipped: ' if args.skip_bad else ''}{p}")
    more = f", {len(problems) - MAX_REPORTED} more not shown" if len(problems) > MAX_REPORTED else ""
    if not args.skip_bad:
        raise CliError(f"{where}: {len(problems)} bad inputs of {total} (named above{more}): nothing written; {rest}")
    if more:
        note(f"{where}: {len(problems) - MAX_REPORTED} more bad inputs skipped (not shown)")


def _check_suite(suite: Path, inputs: list, replace: bool, out: str) -> None:
    """Before anything is built (the suite's lock held): the ids are free (or, with ``--replace``, case
    folders), no name the command writes is a link (check refuses links leading out of a suite), and the
    suite as it is reads as ``check`` reads it (its index and cases: :func:`golden.oracle.ondemand.index_text`)."""
    from ..golden.oracle.ondemand import index_text

    taken, odd = [], []
    for c in inputs:
        folder = suite / c.id
        if not os.path.lexists(folder):
            continue
        if folder.is_symlink() or not folder.is_dir():
            odd.append(f"{str(folder)!r} is {'a link' if folder.is_symlink() else 'not a folder'}")
        elif any(p.is_symlink() for p in folder.iterdir() if p.name in CASE_FILES):
            odd.append(f"{str(folder)!r} holds a link among {', '.join(CASE_FILES)}")
        elif any(folder.iterdir()):  # an empty folder is no case (a run of an older version may leave one)
            taken.append(c.id)
    if (suite / "index.json").is_symlink():
        odd.append(f"{str(suite / 'index.json')!r} is a link")
    if odd:
        raise CliError(f"--out {out}: {odd[0]}: refused (a suite's files are written in place, never through a link)")
    if taken and not replace:
        raise CliError(
            f"--out {out}: case {taken[0]!r} exists"
            + (f" (and {len(taken) - 1} more)" if len(taken) > 1 else "")
            + ": use --replace to overwrite"
        )
    index_text(suite)  # the suite as it is must read (ValueError: one line) before minutes are spent


def commit_cases(suite: Path, built: list) -> None:
    """Write the cases (:class:`golden.oracle.ondemand.UserCase`) and the index that lists them into a staging
    folder in the suite, then move them all in at once (:func:`io.atomic.staged`): a full disk or an error
    leaves the suite as it was.  The caller holds the suite's lock (:func:`writelock.suite_lock`); ``fuzz``
    may write its findings the same way."""
    from ..golden.formats.index import INDEX_NAME
    from ..golden.oracle.ondemand import index_text, write_user_case
    from ..io.atomic import staged, write_text_atomic

    with staged(suite, "case") as stage:
        overlay = {}
        for case in built:
            folder = write_user_case(stage, case, write_text_atomic)
            overlay.update({f"{case.input.id}/{f}": folder / f for f in CASE_FILES})
        write_text_atomic(stage / INDEX_NAME, index_text(suite, overlay))


def run(args: argparse.Namespace) -> int:
    from ...core.progress import Bar
    from ..cliutil import check_output_dir
    from ..golden.oracle.ondemand import TIME_LIMIT_S, CaseError, build_user_case
    from ..golden.paths import DEFAULT_SUITE

    inputs, problems = _inputs(args)
    suite = Path(args.out)
    if suite.resolve() == DEFAULT_SUITE.resolve():
        raise CliError(f"--out {args.out}: the shipped suite is written by its generator only; choose another folder")
    check_output_dir(args.out, "--out")
    if problems:
        _report_bad(args, inputs, problems)
    if not inputs:
        raise CommandFailed(f"--from {args.from_file}: no good input: nothing written")
    failed, built = len(problems), []
    with suite_writer(suite, "--out", args.out):
        _check_suite(suite, inputs, args.replace, args.out)
        with Bar("case", total=len(inputs), unit="cases", enabled=progress_arg(args) is not False) as bar:
            for k, inp in enumerate(inputs):
                try:
                    built.append(
                        build_user_case(
                            inp, max_tolerance=args.max_tolerance, time_limit_s=args.time_limit or TIME_LIMIT_S
                        )
                    )
                except CaseError as e:
                    note(f"no case: {e}")
                    failed += 1
                bar(k + 1)
        for case in built:
            if case.message:
                note(case.message)
        if built:
            commit_cases(suite, built)
    if failed:
        raise CommandFailed(
            f"{failed} of {len(inputs) + len(problems)} input(s) have no case (named above); "
            f"{len(built)} written to {args.out}"
        )
    return 0


#: The files of a case folder that ``case`` writes.
CASE_FILES = ("settings.json", "expected.csv", "provenance.json")
