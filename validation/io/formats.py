"""The package's file formats, one writer each: strict JSON, CSV and NPZ (and figures, saved without
pyplot).

* **JSON** (:func:`json_text`, :func:`write_json`): strict -- a non-finite float (NaN, +-inf) is
  written as ``null`` and :func:`json.dumps` runs with ``allow_nan=False``, so every file parses
  with a parser that rejects ``NaN`` (RFC 8259).  numpy scalars and arrays become numbers and lists,
  tuples lists, mapping keys strings; an object that is not data raises ``TypeError`` (a result
  states what it writes, e.g. its ``summary()``).
* **CSV** (:func:`csv_text`, :func:`write_csv`): a header line and one line per row, nothing else
  (no comment or prose lines); floats as the shortest decimal that reads back to the same float64
  (``repr``), integers as integers, a missing value (``None``) as an empty field.
* **NPZ** (:func:`write_npz`): :func:`numpy.savez_compressed` into exactly the path given (numpy
  appends ``.npz`` to a file name without it; this writer does not).

Every writer writes through :func:`.atomic.write_atomic`: beside the target, flushed, renamed into
place (a kill leaves the earlier file or the new one, whole).

Analyses never write files: they return typed results, and the commands and the report write them
with these functions (docs/architecture.md).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np

from .atomic import write_atomic, write_text_atomic
from .jsontext import json_text


def write_json(path, obj, indent: int | None = 1, ensure_ascii: bool = True) -> Path:
    """Write :func:`json_text` of ``obj`` (and a final newline) to ``path`` (UTF-8); returns the path."""
    return write_text_atomic(path, json_text(obj, indent, ensure_ascii) + "\n")


def _cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "True" if v else "False"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    if isinstance(v, str):
        if any(c in v for c in ',"\n\r'):
            return '"' + v.replace('"', '""') + '"'
        return v
    raise TypeError(f"{type(v).__name__} is not a CSV value")


def csv_text(header: Sequence[str], rows: Iterable[Sequence]) -> str:
    """CSV text: the ``header`` line and one line per row of ``rows`` (see the module docstring)."""
    header = list(header)
    lines = [",".join(_cell(h) for h in header)]
    for i, row in enumerate(rows):
        row = list(row)
        if len(row) != len(header):
            raise ValueError(f"CSV row {i} has {len(row)} fields: allowed {len(header)} (the header's)")
        lines.append(",".join(_cell(v) for v in row))
    return "\n".join(lines) + "\n"


def csv_columns(columns: Mapping[str, Sequence]) -> tuple[list[str], Iterable[tuple]]:
    """``(header, rows)`` of equally long named columns, for :func:`csv_text`."""
    cols = {k: list(v) for k, v in columns.items()}
    lengths = {len(v) for v in cols.values()}
    if len(lengths) > 1:
        raise ValueError(f"CSV columns have different lengths {sorted(lengths)}: allowed one length")
    return list(cols), zip(*cols.values())


def write_csv(path, header: Sequence[str], rows: Iterable[Sequence]) -> Path:
    """Write :func:`csv_text` to ``path``; returns the path."""
    return write_text_atomic(path, csv_text(header, rows))


def write_npz(path, **arrays) -> Path:
    """:func:`numpy.savez_compressed` of ``arrays`` into exactly ``path``; returns the path."""
    return write_atomic(path, lambda fh: np.savez_compressed(fh, **arrays))


#: Resolution of every figure written (the report's and the commands' alike), dots per inch: 150 keeps the
#: densest figures (the velocity series of Figs. 5-7, the diagrams of Figs. 4 and 8) legible.
FIGURE_DPI = 150


def save_figure(fig, path) -> Path:
    """``fig.savefig(path)`` at :data:`FIGURE_DPI` (format from the extension), atomically: the one
    writer of a figure.  Returns the path."""
    fmt = Path(path).suffix[1:].lower() or None
    return write_atomic(path, lambda fh: fig.savefig(fh, format=fmt, dpi=FIGURE_DPI))


__all__ = [
    "write_json",
    "csv_text",
    "csv_columns",
    "write_csv",
    "write_npz",
    "FIGURE_DPI",
    "save_figure",
]
