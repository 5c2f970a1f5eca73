"""The known-failures file of ``gear-rattle check --known-failures FILE`` (docs/reference/golden_commands.md, "Known
failures"): the cases (or orbit records) an implementation is known to fail, each with its reason.

The format, read strictly (:func:`read_known_failures`)::

    # comments and blank lines are skipped
    0004-grazing-impact      our finder samples the flight with a fixed step (issue 12)
    0013-lower-wall-sticking no sticking on the lower wall yet

One entry per line: the id (a case of the suite scored, or with ``--orbits`` a record), blanks (spaces or
tabs), then the reason (required, the rest of the line).  Each id at most once.  The text layer is
that of every file ``check`` reads (:mod:`.textformat`: UTF-8, the characters and limits allowed).
Anything else is a :class:`.textformat.MalformedFile` naming the line and column.  Standard library only.
"""

from __future__ import annotations

import re
from pathlib import Path

from .textformat import MalformedFile, malformed, read_text

_ENTRY = re.compile(r"(?P<id>[^ \t]+)(?:[ \t]+(?P<reason>.*))?")


def read_known_failures(path: str | Path, known: list[str], what: str = "case") -> dict[str, str]:
    """``{id: reason}`` of a known-failures file (module docstring); every id must be one of ``known``
    (``what`` names them in the message).  :class:`MalformedFile` otherwise, :class:`.textformat.MissingFile`
    when there is no such file."""
    text = read_text(path)
    out: dict[str, str] = {}
    first: dict[str, int] = {}
    for k, raw in enumerate(text.split("\n"), start=1):
        line = raw.rstrip("\r")
        body = line.lstrip(" \t")
        if not body or body.startswith("#"):
            continue
        col = len(line) - len(body) + 1
        m = _ENTRY.fullmatch(body.rstrip(" \t"))
        assert m is not None, "a line that is not blank starts with an id"
        cid, reason = m["id"], (m["reason"] or "").strip()
        if cid not in known:
            shown = ", ".join(known[:30]) + (", ..." if len(known) > 30 else "")
            raise malformed(path, k, col, f"unknown {what} id {cid!r} (known: {shown})")
        if cid in out:
            raise malformed(path, k, col, f"{cid!r} is listed twice (also line {first[cid]})")
        if not reason:
            raise malformed(path, k, col + len(cid), f"{cid!r} has no reason: write it after the id, on the same line")
        out[cid], first[cid] = reason, k
    return out


__all__ = ["MalformedFile", "read_known_failures"]
