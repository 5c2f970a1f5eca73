"""``gear-rattle check --orbits``: score periodic orbits and bifurcation points against the certified
records of ``validation/golden/orbits`` (docs/reference/golden_formats.md, "Periodic orbits, Floquet multipliers and bifurcation points").

PATH holds one ``<id>.json`` per record (:mod:`validation.golden.formats.orbits` gives the layout);
with ``--self`` our own float64 solvers (``find_periodic``, ``locate``) are scored instead, and
``--out DIR`` keeps their files (an example of the layout).  Selection, known failures, reports and
exit status as for the impact cases (:mod:`._check_common`): 0 every record scored passes, 1 some
fails, has no output or a malformed file (one line per file on stderr), 2 usage error."""

from __future__ import annotations

import argparse
from functools import partial

from ..cliutil import CliError, check_input_path
from ._check_common import check_items, suite_header, write_output


def _self_values(records, write: str | None) -> dict:
    from ..golden.boundary import member
    from ..golden.self_check import float64_values
    from ..io import write_json

    out = {}
    for rec in records:
        d, values = float64_values(rec)
        if write:
            values.path = write_output(member(write, rec.id, ".json"), write_json, d)
        out[rec.id] = values
    return out


def run_orbits(args: argparse.Namespace) -> int:
    """The ``--orbits`` mode of ``check`` (arguments validated by ``check.run`` first)."""
    from ..golden.formats.orbits import MalformedFile, load_records
    from ..golden.paths import DEFAULT_ORBITS
    from ..golden.scoring.run import ORBITS

    if args.self_check and args.track != "map":
        raise CliError("--orbits --self scores the map track's float64 solvers: --track must be map")
    folder = check_input_path(args.suite, "--suite", directory=True) if args.suite is not None else DEFAULT_ORBITS
    info = suite_header(args, folder, "orbits")
    try:
        records = load_records(folder)
    except MalformedFile as e:
        raise CliError(f"orbit suite: {e}") from None
    return check_items(args, info, records, ORBITS, folder, partial(_self_values, write=args.out))
