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
import sys
import time
from functools import partial
from pathlib import Path

from ..cliutil import CliError, add_renamed, check_input_path, check_output_dir, to_stdout

NAME = "check"
HELP = "score another implementation's output against the golden conformance suite"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", nargs="?", default=None,
                   help="directory with one <case-id>.csv per case (default: none; omit with --self)")
    from ..golden.paths import DEFAULT_ORBITS, DEFAULT_SUITE

    p.add_argument("--suite", default=None,
                   help=f"suite directory (default: the copy installed with this package, {DEFAULT_SUITE}; "
                        f"with --orbits {DEFAULT_ORBITS})")
    p.add_argument("--cases", nargs="+", action="extend", default=None, metavar="ID",
                   help="only these case (or orbit record) ids; repeated, the lists add up (default: all)")
    p.add_argument("--level", action="extend", type=_levels, default=None, metavar="L[,L...]",
                   help="only the cases of these levels, e.g. 1,2 (1, 2 or 3; repeated, they add up; orbit records "
                        "are level 2; with --cases: the cases in both; default: all)")
    p.add_argument("--self", dest="self_check", action="store_true",
                   help="run our own track on every case and score it")
    p.add_argument("--track", choices=("map", "scipy", "diffrax"), default="map",
                   help="track used by --self (default map)")
    p.add_argument("--out", default=None, metavar="DIR",
                   help="with --self: also write the track's <case-id>.csv (with --orbits <id>.json) files to DIR "
                        "(default: none written)")
    add_renamed(p, "--write", "--out")
    p.add_argument("--orbits", action="store_true",
                   help="score periodic orbits and bifurcation points (one <id>.json per record of "
                        "validation/golden/orbits, or --self) instead of impact sequences")
    p.add_argument("--summary", action="store_true",
                   help="print only the summary line of the table (it names the failing cases)")
    p.add_argument("--json", default=None, metavar="FILE",
                   help="also write the results as strict JSON to FILE ('-': stdout, instead of the table): "
                        "the suite's version and digest, per case id, level, passed, digits per column, worst "
                        "|error| / tolerance, first failing row (default: none)")
    p.add_argument("--junit-xml", default=None, metavar="FILE",
                   help="also write a JUnit XML report to FILE (one testcase per case or orbit record, a failure "
                        "with the note and the digits for each failing one; the suite's version and digest as "
                        "properties; default: none)")
    p.add_argument("--suite-version", action="store_true",
                   help="print the suite's version and the digests of its files (with --suite DIR: of DIR, and "
                        "whether they match the recorded version's; exit 1 if not), then exit; PATH not needed")
    p.add_argument("--require-suite", default=None, metavar="VERSION",
                   help="refuse to score (exit 2) unless the suite is VERSION with its files unmodified "
                        "(pinning a suite version in CI; default: any)")
    p.add_argument("--quiet", action="store_true", help="no progress bars (notes and errors still go to stderr)")


def needs_jax(args: argparse.Namespace) -> bool:
    """Only ``--self`` computes (our own tracks): scoring files needs numpy alone (the light install)."""
    return bool(args.self_check) and not args.suite_version


def suite_header(args: argparse.Namespace, folder: Path, part: str):
    """The :class:`golden.version.SuiteInfo` of the suite scored (``folder``: its cases or orbits), for the
    header and the reports; with ``--require-suite VERSION`` a one-line error unless it is that version
    with its files unmodified."""
    from ..golden.version import suite_info

    try:
        info = suite_info(folder, part)
    except OSError as e:
        raise CliError(f"--suite: cannot read {str(folder)!r}: {e.strerror or e}") from None
    if args.require_suite is not None and not (info.version == args.require_suite and info.matches):
        raise CliError(f"--require-suite {args.require_suite}: the suite is {info.label} "
                       f"({info.part} {info.folder}, {info.digest})")
    return info


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


def report(args: argparse.Namespace, results: list[dict], info, *, orbits: bool, times: dict,
           table_to_stdout: bool = True) -> int:
    """The table (or its summary line) on stdout, ``--json`` and ``--junit-xml``; the exit status."""
    from ..cliutil import write_text
    from ..golden.results import document, junit_xml, summary_line, table
    from ..io import json_text

    source = f"our {args.track} track" if args.self_check else str(args.path)
    doc = document(results, info.as_dict(), orbits=orbits, source=source)
    if args.junit_xml is not None:
        write_text(junit_xml(doc, times), args.junit_xml, "--junit-xml")
    if args.json is not None:
        write_text(json_text(doc) + "\n", args.json, "--json")
    if table_to_stdout and "-" not in (args.json, args.junit_xml):
        lines = [summary_line(results, orbits, info.label)]
        if not args.summary:
            lines = [f"suite: {info.line()}", *table(results, orbits), *lines]
        to_stdout("\n".join(lines) + "\n")
    return 0 if all(r["passed"] for r in results) else 1


