"""The text layer shared by every file ``gear-rattle check`` reads (docs/reference/golden_formats.md, "What check reads"):
size limits, the encoding, the characters allowed and the line ends.  The CSV and JSON grammars on
top of it are :mod:`.csvformat` and :mod:`.jsonformat`.  Standard library only.

A file is malformed (:class:`MalformedFile`, one line naming the file, line and column) when it is
larger than :data:`MAX_BYTES`, has more than :data:`MAX_LINES` lines, is not UTF-8, or holds a
character outside :data:`FORBIDDEN`'s complement: control characters other than TAB (and LF, or CR
directly before LF, as line ends), DEL and the C1 controls (U+0085 included), the Unicode line and
paragraph separators U+2028/U+2029, and U+FEFF anywhere but as the first character (a byte-order
mark, dropped).  Reading stops at ``MAX_BYTES + 1`` bytes, so a huge file costs no more than that.

**Only regular files are read** (:func:`read_bytes`, the one place a file of a suite, an implementation's
output folder or a ``--from`` file is opened): a named pipe, a device, a socket or a folder at the name is
refused in one line, never waited on (the name is examined with ``stat`` and opened with ``O_NONBLOCK``,
then checked again on the open descriptor); with ``inside`` (the folder the name was built in), a name
whose links lead outside that folder is refused as well.
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path
from typing import BinaryIO

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


def _kind(mode: int) -> str | None:
    """What a file that is not a regular file is (None for a regular file)."""
    for test, what in (
        (stat.S_ISREG, None),
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a named pipe (FIFO)"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return what
    return "not a regular file"


def lies_inside(path: str | Path, folder: str | Path) -> bool:
    """Whether ``path``, its links resolved, lies inside ``folder`` (its links resolved too)."""
    root = os.path.realpath(folder)
    return os.path.commonpath([root, os.path.realpath(path)]) == root


def open_regular(path: str | Path, inside: str | Path | None = None) -> BinaryIO:
    """``path`` opened for reading in binary if it is a **regular file** (module docstring): never waits
    on a pipe or a device.  :class:`MissingFile` when nothing is there; :class:`MalformedFile` (one line)
    for anything else than a regular file, a name whose links lead outside the folder ``inside``, or a
    file that cannot be opened."""
    path = Path(path)
    if inside is not None and not lies_inside(path, inside):
        raise MalformedFile(
            f"{path}: a link to {os.path.realpath(path)!r}, outside {str(inside)!r}: refused (only files "
            "inside the folder are read)"
        )
    try:
        kind = _kind(os.stat(path).st_mode)
        if kind is None:
            fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | getattr(os, "O_CLOEXEC", 0))
            kind = _kind(os.fstat(fd).st_mode)  # the file opened is the one examined (or refused after all)
            if kind is None:
                return os.fdopen(fd, "rb")
            os.close(fd)
    except FileNotFoundError:
        raise MissingFile(f"{path}: missing file") from None
    except OSError as e:
        raise MalformedFile(f"{path}: cannot read: {e.strerror or e}") from None
    raise MalformedFile(f"{path}: {kind}, not a regular file: refused (only regular files are read)")


def read_bytes(path: str | Path, max_bytes: int = MAX_BYTES, inside: str | Path | None = None) -> bytes:
    """At most ``max_bytes + 1`` bytes of the regular file ``path`` (:func:`open_regular`)."""
    with open_regular(path, inside) as fh:
        try:
            return fh.read(max_bytes + 1)
        except OSError as e:
            raise MalformedFile(f"{path}: cannot read: {e.strerror or e}") from None


def read_text(path: str | Path, max_bytes: int = MAX_BYTES, inside: str | Path | None = None) -> str:
    """The file's text, checked against the limits (at most ``max_bytes``) and the character rule; a
    leading byte-order mark is dropped.  Read by :func:`read_bytes` (a regular file, inside the folder
    ``inside`` where given).  :class:`MissingFile` when it does not exist, :class:`MalformedFile`
    otherwise."""
    path = Path(path)
    data = read_bytes(path, max_bytes, inside)
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
