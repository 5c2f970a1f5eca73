"""Build a golden-format case for your own input: its orbit certified by ball arithmetic, its tolerances set
by every rule of docs/golden.md ("Asking the oracle").

Writes SUITE/ID/ (settings.json, expected.csv, provenance.json) and updates SUITE/index.json (its other
fields kept). Score an implementation against it with `gear-rattle check OUT --suite SUITE`. No case
has a tolerance of 1e-6 or more: where the error of a correct float64 implementation, amplified along the
orbit, would need one, the case stops at the last impact within that limit and says so (notes.truncation
in settings.json, one line on stderr). With --from FILE, one case per input of a CSV (header
id,alpha,beta,gamma,r,tau0,sdot0,impacts[,s0][,stick_time]) or a JSON list of such objects.

Exit status: 0 every case written, 1 some input has no case (not even impact 0 certified within the
limit; named on stderr, the others written), 2 usage error."""

from __future__ import annotations

import argparse
from pathlib import Path

from ...core.params import PARAM_NAMES
from ..cliutil import CliError, CommandFailed, add_stick_time_arg, nonneg_int, note, progress_arg, real, tau0_type

NAME = "case"
HELP = "build a certified golden-format case (or a whole suite, --from) for your own input"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from ..golden.ondemand import MAX_CASE_IMPACTS, TOLERANCE_LIMIT

    g = p.add_argument_group("one input (or --from)")
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
    p.add_argument("--replace", action="store_true", help="overwrite cases of the same id already in SUITE")
    p.add_argument("--quiet", action="store_true", help="no progress bar (notes and errors still go to stderr)")


ONE = (*PARAM_NAMES, "tau0", "sdot0", "impacts", "id")


def _inputs(args: argparse.Namespace):
    from ..golden.ondemand import case_input, read_inputs

    given = [k for k in ONE + ("s0", "stick_time") if getattr(args, k) is not None]
    if args.from_file is not None:
        if given:
            raise CliError(f"--from FILE takes the inputs from FILE: drop --{given[0].replace('_', '-')}")
        return read_inputs(args.from_file)
    missing = [f"--{k}" for k in ONE if getattr(args, k) is None]
    if missing:
        raise CliError(f"missing {', '.join(missing)} (or give --from FILE)")
    return [
        case_input(
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
    ]


def run(args: argparse.Namespace) -> int:
    from ...core.progress import Bar
    from ..cliutil import check_output_dir
    from ..golden.ondemand import CaseError, build_user_case, update_index, write_user_case
    from ..io.atomic import commit_pending, write_text_atomic
    from ..golden.suite import DEFAULT_SUITE

    inputs = _inputs(args)
    suite = Path(args.out)
    if suite.resolve() == DEFAULT_SUITE.resolve():
        raise CliError(f"--out {args.out}: the shipped suite is written by its generator only; choose another folder")
    check_output_dir(args.out, "--out")
    if not args.replace:
        taken = [c.id for c in inputs if (suite / c.id).exists()]
        if taken:
            raise CliError(
                f"--out {args.out}: case {taken[0]!r} exists"
                + (f" (and {len(taken) - 1} more)" if len(taken) > 1 else "")
                + ": use --replace to overwrite"
            )
    failed = 0
    with Bar("case", total=len(inputs), unit="cases", enabled=progress_arg(args) is not False) as bar:
        for k, inp in enumerate(inputs):
            try:
                case = build_user_case(inp)
            except CaseError as e:
                note(f"no case: {e}")
                failed += 1
            else:
                write_user_case(suite, case, write_text_atomic)
                if case.message:
                    note(case.message)
            bar(k + 1)
    if failed < len(inputs):
        commit_pending()  # the case files in place first: the index lists the folders and digests them
        update_index(suite, write_text_atomic)
    if failed:
        commit_pending()  # the cases that were built stay (io.atomic discards a failing command's files)
        raise CommandFailed(
            f"{failed} of {len(inputs)} input(s) have no case (named above); "
            f"{len(inputs) - failed} written to {args.out}"
        )
    return 0