def _levels(text: str) -> list[int]:
    """``--level 1,2``: a comma-separated list of levels (argparse type)."""
    from ..golden.suite import LEVELS

    out = []
    for part in text.split(","):
        if part.strip() not in [str(v) for v in LEVELS]:
            raise argparse.ArgumentTypeError(f"{text!r}: allowed levels {', '.join(map(str, LEVELS))}, "
                                             "comma-separated (e.g. 1,2)")
        out.append(int(part))
    return out


def no_selection(what: str, args: argparse.Namespace, where) -> CliError:
    """The error when the selection holds nothing."""
    how = " and ".join(x for x in (f"--cases {' '.join(args.cases)}" if args.cases else "",
                                   f"--level {','.join(map(str, sorted(set(args.level))))}" if args.level else "")
                       if x)
    return CliError(f"{what} {str(where)!r} has no {'record' if 'orbit' in what else 'case'}"
                    + (f" selected by {how}" if how else ""))


def write_output(path: Path, write, *args) -> str:
    """Write one ``--out`` file with ``write(path, *args)`` (one of :mod:`validation.io`'s writers; an OS
    error is a one-line usage error); returns its path."""
    from ..cliutil import write_file

    write_file("--out", path, lambda p: write(p, *args))
    return str(path)


def score_and_report(args: argparse.Namespace, items, outputs: dict, info, *, orbits: bool, root: Path | None,
                     suffix: str, score, no_output, result) -> int:
    """Score each case or orbit record (``items``) on its output (``outputs[id]``; None: the file
    ``root/<id><suffix>`` is missing, a failing "no output"), timing each, and :func:`report` the results
    (``result(item, score)``: :func:`golden.results.case_result` or ``orbit_result``)."""
    from ..golden.suite import MalformedFile

    results, times = [], {}
    for item in items:
        t0 = time.perf_counter()
        got = outputs[item.id]
        try:
            if got is None:
                assert root is not None, "an output is missing only where it is read from root (not with --self)"
                sc = no_output(item, root / f"{item.id}{suffix}")
            else:
                sc = score(item, got)
        except MalformedFile as e:
            raise CliError(str(e)) from None
        results.append(result(item, sc))
        times[item.id] = time.perf_counter() - t0
    return report(args, results, info, orbits=orbits, times=times)


def read_outputs(reads: dict, malformed, missing=None) -> tuple[dict, dict]:
    """``({id: read()}, {id: problem})`` for ``reads = {id: read}`` (each reads one file): where a file
    is missing (``missing``: its exception class) the value is ``None`` (a failing case, "no output");
    where a file is malformed (``malformed``: the exception class) its one-line problem is reported on
    stderr and kept in the second mapping (the run's exit status is then 2, and ``--json`` and
    ``--junit-xml`` list it as an error)."""
    out, errors = {}, {}
    for key, read in reads.items():
        try:
            out[key] = read()
        except malformed as e:
            if missing is not None and isinstance(e, missing):
                out[key] = None
            else:
                text = " ".join(str(e).split())
                errors[key] = text if len(text) <= 500 else text[:500] + " ... (cut)"
    for problem in errors.values():
        print(f"gear-rattle check: error: {problem}", file=sys.stderr)
    return out, errors


def report_malformed(args: argparse.Namespace, items, errors: dict, info, *, orbits: bool) -> int:
    """Exit status 2 for malformed output files (each already named on stderr); ``--json`` and
    ``--junit-xml`` are still written, each malformed file an error and the others not scored."""
    from ..golden.results import malformed_result

    if args.json is None and args.junit_xml is None:
        return 2
    results = [malformed_result(item.id, getattr(item, "level", None), errors.get(item.id), orbits) for item in items]
    report(args, results, info, orbits=orbits, times={}, table_to_stdout=False)
    return 2


def _self_outputs(cases, track: str, write: str | None):
    from ..golden.suite import run_case, sequence_from_impacts
    from ..io import write_csv

    try:
        if track != "map":
            import importlib

            from ...mapimpl.tracks import _MODULES

            importlib.import_module(_MODULES[track])
    except ImportError as e:
        raise CliError(f"track {track!r} is not available: {e}") from None
    out = {}
    for case in cases:
        seq = run_case(case, track)
        label = f"<{track} track, case {case.id}>"
        if write:
            label = write_output(Path(write) / f"{case.id}.csv", write_csv, *seq.table())
        out[case.id] = sequence_from_impacts(seq, label)
    return out


def run(args: argparse.Namespace) -> int:
    from ..cliutil import check_distinct, check_output_file
    from ..golden.results import case_result
    from ..golden.suite import DEFAULT_SUITE, MalformedFile, MissingFile, load_suite, no_output_score, \
        read_sequence, score_sequence

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
        root = check_input_path(args.path, "PATH", directory=True)
        outputs, errors = read_outputs({case.id: partial(read_sequence, root / f"{case.id}.csv") for case in cases},
                                       MalformedFile, MissingFile)
        if errors:
            return report_malformed(args, cases, errors, info, orbits=False)
    return score_and_report(args, cases, outputs, info, orbits=False, root=None if args.self_check else root,
                            suffix=".csv", score=score_sequence, no_output=no_output_score, result=case_result)
