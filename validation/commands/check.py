"""Score an implementation's impact sequences against the golden conformance suite (docs/golden.md).

PATH is a directory holding one <case-id>.csv per case, in the impact-sequence layout
(header n,tau,tau_mod_2pi,wall,sdot,kind; extra trailing columns are ignored). Each case passes when
every row matches: n, wall and kind exactly, tau, tau_mod_2pi (circular) and sdot within the case's
absolute/relative tolerances; a missing file fails its case ("no output"). --cases and --level select
cases (repeated, they add up). Exit status: 0 all pass, 1 some case fails, 2 usage error or malformed
input (missing column, wrong header, a field or file outside the format; one line per file).

With --self, our own track (--track map|scipy|diffrax) is run on every case and scored instead.

With --orbits, PATH holds one <id>.json per certified periodic orbit or bifurcation point of
validation/golden/orbits (points, multipliers, value; docs/golden.md), scored against the records'
enclosures; --orbits --self scores our float64 Newton solvers.

For CI (docs/golden.md, "Using the suite in CI"): --junit-xml FILE (one testcase per case or record)
and --json FILE (strict JSON) besides the table; the header names the suite's version and digest;
--suite-version prints them (exit 1 if the suite's files differ from the recorded version's) and
--require-suite VERSION refuses to score (exit 2) any other version or modified files.  Scoring
files needs numpy alone (pip install --no-deps gear-rattle numpy); --self needs the full install."""

from __future__ import annotations

import argparse

from ..cliutil import CliError, add_renamed, check_input_path, check_output_dir, to_stdout
from ._check_scoring import (
    no_selection,
    read_output_folder,
    report_malformed,
    score_and_report,
    suite_header,
    write_output,
)

NAME = "check"
HELP = "score another implementation's output against the golden conformance suite"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "path",
        nargs="?",
        default=None,
        help="directory with one <case-id>.csv per case (default: none; omit with --self)",
    )
    from ..golden.paths import DEFAULT_ORBITS, DEFAULT_SUITE

    p.add_argument(
        "--suite",
        default=None,
        help=f"suite directory (default: the copy installed with this package, {DEFAULT_SUITE}; "
        f"with --orbits {DEFAULT_ORBITS})",
    )
    p.add_argument(
        "--cases",
        nargs="+",
        action="extend",
        default=None,
        metavar="ID",
        help="only these case (or orbit record) ids; repeated, the lists add up (default: all)",
    )
    p.add_argument(
        "--level",
        action="extend",
        type=_levels,
        default=None,
        metavar="L[,L...]",
        help="only the cases of these levels, e.g. 1,2 (1, 2 or 3; repeated, they add up; orbit records "
        "are level 2; with --cases: the cases in both; default: all)",
    )
    p.add_argument(
        "--self", dest="self_check", action="store_true", help="run our own track on every case and score it"
    )
    p.add_argument(
        "--track", choices=("map", "scipy", "diffrax"), default="map", help="track used by --self (default map)"
    )
    p.add_argument(
        "--out",
        default=None,
        metavar="DIR",
        help="with --self: also write the track's <case-id>.csv (with --orbits <id>.json) files to DIR "
        "(default: none written)",
    )
    add_renamed(p, "--write", "--out")
    p.add_argument(
        "--orbits",
        action="store_true",
        help="score periodic orbits and bifurcation points (one <id>.json per record of "
        "validation/golden/orbits, or --self) instead of impact sequences",
    )
    p.add_argument(
        "--summary", action="store_true", help="print only the summary line of the table (it names the failing cases)"
    )
    p.add_argument(
        "--json",
        default=None,
        metavar="FILE",
        help="also write the results as strict JSON to FILE ('-': stdout, instead of the table): "
        "the suite's version and digest, per case id, level, passed, digits per column, worst "
        "|error| / tolerance, first failing row (default: none)",
    )
    p.add_argument(
        "--junit-xml",
        default=None,
        metavar="FILE",
        help="also write a JUnit XML report to FILE (one testcase per case or orbit record, a failure "
        "with the note and the digits for each failing one; the suite's version and digest as "
        "properties; default: none)",
    )
    p.add_argument(
        "--suite-version",
        action="store_true",
        help="print the suite's version and the digests of its files (with --suite DIR: of DIR, and "
        "whether they match the recorded version's; exit 1 if not), then exit; PATH not needed",
    )
    p.add_argument(
        "--require-suite",
        default=None,
        metavar="VERSION",
        help="refuse to score (exit 2) unless the suite is VERSION with its files unmodified "
        "(pinning a suite version in CI; default: any)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bars (notes and errors still go to stderr)")


