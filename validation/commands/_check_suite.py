"""``gear-rattle check --suite-version`` and ``--export-suite DIR``: the suite itself, not an
implementation's output (docs/reference/golden_commands.md, "In CI").  The description and the files
exported are :mod:`validation.golden.formats.export`'s; the files are written by the atomic writer."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..cliutil import CliError, check_input_path, to_stdout


def _parts(args: argparse.Namespace) -> dict:
    """``{part: folder}`` described: the installed suite's two parts, or ``--suite DIR`` (a records
    folder with ``--orbits``)."""
    from ..golden.formats.version import PARTS

    if args.suite is None:
        return dict(PARTS)
    return {"orbits" if args.orbits else "cases": check_input_path(args.suite, "--suite", directory=True)}


def _ids(part: str, folder: Path) -> list[str]:
    from ..golden.formats.orbits import record_ids
    from ..golden.formats.textformat import MalformedFile
    from ..golden.formats.cases import case_ids

    try:
        return record_ids(folder) if part == "orbits" else case_ids(folder)
    except MalformedFile as e:
        raise CliError(f"--suite: {e}") from None


def suite_version(args: argparse.Namespace, header) -> int:
    """``--suite-version``: the version and digests of the suite (or of ``--suite DIR``), as lines or,
    with ``--json FILE``, as the description of :func:`golden.formats.export.describe` (folders, index, ids);
    exit 1 where the files differ from the recorded version's."""
    from ..cliutil import write_text
    from ..golden.formats.export import describe
    from ..golden.formats.version import recorded
    from ..io import json_text

    infos = {part: header(args, folder, part) for part, folder in _parts(args).items()}
    if args.json is not None:
        doc = describe({part: (info, _ids(part, info.folder)) for part, info in infos.items()})
        write_text(json_text(doc) + "\n", args.json, "--json")
    if args.json != "-":
        lines = [info.line() for info in infos.values()]
        if args.suite is None:
            lines.append(f"suite digest {recorded().get('digest')}")
        to_stdout("\n".join(lines) + "\n")
    return 0 if all(i.matches for i in infos.values()) else 1


def export_suite(args: argparse.Namespace, header) -> int:
    """``--export-suite DIR``: the suite's files, its format description and ``suite.json`` (the
    description, folders relative to DIR) written into DIR, a new or empty directory; one line on stdout."""
    from ..cliutil import check_output_dir, write_file
    from ..golden.formats.export import DESCRIPTION, describe, export_files, exported
    from ..io import json_text
    from ..io.atomic import write_atomic

    dest = Path(args.export_suite)
    check_output_dir(args.export_suite, "--export-suite")
    if dest.is_dir() and any(dest.iterdir()):
        raise CliError(f"--export-suite={args.export_suite!r} is not empty: allowed a new or empty directory")
    if args.suite is not None or args.path is not None or args.self_check:
        raise CliError("--export-suite exports the installed suite and exits: no PATH, --self or --suite with it")
    parts = _parts(args)
    infos = {part: header(args, folder, part) for part, folder in parts.items()}
    files = export_files(parts["cases"], parts["orbits"])
    for rel, source in files:
        data = source.read_bytes()
        write_file("--export-suite", dest / rel, lambda p, d=data: write_atomic(p, d))
    doc = exported(describe({part: (info, _ids(part, info.folder)) for part, info in infos.items()}))
    write_file("--export-suite", dest / DESCRIPTION, lambda p: write_atomic(p, (json_text(doc) + "\n").encode()))
    first = next(iter(infos.values()))
    to_stdout(f"exported {first.name} {first.label} ({len(files) + 1} files) to {dest}\n")
    return 0 if all(i.matches for i in infos.values()) else 1
