"""What the two modes of ``gear-rattle check`` -- the impact cases (:mod:`.check`) and the orbit records
(:mod:`._check_orbits`) -- share: the suite's header and its ``--require-suite`` check, the run composed of
the library's steps (:mod:`validation.golden.scoring.run`: the selection, the known failures, the outputs
read or computed, the scores as typed results), the reports written (``--junit-xml``, ``--json``, the
table and details on stdout) and the exit status.  Each step's error is one line (a usage error).  Below
both modes, so that neither imports the other's module."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..cliutil import CliError, to_stdout


def suite_header(args: argparse.Namespace, folder: Path, part: str):
    """The :class:`golden.formats.version.SuiteInfo` of the suite scored (``folder``: its cases or orbits),
    for the header and the reports; with ``--require-suite SPEC`` a one-line error unless its version meets
    SPEC (:func:`golden.formats.version.satisfies`) with its files unmodified."""
    from ..golden.formats.textformat import MalformedFile
    from ..golden.formats.version import satisfies, suite_info

    try:
        info = suite_info(folder, part)
    except OSError as e:
        raise CliError(f"--suite: cannot read {str(folder)!r}: {e.strerror or e}") from None
    except MalformedFile as e:
        raise CliError(f"suite: {e}") from None
    spec = args.require_suite
    if spec is not None and not (satisfies(info.version, spec) and info.matches):
        why = "" if satisfies(info.version, spec) else f", not {spec}"
        raise CliError(
            f"--require-suite {spec}: the suite is {info.label}{why} ({info.part} {info.folder}, {info.digest})"
        )
    return info


def check_items(args: argparse.Namespace, info, items, scorer, where, self_outputs=None) -> int:
    """Select, read (or, with ``--self``, compute: ``self_outputs(selected)``), score and report every
    item of the suite (``items``, in order; ``scorer``: :data:`golden.scoring.run.CASES` or ``ORBITS``;
    ``where``: the suite folder, for messages)."""
    from ..golden.formats.textformat import MalformedFile
    from ..golden.scoring import run
    from ..golden.scoring.results import CheckRun, Selection

    selection = Selection(
        tuple(args.cases) if args.cases else None,
        tuple(args.level) if args.level else None,
        tuple(args.exclude) if args.exclude else None,
        args.known_failures,
    )
    try:
        known = run.known_failures(items, selection, scorer)
    except MalformedFile as e:
        raise CliError(f"--known-failures: {e}") from None
    try:
        plan = run.plan(items, selection, where, scorer, known)
    except (MalformedFile, run.NothingSelected) as e:
        raise CliError(str(e)) from None
    if args.self_check:
        outputs = self_outputs(plan.selected)
    else:
        read = run.read_outputs(args.path, plan.selected, scorer)
        if read.folder_missing:
            each = "every record" if scorer.orbits else "every case"
            print(f'gear-rattle check: error: PATH={args.path!r} not found: {each} scored "no output"', file=sys.stderr)
        for text in read.malformed:
            print(f"gear-rattle check: error: {text}", file=sys.stderr)
        outputs = read.values
    results, times = run.score_items(items, plan, outputs, scorer, args.known_failures)
    source = f"our {args.track} track" if args.self_check else str(args.path)
    return report(args, CheckRun(info, scorer.orbits, source, selection, tuple(results), times))


def report(args: argparse.Namespace, result) -> int:
    """The reports of a run (:class:`golden.scoring.results.CheckRun`): ``--junit-xml``, ``--json`` (its
    JSON document, serialised here), the table, the details of each failure and the summary line (or the
    summary line alone) on stdout; the exit status."""
    from ..cliutil import write_text
    from ..golden.scoring.junit import junit_xml
    from ..golden.scoring.text_report import report_text
    from ..io import json_text

    if args.junit_xml is not None:
        write_text(junit_xml(result), args.junit_xml, "--junit-xml")
    if args.json is not None:
        write_text(json_text(result.as_dict()) + "\n", args.json, "--json")
    if "-" not in (args.json, args.junit_xml):
        to_stdout(report_text(result, summary_only=args.summary))
    return result.exit_status()


def write_output(path: Path, write, *args) -> str:
    """Write one ``--out`` file with ``write(path, *args)`` (one of :mod:`validation.io`'s writers; an OS
    error is a one-line usage error); returns its path."""
    from ..cliutil import write_file

    write_file("--out", path, lambda p: write(p, *args))
    return str(path)
