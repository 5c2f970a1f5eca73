"""The scoring and reporting steps of ``gear-rattle check`` that the impact cases (:mod:`.check`) and the
orbit records (:mod:`._check_orbits`) share: the suite's header, which items are selected (the others
skipped, with the reason), the known failures, reading each output file on its own, scoring each
item, the table with the details of each failure, ``--json`` and ``--junit-xml``, and the exit status.
Below both modes, so that neither imports the other's module."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ..cliutil import CliError, to_stdout


def suite_header(args: argparse.Namespace, folder: Path, part: str):
    """The :class:`golden.version.SuiteInfo` of the suite scored (``folder``: its cases or orbits), for the
    header and the reports; with ``--require-suite SPEC`` a one-line error unless its version meets SPEC
    (:func:`golden.version.satisfies`) with its files unmodified."""
    from ..golden.textformat import MalformedFile
    from ..golden.version import satisfies, suite_info

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


@dataclass
class Scorer:
    """What differs between the impact cases and the orbit records: the output files' suffix, how one
    is read (``read(path, item, root)``: a regular file inside the folder ``root``), scored, scored when missing or unreadable, and made a result."""

    orbits: bool
    suffix: str
    read: Callable
    score: Callable
    no_output: Callable
    problem: Callable
    result: Callable


@dataclass
class Ready:
    """A score decided without scoring values: no output, a malformed file, a crash."""

    score: object


def selection(args: argparse.Namespace) -> dict:
    """How the items were selected, for the reports."""
    return {
        "cases": list(args.cases) if args.cases else None,
        "levels": sorted(set(args.level)) if args.level else None,
        "exclude": list(args.exclude) if args.exclude else None,
        "known_failures": args.known_failures,
    }


def skip_reasons(args: argparse.Namespace, items, where, what: str) -> dict:
    """``{id: reason}`` of the items not selected by ``--cases``, ``--level`` and ``--exclude`` (an
    unknown id there is a one-line usage error naming the known ones)."""
    from ..golden.suite import MalformedFile, select_ids

    ids = [i.id for i in items]
    try:
        select_ids(ids, args.cases, where, what)
        select_ids(ids, args.exclude, where, what)
    except MalformedFile as e:
        raise CliError(str(e)) from None
    levels = ",".join(map(str, sorted(set(args.level or []))))
    out = {}
    for item in items:
        level = getattr(item, "level", None)
        if args.cases and item.id not in args.cases:
            out[item.id] = "not selected by --cases"
        elif args.level and level not in args.level:
            out[item.id] = f"level {level}, not selected by --level {levels}"
        elif args.exclude and item.id in args.exclude:
            out[item.id] = "excluded by --exclude"
    return out


def known_failures(args: argparse.Namespace, items, what: str) -> dict:
    """``{id: reason}`` of ``--known-failures FILE`` (empty without it); a malformed file is a one-line
    usage error."""
    if args.known_failures is None:
        return {}
    from ..golden.known_failures import read_known_failures
    from ..golden.suite import MalformedFile

    try:
        return read_known_failures(args.known_failures, [i.id for i in items], what)
    except MalformedFile as e:
        raise CliError(f"--known-failures: {e}") from None


def read_outputs(args: argparse.Namespace, items, scorer: Scorer) -> dict:
    """``{id: output or Ready(score)}``: each file of PATH read on its own.  A missing file is "no
    output"; a malformed one an error of its item alone, named on stderr (one line per file).  A PATH
    that does not exist: every item "no output", one line on stderr."""
    from ..golden.boundary import member
    from ..golden.suite import MalformedFile, MissingFile

    root = Path(args.path)
    out: dict = {}
    if not root.is_dir():
        each = "every record" if scorer.orbits else "every case"
        print(f'gear-rattle check: error: PATH={args.path!r} not found: {each} scored "no output"', file=sys.stderr)
        return {i.id: Ready(scorer.no_output(i, member(root, i.id, scorer.suffix))) for i in items}
    for item in items:
        path = member(root, item.id, scorer.suffix)  # a path built from a validated id, inside PATH
        try:
            out[item.id] = scorer.read(path, item, root)  # a regular file inside PATH, its links resolved
        except MissingFile:
            out[item.id] = Ready(scorer.no_output(item, path))
        except MalformedFile as e:
            text = " ".join(str(e).split())
            text = text if len(text) <= 500 else text[:500] + " ... (cut)"
            print(f"gear-rattle check: error: {text}", file=sys.stderr)
            place = e.path or str(path)
            out[item.id] = Ready(scorer.problem(item, "malformed", text, place, e.line, e.column))
    return out


def check_items(args: argparse.Namespace, info, items, scorer: Scorer, where, self_outputs=None) -> int:
    """Select, read (or, with ``--self``, compute: ``self_outputs(selected)``), score and report every
    item of the suite (``items``, in order; ``where``: the suite folder, for messages)."""
    from ..golden.results import known_failure, skipped_result

    what = "orbit" if scorer.orbits else "case"
    known = known_failures(args, items, what)
    skipped = skip_reasons(args, items, where, what)
    selected = [i for i in items if i.id not in skipped]
    if not selected:
        raise no_selection("orbit suite" if scorer.orbits else "suite", args, where)
    outputs = self_outputs(selected) if args.self_check else read_outputs(args, selected, scorer)
    results, times = [], {}
    for item in items:
        if item.id in skipped:
            results.append(skipped_result(item.id, getattr(item, "level", None), skipped[item.id], scorer.orbits))
            continue
        t0 = time.perf_counter()
        got = outputs[item.id]
        sc = got.score if isinstance(got, Ready) else scorer.score(item, got)
        r = scorer.result(item, sc)
        results.append(known_failure(r, known[item.id], args.known_failures) if item.id in known else r)
        times[item.id] = time.perf_counter() - t0
    return report(args, results, info, orbits=scorer.orbits, times=times)


def report(args: argparse.Namespace, results: list[dict], info, *, orbits: bool, times: dict) -> int:
    """The table, the details of each failure and the summary line (or the summary line alone) on stdout,
    ``--json`` and ``--junit-xml``; the exit status (:func:`golden.results.exit_status`)."""
    from ..cliutil import write_text
    from ..golden.results import document, exit_status, junit_xml
    from ..golden.results_text import details, details_block, summary_line, table
    from ..io import json_text

    source = f"our {args.track} track" if args.self_check else str(args.path)
    doc = document(results, info.as_dict(), orbits=orbits, source=source, selection=selection(args))
    if args.junit_xml is not None:
        write_text(junit_xml(doc, times, details), args.junit_xml, "--junit-xml")
    if args.json is not None:
        write_text(json_text(doc) + "\n", args.json, "--json")
    if "-" not in (args.json, args.junit_xml):
        lines = [summary_line(results, orbits, info.label)]
        if not args.summary:
            blocks = details_block(results)
            lines = [f"suite: {info.line()}", *table(results, orbits), *blocks, *([""] if blocks else []), *lines]
        to_stdout("\n".join(lines) + "\n")
    return exit_status(results)


def no_selection(what: str, args: argparse.Namespace, where) -> CliError:
    """The error when the selection holds nothing."""
    how = " and ".join(
        x
        for x in (
            f"--cases {' '.join(args.cases)}" if args.cases else "",
            f"--level {','.join(map(str, sorted(set(args.level))))}" if args.level else "",
            f"--exclude {' '.join(args.exclude)}" if args.exclude else "",
        )
        if x
    )
    return CliError(
        f"{what} {str(where)!r} has no {'record' if 'orbit' in what else 'case'}"
        + (f" selected by {how}" if how else "")
    )


def write_output(path: Path, write, *args) -> str:
    """Write one ``--out`` file with ``write(path, *args)`` (one of :mod:`validation.io`'s writers; an OS
    error is a one-line usage error); returns its path."""
    from ..cliutil import write_file

    write_file("--out", path, lambda p: write(p, *args))
    return str(path)