def needs_jax(args: argparse.Namespace) -> bool:
    """Only ``--self`` computes (our own tracks): scoring files needs numpy alone (the light install)."""
    return bool(args.self_check) and not args.suite_version


def suite_version(args: argparse.Namespace) -> int:
    """``--suite-version``: the version and digests of the suite (or of ``--suite DIR``); exit 1 where
    the files differ from the recorded version's."""
    from ..golden.version import PARTS, recorded

    if args.suite is not None:
        part = "orbits" if args.orbits else "cases"
        infos = [suite_header(args, check_input_path(args.suite, "--suite", directory=True), part)]
    else:
        infos = [suite_header(args, folder, part) for part, folder in PARTS.items()]
    lines = [info.line() for info in infos]
    if args.suite is None:
        lines.append(f"suite digest {recorded().get('digest')}")
    to_stdout("\n".join(lines) + "\n")
    return 0 if all(i.matches for i in infos) else 1


def _levels(text: str) -> list[int]:
    """``--level 1,2``: a comma-separated list of levels (argparse type)."""
    from ..golden.suite import LEVELS

    out = []
    for part in text.split(","):
        if part.strip() not in [str(v) for v in LEVELS]:
            raise argparse.ArgumentTypeError(
                f"{text!r}: allowed levels {', '.join(map(str, LEVELS))}, comma-separated (e.g. 1,2)"
            )
        out.append(int(part))
    return out


def _self_outputs(cases, track: str, write: str | None):
    from ..golden.boundary import member
    from ..golden.suite import run_case, sequence_from_impacts
    from ..io import write_csv

    from ...mapimpl.tracks import get

    try:
        get(track)  # loads a numerical track: its integrator must be installed
    except ImportError as e:
        raise CliError(f"track {track!r} is not available: {e}") from None
    out = {}
    for case in cases:
        seq = run_case(case, track)
        label = f"<{track} track, case {case.id}>"
        if write:
            label = write_output(member(write, case.id, ".csv"), write_csv, *seq.table())
        out[case.id] = sequence_from_impacts(seq, label)
    return out


def run(args: argparse.Namespace) -> int:
    from ..cliutil import check_distinct, check_output_file
    from ..golden.results import case_result
    from ..golden.suite import (
        DEFAULT_SUITE,
        MalformedFile,
        load_suite,
        no_output_score,
        read_sequence,
        score_sequence,
    )

    if args.suite_version:
        return suite_version(args)
    for option in ("--json", "--junit-xml"):
        check_output_file(getattr(args, option[2:].replace("-", "_")), option)
    check_distinct(**{"--json": args.json, "--junit-xml": args.junit_xml})
    if args.json == "-" and args.junit_xml == "-":
        raise CliError("--json - and --junit-xml - both name stdout: allowed one of them")
    if args.self_check and args.path is not None:
        raise CliError("give either PATH or --self, not both")
    if not args.self_check and args.path is None:
        raise CliError("missing PATH (a directory with one <case-id>.csv per case), or use --self")
    if args.out is not None and not args.self_check:
        raise CliError("--out needs --self (it keeps the files of our own track)")
    if args.out is not None:
        check_output_dir(args.out, "--out")
    if args.orbits:
        from ._check_orbits import run_orbits

        return run_orbits(args)
    suite = check_input_path(args.suite, "--suite", directory=True) if args.suite is not None else DEFAULT_SUITE
    info = suite_header(args, suite, "cases")
    try:
        cases = load_suite(suite, args.cases, args.level)
    except MalformedFile as e:
        raise CliError(f"suite: {e}") from None
    if not cases:
        raise no_selection("suite", args, suite)
    if args.self_check:
        outputs = _self_outputs(cases, args.track, args.out)
    else:
        root, outputs, errors = read_output_folder(
            args.path, cases, ".csv", lambda path, case, root: read_sequence(path, inside=root)
        )
        if errors:
            return report_malformed(args, cases, errors, info, orbits=False)
    return score_and_report(
        args,
        cases,
        outputs,
        info,
        orbits=False,
        root=None if args.self_check else root,
        suffix=".csv",
        score=score_sequence,
        no_output=no_output_score,
        result=case_result,
    )
