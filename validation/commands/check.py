"""Score an implementation's impact sequences against the golden conformance suite (docs/golden.md).

PATH is a directory holding one <case-id>.csv per case, in the impact-sequence layout
(header n,tau,tau_mod_2pi,wall,sdot,kind; extra trailing columns are ignored). Each case passes when
every row matches: n, wall and kind exactly, tau, tau_mod_2pi (circular) and sdot within the case's
absolute/relative tolerances. Each file is scored on its own: a missing one fails its case ("no
output"), a malformed one is an error of its case (one line on stderr naming file, line and column).
--cases and --level select cases (repeated, they add up), --exclude leaves some out: the others are
skipped (reported as such). --known-failures FILE lists cases expected to fail, with a reason.
A failing case is shown expected against got (the golden and the output rows around the first
difference). Exit status: 0 every case scored passes (known failures allowed), 1 some case fails,
is malformed or has no output, or a known failure passes; 2 usage error (or a malformed suite,
--known-failures file, or --require-suite mismatch).

With --self, our own track (--track map|scipy|diffrax) is run on every case and scored instead.

With --orbits, PATH holds one <id>.json per certified periodic orbit or bifurcation point of
validation/golden/orbits (points, multipliers, value; docs/golden.md), scored against the records'
enclosures; --orbits --self scores our float64 Newton solvers.

For CI (docs/reference/golden_commands.md, "In CI"): --junit-xml FILE (one testcase per case or record)
and --json FILE (strict JSON) besides the table, written whatever the outcome; the header names the
suite's version and digest; --suite-version prints them (--json FILE: the folders, index and ids as
JSON; exit 1 if the suite's files differ from the recorded version's), --export-suite DIR copies the
suite with its format description, and --require-suite SPEC (1, 1.0, ~=1.0, 1.0.0) refuses to score
(exit 2) another version or modified files.  Scoring files needs numpy alone (pip install --no-deps
gear-rattle numpy); --self needs the full install."""

from __future__ import annotations

import argparse
from functools import partial
from pathlib import Path

