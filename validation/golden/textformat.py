"""The text layer shared by every file ``gear-rattle check`` reads (docs/golden.md, "What check reads"):
size limits, the encoding, the characters allowed and the line ends.  The CSV and JSON grammars on
top of it are :mod:`.csvformat` and :mod:`.jsonformat`.  Standard library only.

A file is malformed (:class:`MalformedFile`, one line naming the file, line and column) when it is
larger than :data:`MAX_BYTES`, has more than :data:`MAX_LINES` lines, is not UTF-8, or holds a
character outside :data:`FORBIDDEN`'s complement: control characters other than TAB (and LF, or CR
directly before LF, as line ends), DEL and the C1 controls (U+0085 included), the Unicode line and
paragraph separators U+2028/U+2029, and U+FEFF anywhere but as the first character (a byte-order
mark, dropped).  Reading stops at ``MAX_BYTES + 1`` bytes, so a huge file costs no more than that.
"""

from __future__ import annotations

import re
from pathlib import Path

#: Largest file read, in bytes (2 MiB): a case has tens of rows (about 100 bytes each).
MAX_BYTES = 2 * 1024 * 1024
#: Most lines in a file (blank lines included).
MAX_LINES = 20_000
#: Characters no file may hold (LF is the line end; CR is allowed only directly before LF).
FORBIDDEN = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\u2028\u2029\ufeff]|\r(?!\n)")


class MalformedFile(Exception):
    """An input file cannot be read as the documented layout (one-line message naming file and line).
    Where the problem has a place (:func:`malformed`), ``path``, ``line`` and ``column`` hold it (1-based),
    and ``reason`` the message without the place, so that reports need not parse the message."""

    path: str | None = None
    line: int | None = None
    column: int | None = None
    reason: str | None = None


class MissingFile(MalformedFile):
    """The file does not exist (``check`` scores a missing output as a failing case, "no output")."""


def malformed(path, line: int, column: int, msg: str) -> MalformedFile:
    """The one-line error ``PATH: line L, column C: msg`` (its parts as attributes too)."""
    e = MalformedFile(f"{path}: line {line}, column {column}: {msg}")
    e.path, e.line, e.column, e.reason = str(path), line, column, msg
    return e


def position(text: str, offset: int) -> tuple[int, int]:
    """1-based ``(line, column)`` of a character offset (columns count characters)."""
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


def _describe(ch: str) -> str:
    if ch == "\r":
        return "a carriage return not followed by a line feed (line ends are LF or CRLF)"
    if ch == "\ufeff":
        return "U+FEFF (a byte-order mark is allowed only at the start of the file)"
    return f"the character U+{ord(ch):04X}, which the format does not allow (control or line-separator character)"


def read_text(path: str | Path, max_bytes: int = MAX_BYTES) -> str:
    """The file's text, checked against the limits (at most ``max_bytes``) and the character rule; a
    leading byte-order mark is dropped.  :class:`MissingFile` when it does not exist,
    :class:`MalformedFile` otherwise."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read(max_bytes + 1)
    except FileNotFoundError:
        raise MissingFile(f"{path}: missing file") from None
    except OSError as e:
        raise MalformedFile(f"{path}: cannot read: {e.strerror or e}") from None
    if len(data) > max_bytes:
        head = data[:max_bytes]
        raise malformed(
            path,
            head.count(b"\n") + 1,
            max_bytes - head.rfind(b"\n"),
            f"file larger than {max_bytes} bytes (the limit of the format)",
        )
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        raise malformed(
            path, line, e.start - data.rfind(b"\n", 0, e.start), f"not UTF-8 (byte 0x{data[e.start]:02x})"
        ) from None
    if text.startswith("\ufeff"):
        text = text[1:]
    lines = text.count("\n") + (not text.endswith("\n"))
    if lines > MAX_LINES:
        raise malformed(path, MAX_LINES + 1, 1, f"more than {MAX_LINES} lines (the limit of the format)")
    bad = FORBIDDEN.search(text)
    if bad:
        raise malformed(path, *position(text, bad.start()), _describe(bad.group()[0]))
    return text
