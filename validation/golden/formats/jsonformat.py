"""The one JSON reader of ``gear-rattle check`` (docs/reference/golden_formats.md, "What check reads"): an
implementation's ``<id>.json``, the orbit records, ``settings.json`` and ``index.json``.  Standard
library only.

JSON (RFC 8259) on the text of :func:`.textformat.read_text`, with these limits: the top level is an
object; no key twice in an object (compared after unescaping); nesting at most :data:`MAX_DEPTH`
arrays and objects deep; a string at most :data:`MAX_STRING` characters; a number literal at most
:data:`MAX_NUMBER` characters, and one whose float64 value overflows is malformed; no ``NaN``,
``Infinity`` or escaped lone surrogates.  Numbers are read as Python ``int`` (no fraction, no
exponent) or as the float64 nearest to the literal.  Every value's position is kept
(:meth:`JsonDoc.error`), so a later check can name the line and column of the value it refuses.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any
from pathlib import Path

from .textformat import MalformedFile, malformed, position, read_text

#: Deepest nesting of arrays and objects.
MAX_DEPTH = 32
#: Longest string, in characters (after unescaping).
MAX_STRING = 10_000
#: Longest number literal, in characters.
MAX_NUMBER = 100
#: Largest JSON file, in bytes (the text layer's own limit is larger).
MAX_JSON_BYTES = 256 * 1024

_WS = re.compile(r"[ \t\n\r]*")
_NUMBER = re.compile(r"-?(?:0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?")
_CHUNK = re.compile(r'[^"\\\x00-\x1f]*')
_ESCAPES = {'"': '"', "\\": "\\", "/": "/", "b": "\b", "f": "\f", "n": "\n", "r": "\r", "t": "\t"}
_HEX4 = re.compile(r"[0-9a-fA-F]{4}")


@dataclass
class JsonDoc:
    """A JSON file read by :func:`read_json`: its value (the top-level object) and the offset of every
    value by its path (a tuple of keys and indices; ``()`` is the top level)."""

    path: str
    text: str
    value: Any
    offsets: dict = field(default_factory=dict)

    def error(self, where: tuple, msg: str) -> MalformedFile:
        """A :class:`MalformedFile` at the value ``where`` (or at its nearest enclosing value)."""
        while where not in self.offsets and where:
            where = where[:-1]
        return malformed(
            self.path, *position(self.text, self.offsets.get(where, 0)), f"{_name(where)}: {msg}" if where else msg
        )


def _name(where: tuple) -> str:
    out = ""
    for k in where:
        out += f"[{k}]" if isinstance(k, int) else (f".{k}" if out else str(k))
    return out


def _match(pattern: re.Pattern[str], text: str, pos: int) -> re.Match[str]:
    """The match at ``pos`` of a pattern that also matches the empty string (``_WS``, ``_CHUNK``):
    there is always one."""
    m = pattern.match(text, pos)
    assert m is not None, "the pattern matches the empty string"
    return m


class _Parser:
    def __init__(self, text: str, path: str):
        self.text, self.path = text, path
        self.offsets: dict[tuple, int] = {}

    def fail(self, pos: int, msg: str) -> MalformedFile:
        return malformed(self.path, *position(self.text, pos), f"invalid JSON: {msg}")

    def ws(self, pos: int) -> int:
        return _match(_WS, self.text, pos).end()

    def value(self, pos: int, where: tuple, depth: int):
        t = self.text
        self.offsets[where] = pos
        c = t[pos : pos + 1]
        if c == "{" or c == "[":
            if depth >= MAX_DEPTH:
                raise self.fail(pos, f"nested deeper than {MAX_DEPTH} arrays and objects (the limit of the format)")
            return self.obj(pos, where, depth + 1) if c == "{" else self.arr(pos, where, depth + 1)
        if c == '"':
            return self.string(pos)
        for word, v in (("true", True), ("false", False), ("null", None)):
            if t.startswith(word, pos):
                return v, pos + len(word)
        m = _NUMBER.match(t, pos)
        if m is None or m.end() == pos:
            for word in ("NaN", "Infinity", "-Infinity", "nan", "inf", "-inf"):
                if t.startswith(word, pos):
                    raise self.fail(pos, f"{word} is not a JSON number (not a finite number)")
            raise self.fail(pos, "expected a value" if c else "unexpected end of file")
        lit = m.group()
        if len(lit) > MAX_NUMBER:
            raise self.fail(pos, f"a number literal longer than {MAX_NUMBER} characters (the limit of the format)")
        if m.group(1) is None and m.group(2) is None:
            return int(lit), m.end()
        x = float(lit)
        if not math.isfinite(x):
            raise self.fail(pos, f"{lit} is beyond the float64 range (not a finite number)")
        return x, m.end()

    def string(self, pos: int):
        t, parts, p = self.text, [], pos + 1
        n = 0
        while True:
            m = _match(_CHUNK, t, p)
            parts.append(m.group())
            n += len(m.group())
            p = m.end()
            c = t[p : p + 1]
            if c == '"':
                break
            if c == "\\":
                e = t[p + 1 : p + 2]
                if e in _ESCAPES:
                    parts.append(_ESCAPES[e])
                    p += 2
                elif e == "u" and _HEX4.fullmatch(t, p + 2, p + 6):
                    u = int(t[p + 2 : p + 6], 16)
                    p += 6
                    if (
                        0xD800 <= u < 0xDC00
                        and t.startswith("\\u", p)
                        and _HEX4.fullmatch(t, p + 2, p + 6)
                        and 0xDC00 <= int(t[p + 2 : p + 6], 16) < 0xE000
                    ):
                        u = 0x10000 + ((u - 0xD800) << 10) + (int(t[p + 2 : p + 6], 16) - 0xDC00)
                        p += 6
                    elif 0xD800 <= u < 0xE000:
                        raise self.fail(p - 6, "an escaped lone surrogate (not a character)")
                    parts.append(chr(u))
                else:
                    raise self.fail(p, "an invalid escape in a string")
                n += 1
            elif c == "":
                raise self.fail(pos, "a string without its closing quote")
            else:
                raise self.fail(p, f"the control character U+{ord(c):04X} inside a string (write it escaped)")
            if n > MAX_STRING:
                raise self.fail(pos, f"a string longer than {MAX_STRING} characters (the limit of the format)")
        s = "".join(parts)
        if len(s) > MAX_STRING:
            raise self.fail(pos, f"a string longer than {MAX_STRING} characters (the limit of the format)")
        return s, p + 1

    def obj(self, pos: int, where: tuple, depth: int):
        out: dict = {}
        keys: dict = {}
        p = self.ws(pos + 1)
        if self.text.startswith("}", p):
            return out, p + 1
        while True:
            if not self.text.startswith('"', p):
                raise self.fail(p, "expected a string key")
            k, q = self.string(p)
            if k in keys:
                raise self.fail(p, f"duplicate key {k!r} (also at line {position(self.text, keys[k])[0]})")
            keys[k] = p
            q = self.ws(q)
            if not self.text.startswith(":", q):
                raise self.fail(q, "expected ':' after a key")
            q = self.ws(q + 1)
            out[k], q = self.value(q, where + (k,), depth)
            q = self.ws(q)
            c = self.text[q : q + 1]
            if c == "}":
                return out, q + 1
            if c != ",":
                raise self.fail(q, "expected ',' or '}' in an object")
            p = self.ws(q + 1)

    def arr(self, pos: int, where: tuple, depth: int):
        out: list = []
        p = self.ws(pos + 1)
        if self.text.startswith("]", p):
            return out, p + 1
        while True:
            v, q = self.value(p, where + (len(out),), depth)
            out.append(v)
            q = self.ws(q)
            c = self.text[q : q + 1]
            if c == "]":
                return out, q + 1
            if c != ",":
                raise self.fail(q, "expected ',' or ']' in an array")
            p = self.ws(q + 1)


def parse_json(text: str, path: str, top: type = dict) -> JsonDoc:
    """Parse JSON text strictly (module docstring); the top level must be an object (``top=list``: an
    array, as a ``--from`` file holds)."""
    p = _Parser(text, path)
    start = p.ws(0)
    if not text.startswith("{" if top is dict else "[", start):
        raise malformed(path, *position(text, start), f"expected a JSON {'object' if top is dict else 'array'}")
    value, end = p.value(start, (), 0)
    end = p.ws(end)
    if end != len(text):
        raise p.fail(end, "text after the JSON object")
    return JsonDoc(path, text, value, p.offsets)


def read_json(path: str | Path, inside: str | Path | None = None, max_bytes: int = MAX_JSON_BYTES) -> JsonDoc:
    """Read a JSON file strictly: :class:`.textformat.MissingFile` if it does not exist,
    :class:`MalformedFile` (one line: file, line, column) if it breaks the format (or is not a regular
    file inside the folder ``inside``, :func:`.textformat.read_bytes`); at most ``max_bytes`` bytes."""
    text = read_text(path, max_bytes, inside)
    return parse_json(text, str(path))