from ..cliutil import CliError, add_renamed, check_input_path, check_output_dir
from ._check_common import check_items, suite_header, write_output

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
    for option, text in (
        (
            "--cases",
            "only these case (or orbit record) ids, the others skipped; repeated, the lists add up (default: all)",
        ),
        ("--exclude", "leave these case (or orbit record) ids out: skipped, reported as such (default: none)"),
    ):
        p.add_argument(option, nargs="+", action="extend", default=None, metavar="ID", help=text)
    p.add_argument(
        "--known-failures",
        default=None,
        metavar="FILE",
        help="cases (or records) expected to fail: one 'ID reason' per line, '#' comments (docs/reference/golden_commands.md, "
        "Known failures); they are reported as expected failures, and one that passes fails the run "
        "(default: none)",
    )
    p.add_argument(
        "--level",
        action="extend",
        type=_levels,
        default=None,
        metavar="L[,L...]",
        help="only the cases of these levels, e.g. 1,2, the others skipped (1, 2 or 3; repeated, they add "
        "up; orbit records are level 2; with --cases: the cases in both; default: all)",
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
    _add_report_arguments(p)


def _add_report_arguments(p: argparse.ArgumentParser) -> None:
    """The options of the output and of the suite: --summary, --json, --junit-xml, --suite-version,
    --export-suite, --require-suite, --quiet."""
    p.add_argument(
        "--summary", action="store_true", help="print only the summary line of the table (it names the failing cases)"
    )
    p.add_argument(
        "--json",
        default=None,
        metavar="FILE",
        help="also write the results as strict JSON to FILE ('-': stdout, instead of the table): "
        "the suite's version and digest, the counts, per case id, level, verdict, digits per column, "
        "worst |error| / tolerance, the first failure (file, line, column, expected and actual rows, "
        "error, tolerance); with --suite-version the suite's folders, index and ids (default: none)",
    )
    p.add_argument(
        "--junit-xml",
        default=None,
        metavar="FILE",
        help="also write a JUnit XML report to FILE (one testcase per case or orbit record, a failure "
        "with expected against got for each failing one, skipped ones and known failures as skipped; "
        "the suite's version and digest as properties; default: none)",
    )
    p.add_argument(
        "--suite-version",
        action="store_true",
        help="print the suite's version and the digests of its files (with --suite DIR: of DIR, and "
        "whether they match the recorded version's; exit 1 if not), then exit; PATH not needed; with "
        "--json FILE also the folders of the cases and records, the index and the ids, as JSON",
    )
    p.add_argument(
        "--export-suite",
        default=None,
        metavar="DIR",
        help="copy the installed suite (cases/, orbits/, its format description FORMAT.md and suite.json) "
        "into DIR, a new or empty directory, for an implementation that cannot import Python; then exit "
        "(default: none)",
    )
    p.add_argument(
        "--require-suite",
        default=None,
        type=_requirement,
        metavar="SPEC",
        help="refuse to score (exit 2) unless the suite's version meets SPEC with its files unmodified: "
        "1 (any 1.x.y), 1.0 (any 1.0.y), ~=1.0 (1.0 or later, before 2), 1.0.0 (exactly) "
        "(pinning a suite version in CI; default: any)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bars (notes and errors still go to stderr)")


def needs_jax(args: argparse.Namespace) -> bool:
    """Only ``--self`` computes (our own tracks): scoring files needs numpy alone (the light install)."""
    return bool(args.self_check) and not args.suite_version


def _requirement(text: str) -> str:
    """``--require-suite SPEC`` (argparse type): one of the forms of :func:`golden.formats.version.satisfies`."""
    from ..golden.formats.version import parse_requirement

    try:
        parse_requirement(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None
    return text


def _levels(text: str) -> list[int]:
    """``--level 1,2``: a comma-separated list of levels (argparse type)."""
    from ..golden.formats.cases import LEVELS

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
    from ..golden.formats.cases import sequence_from_impacts
    from ..golden.scoring.cases import problem_score
    from ..golden.scoring.run import Ready
    from ..golden.self_check import run_case
    from ..io import write_csv

    from ...mapimpl.tracks import get

    try:
        get(track)  # loads a numerical track: its integrator must be installed
    except ImportError as e:
        raise CliError(f"track {track!r} is not available: {e}") from None
    out: dict = {}
    for case in cases:
        label = f"<{track} track, case {case.id}>"
        try:
            seq = run_case(case, track)
        except Exception as e:  # noqa: BLE001 - a crash on one case is an error of that case alone
            msg = " ".join(f"our {track} track raised {type(e).__name__}: {e}".split())[:500]
            out[case.id] = Ready(problem_score(case, "crash", msg, label))
            continue
        if write:
            label = write_output(member(write, case.id, ".csv"), write_csv, *seq.table())
        out[case.id] = sequence_from_impacts(seq, label)
    return out


def _run_options(args: argparse.Namespace) -> None:
    """The options' combinations (one-line usage errors)."""
    from ..cliutil import check_distinct, check_output_file

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
    if args.known_failures is not None:
        check_input_path(args.known_failures, "--known-failures", directory=False)
    if args.path is not None and (not args.path.strip() or _exists(args.path)):
        # an empty name, a file, an unreadable folder: usage errors; a folder that is not there is scored
        # ("no output" for every case, the reports written)
        check_input_path(args.path, "PATH", directory=True)


def _exists(path: str) -> bool:
    try:
        return Path(path).exists()
    except OSError:  # a name the system refuses (too long): check_input_path says so
        return True


def run(args: argparse.Namespace) -> int:
    from ..golden.formats.cases import MalformedFile, load_suite
    from ..golden.paths import DEFAULT_SUITE
    from ..golden.scoring.run import CASES

    if args.suite_version:
        from ._check_suite import suite_version

        return suite_version(args, suite_header)
    if args.export_suite is not None:
        from ._check_suite import export_suite

        return export_suite(args, suite_header)
    _run_options(args)
    if args.orbits:
        from ._check_orbits import run_orbits

        return run_orbits(args)
    suite = check_input_path(args.suite, "--suite", directory=True) if args.suite is not None else DEFAULT_SUITE
    info = suite_header(args, suite, "cases")
    try:
        cases = load_suite(suite)
    except MalformedFile as e:
        raise CliError(f"suite: {e}") from None
    return check_items(args, info, cases, CASES, suite, partial(_self_outputs, track=args.track, write=args.out))
