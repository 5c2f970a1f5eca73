"""The scoring and reporting steps of ``gear-rattle check`` that the impact cases (:mod:`.check`) and the
orbit records (:mod:`._check_orbits`) share: the suite's header, reading the output files, scoring each
item, the table, ``--json`` and ``--junit-xml``, and the exit status.  Below both modes, so that neither
imports the other's module."""

from __future__ import annotations

import argparse
import sys
import time
from functools import partial
from pathlib import Path

from ..cliutil import CliError, to_stdout


def suite_header(args: argparse.Namespace, folder: Path, part: str):
    """The :class:`golden.version.SuiteInfo` of the suite scored (``folder``: its cases or orbits), for the
    header and the reports; with ``--require-suite VERSION`` a one-line error unless it is that version
    with its files unmodified."""
    from ..golden.textformat import MalformedFile
    from ..golden.version import suite_info

    try:
        info = suite_info(folder, part)
    except OSError as e:
        raise CliError(f"--suite: cannot read {str(folder)!r}: {e.strerror or e}") from None
    except MalformedFile as e:
        raise CliError(f"suite: {e}") from None
    if args.require_suite is not None and not (info.version == args.require_suite and info.matches):
        raise CliError(
            f"--require-suite {args.require_suite}: the suite is {info.label} "
            f"({info.part} {info.folder}, {info.digest})"
        )
    return info


def report(
    args: argparse.Namespace, results: list[dict], info, *, orbits: bool, times: dict, table_to_stdout: bool = True
) -> int:
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


def no_selection(what: str, args: argparse.Namespace, where) -> CliError:
    """The error when the selection holds nothing."""
    how = " and ".join(
        x
        for x in (
            f"--cases {' '.join(args.cases)}" if args.cases else "",
            f"--level {','.join(map(str, sorted(set(args.level))))}" if args.level else "",
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


def score_and_report(
    args: argparse.Namespace,
    items,
    outputs: dict,
    info,
    *,
    orbits: bool,
    root: Path | None,
    suffix: str,
    score,
    no_output,
    result,
) -> int:
    """Score each case or orbit record (``items``) on its output (``outputs[id]``; None: the file
    ``root/<id><suffix>`` is missing, a failing "no output"), timing each, and :func:`report` the results
    (``result(item, score)``: :func:`golden.results.case_result` or ``orbit_result``)."""
    from ..golden.boundary import member
    from ..golden.suite import MalformedFile

    results, times = [], {}
    for item in items:
        t0 = time.perf_counter()
        got = outputs[item.id]
        try:
            if got is None:
                assert root is not None, "an output is missing only where it is read from root (not with --self)"
                sc = no_output(item, member(root, item.id, suffix))
            else:
                sc = score(item, got)
        except MalformedFile as e:
            raise CliError(str(e)) from None
        results.append(result(item, sc))
        times[item.id] = time.perf_counter() - t0
    return report(args, results, info, orbits=orbits, times=times)


def read_output_folder(path: str, items, suffix: str, read) -> tuple[Path, dict, dict]:
    """``(root, outputs, problems)`` of the implementation's folder ``PATH``: each item's file
    ``<id><suffix>``, its path built from the validated id (:func:`golden.boundary.member`), read by
    ``read(file, item, root)`` as a regular file inside the folder (:func:`read_outputs`)."""
    from ..cliutil import check_input_path
    from ..golden.boundary import member
    from ..golden.suite import MalformedFile, MissingFile

    root = check_input_path(path, "PATH", directory=True)
    reads = {item.id: partial(read, member(root, item.id, suffix), item, root) for item in items}
    outputs, errors = read_outputs(reads, MalformedFile, MissingFile)
    return root, outputs, errors


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
