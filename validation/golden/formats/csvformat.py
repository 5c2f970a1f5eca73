"""The one CSV reader of ``gear-rattle check`` (docs/reference/golden_formats.md, "What check reads"): records and fields
of an impact-sequence file (``expected.csv`` and an implementation's ``<case-id>.csv``), and the
number forms of its fields.  The column meanings are :mod:`.cases`'s.  Standard library only.

Grammar (on the text of :func:`.textformat.read_text`, lines split at LF, a CR before it dropped)::

    line   = field ("," field)*                 a line of spaces and tabs only is blank: skipped
    field  = blanks (quoted | bare) blanks      blanks: spaces and tabs
    bare   = any characters but , and "         (its value: stripped of blanks)
    quoted = '"' (any character but " | '""')* '"'   (its value: the text inside, "" read as ",
                                                  stripped of blanks)

The first line that is not blank is the header; every other line that is not blank is a record with
exactly as many fields as the header.  Column names are not empty and distinct.  A field is at most
:data:`MAX_FIELD` characters (blanks and quotes included), a header at most :data:`MAX_COLUMNS`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

from .textformat import MalformedFile, malformed, read_text

#: Longest field, in characters (blanks and quotes included).
MAX_FIELD = 1000
#: Most columns in a header.
MAX_COLUMNS = 100
#: Most digits of an integer field (``n``, ``wall``).
MAX_INT_DIGITS = 18
_BLANKS = " \t"
#: One field at a position: a quoted field (group 1: its inside) or a bare one (group 2), then a comma or the end.
_FIELD = re.compile(r'[ \t]*(?:"((?:[^"]|"")*)"[ \t]*|([^,"]*))(?=,|\Z)')
_QUOTED = re.compile(r'"(?:[^"]|"")*"')

#: A decimal literal: optional sign, ASCII digits with an optional point, optional exponent.
DECIMAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
#: An integer: optional sign, 1 to 18 ASCII digits, optionally a point and zeros.
INTEGRAL = re.compile(r"[+-]?[0-9]{1,%d}(?:\.0*)?" % MAX_INT_DIGITS)
#: "not a number" where a value may be absent (any case, optional sign, as C's printf writes it).
NAN = re.compile(r"[+-]?nan", re.IGNORECASE)


@dataclass(slots=True)
class Record:
    """One line that is not blank: its 1-based line number, text (without the line end) and field values."""

    line: int
    text: str
    values: list


def _spans(text: str, path, line: int) -> list[tuple[int, int, str]]:
    """``(start, end, value)`` of every field of a line (offsets in ``text``); malformed when a quote
    is misplaced or a field is too long."""
    out, pos = [], 0
    while True:
        m = _FIELD.match(text, pos)
        if m is None:
            p = pos + len(text[pos:]) - len(text[pos:].lstrip(_BLANKS))
            q = _QUOTED.match(text, p) if text.startswith('"', p) else None
            if q is None and text.startswith('"', p):
                raise malformed(path, line, p + 1, "a quoted field without its closing quote")
            if q is not None:
                e = q.end() + len(text[q.end() :]) - len(text[q.end() :].lstrip(_BLANKS))
                raise malformed(path, line, e + 1, "text after the closing quote of a field")
            raise malformed(
                path, line, text.index('"', p) + 1, 'a quote (") inside a field that does not start with one'
            )
        if m.end() - pos > MAX_FIELD:
            raise malformed(
                path, line, pos + 1, f"a field longer than {MAX_FIELD} characters (the limit of the format)"
            )
        inner = m.group(1)
        out.append((pos, m.end(), (inner.replace('""', '"') if inner is not None else m.group(2)).strip(_BLANKS)))
        if m.end() == len(text):
            return out
        pos = m.end() + 1


def split_line(text: str, path, line: int) -> list[str]:
    """The field values of one line (the grammar of the module docstring)."""
    if '"' not in text:
        fields = text.split(",")
        if len(text) > MAX_FIELD:
            pos = 0
            for f in fields:
                if len(f) > MAX_FIELD:
                    raise malformed(
                        path, line, pos + 1, f"a field longer than {MAX_FIELD} characters (the limit of the format)"
                    )
                pos += len(f) + 1
        return [f.strip(_BLANKS) for f in fields]
    return [v for _, _, v in _spans(text, path, line)]


def field_column(rec: Record, k: int, path) -> int:
    """1-based character column where field ``k`` of a record starts (its first character that is not
    a blank; the end of the line for a field beyond the last)."""
    spans = _spans(rec.text, path, rec.line)
    if k >= len(spans):
        return len(rec.text) + 1
    s, e, _ = spans[k]
    return s + (len(rec.text[s:e]) - len(rec.text[s:e].lstrip(_BLANKS))) + 1


@dataclass
class Table:
    """A CSV file read by :func:`read_csv`: the header record and the data records."""

    path: str
    header: Record
    records: list

    def error(self, rec: Record, k: int, msg: str) -> MalformedFile:
        """A :class:`MalformedFile` at field ``k`` of ``rec``."""
        return malformed(self.path, rec.line, field_column(rec, k, self.path), msg)


def text_lines(text: str) -> list[tuple[int, str]]:
    """``(line number, text)`` of every line that is not blank (the line end and a CR before it dropped)."""
    out = []
    for i, raw in enumerate(text.split("\n")):
        t = raw[:-1] if raw.endswith("\r") else raw
        if t.strip(_BLANKS):
            out.append((i + 1, t))
    return out


def read_csv(path: str | Path, inside: str | Path | None = None) -> Table:
    """Read a CSV file strictly (module docstring): :class:`.textformat.MissingFile` if it does not
    exist, :class:`MalformedFile` (one line: file, line, column) if it breaks the format (or is not a
    regular file inside the folder ``inside``, :func:`.textformat.read_bytes`)."""
    text = read_text(path, inside=inside)
    header, records = None, []
    for line, t in text_lines(text):
        i = line - 1
        values = split_line(t, path, i + 1)
        rec = Record(i + 1, t, values)
        if header is None:
            header = rec
            check_header(path, rec)
        elif len(values) != len(header.values):
            raise malformed(
                path,
                i + 1,
                field_column(rec, min(len(values), len(header.values)), path),
                f"{len(values)} fields, expected {len(header.values)} (as many as the header)",
            )
        else:
            records.append(rec)
    if header is None:
        raise malformed(path, 1, 1, "empty file (no header line)")
    return Table(str(path), header, records)


def check_header(path, rec: Record) -> None:
    """The header's rules (module docstring): at most :data:`MAX_COLUMNS` names, none empty, none twice."""
    names = rec.values
    if len(names) > MAX_COLUMNS:
        raise malformed(
            path,
            rec.line,
            field_column(rec, MAX_COLUMNS, path),
            f"more than {MAX_COLUMNS} columns (the limit of the format)",
        )
    seen: dict[str, int] = {}
    for k, name in enumerate(names):
        if not name:
            raise malformed(path, rec.line, field_column(rec, k, path), f"column {k + 1} has an empty name")
        if name in seen:
            raise malformed(
                path,
                rec.line,
                field_column(rec, k, path),
                f"duplicate column name {name!r} (also column {seen[name] + 1})",
            )
        seen[name] = k


# ------------------------------------------------------------------------------------------------
# field forms


def decimal_value(value: str) -> float:
    """The float64 nearest to a decimal literal (:data:`DECIMAL`); ValueError names the problem."""
    if not DECIMAL.fullmatch(value):
        raise ValueError("is not a number (allowed: a decimal literal such as -1.25e-3)")
    v = float(value)
    if not math.isfinite(v):
        raise ValueError("is not finite (beyond the float64 range)")
    return v


def integer_value(value: str) -> int:
    """The integer of an integral field (:data:`INTEGRAL`); ValueError names the problem."""
    if not INTEGRAL.fullmatch(value):
        raise ValueError(
            f"is not an integer (allowed: up to {MAX_INT_DIGITS} digits with an optional sign, "
            "optionally followed by '.' and zeros)"
        )
    return int(value.split(".")[0])


def is_absent(value: str) -> bool:
    """An empty field or ``nan`` (any case, optional sign): no value."""
    return value == "" or NAN.fullmatch(value) is not None
