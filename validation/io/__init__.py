"""Output files: one writer per format (:mod:`.formats`: strict JSON, CSV, NPZ, figures; :mod:`.jsontext`: the JSON text) and the file
layouts of the analyses' results (:mod:`.transients`: Figs. 9-11; :mod:`.crises`: r2, r1, alpha1).

The I/O layer sits above the analyses (which return typed results and never write) and below the
report and the commands (which compose: compute -> write -> plot); docs/architecture.md.
"""

from .formats import csv_columns, csv_text, save_figure, write_csv, write_json, write_npz
from .jsontext import json_text, jsonable, nan_from_null, read_json

__all__ = [
    "csv_columns",
    "csv_text",
    "json_text",
    "jsonable",
    "nan_from_null",
    "read_json",
    "save_figure",
    "write_csv",
    "write_json",
    "write_npz",
]
