"""Strict JSON text (RFC 8259): :func:`json_text` writes it, :func:`read_json` reads it back.

A non-finite float (NaN, +-inf) is written as ``null`` and :func:`json.dumps` runs with
``allow_nan=False``; numpy scalars and arrays become numbers and lists, tuples lists, mapping keys
strings; an object that is not data raises ``TypeError``.  Below both the writers of
:mod:`.formats` and the atomic writer's manifest (:mod:`.atomic`), which use it.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np


def jsonable(x):
    """``x`` as plain JSON data: numpy scalars/arrays as Python numbers/lists, tuples as lists, keys as
    strings, non-finite floats as ``None``.  ``TypeError`` for an object that is not data."""
    if isinstance(x, Mapping):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, (np.bool_, np.integer, np.floating)):
        return jsonable(x.item())
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if x is None or isinstance(x, (bool, int, str)):
        return x
    if isinstance(x, complex):
        raise TypeError("a complex number is not JSON data: write its real and imaginary parts")
    raise TypeError(f"{type(x).__name__} is not JSON data")


def json_text(obj, indent: int | None = 1, ensure_ascii: bool = True) -> str:
    """Strict JSON text of ``obj`` (see the module docstring); ``ensure_ascii=False`` keeps non-ASCII
    characters as they are (the file is UTF-8)."""
    return json.dumps(jsonable(obj), indent=indent, allow_nan=False, ensure_ascii=ensure_ascii)


def read_json(path):
    """The data of a JSON file written by :func:`.formats.write_json`: strict (a bare ``NaN`` or ``Infinity`` is
    refused with ``ValueError``); ``null`` stays ``None`` -- the reader of a numeric field turns it
    back into NaN where NaN is what was written (:func:`nan_from_null`)."""

    def refuse(name):
        raise ValueError(f"{str(path)!r}: {name} is not JSON (RFC 8259): allowed numbers and null")

    return json.loads(Path(path).read_text(encoding="utf-8"), parse_constant=refuse)


def nan_from_null(x):
    """A numeric value read from strict JSON: ``None`` (a NaN or infinity written as ``null``) as NaN."""
    return math.nan if x is None else x


__all__ = [
    "jsonable",
    "json_text",
    "read_json",
    "nan_from_null",
]
