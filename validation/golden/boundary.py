"""What is checked where a suite, a ``--from`` file or an implementation's output folder comes in
(docs/reference/golden_formats.md, "What check reads": ids, tolerances, sizes).  Standard library only.

A suite travels: ``case`` builds one, ``fuzz`` writes one, a project keeps one and shares it.  So
nothing in it is trusted as a path or a bound:

* **Ids** (:func:`check_id`, :data:`ID_PATTERN`): a case or record id names a folder or a file
  (``SUITE/<id>/``, ``OUT/<id>.csv``, ``ORBITS/<id>.json``), so it is 1-100 ASCII letters, digits,
  ``.``, ``_`` and ``-``, starting with a letter, a digit or ``_`` and not ending with ``.`` (no
  separator, no dot-name, nothing unprintable), and not a name of the suite's own files
  (:func:`reserved`: ``index``, ``index.json``, ``*.manifest``, ``*.manifest.json``, ``*.lock``, any
  case) or a device name Windows reserves.  The same rule serves ``case``, ``check`` (a suite's
  folders and ``settings.json`` ids), ``check --self --out``, ``check --orbits`` and the index.
* **Tolerances** (:func:`check_tolerance`): a number ``0 <= t <`` :data:`MAX_TOLERANCE`.
* **Counts**: at most :data:`MAX_CASES` cases (or records) in a suite.
* **Values in messages** (:func:`shown`): ``ascii()`` of the value, cut, so that no escape code of a
  hostile file reaches the terminal raw.

Files themselves are read by :func:`.textformat.read_bytes` (regular files only, inside their folder).
"""

from __future__ import annotations

import math
import re

#: A case or record id (module docstring); the reserved names are refused beside it (:func:`reserved`).
ID_PATTERN = re.compile(r"[A-Za-z0-9_](?:[A-Za-z0-9._-]{0,98}[A-Za-z0-9_-])?")
#: The rule of :data:`ID_PATTERN` and :func:`reserved` in words (for messages and the docs).
ID_RULE = (
    "1-100 ASCII letters, digits, '.', '_' or '-', starting with a letter, a digit or '_', not ending "
    "with '.', and not a name of the suite's own files (index, index.json, *.manifest, *.manifest.json, "
    "*.lock; any case) or a device name Windows reserves (CON, PRN, AUX, NUL, COM1-9, LPT1-9)"
)
#: Names of the suite's own files and bookkeeping that an id must not take (compared in lower case).
RESERVED_NAMES = frozenset({"index", "index.json"})
RESERVED_SUFFIXES = (".manifest", ".manifest.json", ".lock")
#: Device names Windows reserves, with or without an extension (``CON``, ``con.csv``).
WINDOWS_DEVICES = frozenset(
    {"con", "prn", "aux", "nul", *(f"com{i}" for i in range(1, 10)), *(f"lpt{i}" for i in range(1, 10))}
)
#: The largest tolerance a suite may hold (exclusive), absolute or relative: above the loosest
#: tolerance any shipped suite has had (3e-6, the grazes of 1.0.0) and every tolerance ``case`` gives
#: (below 1e-6, the horizon rule), and far below the values a case holds: an impact time or velocity off
#: by 1e-4 is a wrong answer in every case.  A suite with 1e308 (which passes anything) is refused.
MAX_TOLERANCE = 1e-4
#: Most cases (or orbit records) in one suite folder: its ``index.json`` (~400 bytes a case) then stays well
#: within the 2 MiB a suite's index may have.
MAX_CASES = 2000
#: Most impacts a case may ask for (``case --impacts``; a suite's ``n_impacts``, which ``check --self`` runs).
MAX_CASE_IMPACTS = 100_000
#: Characters of a value shown in a message.
SHOWN_CHARS = 60


def shown(value) -> str:
    """``ascii(value)``, cut to :data:`SHOWN_CHARS` characters: a value from a file, safe on a terminal."""
    text = ascii(value)
    return text if len(text) <= SHOWN_CHARS else text[: SHOWN_CHARS - 3] + "..."


def printable(value) -> str:
    """``value`` as text for a message or a table: itself where it is a printable string of at most
    :data:`SHOWN_CHARS` characters, else :func:`shown` (a suite's name from its ``index.json`` may hold
    ``\u001b``, which JSON unescapes into an escape code)."""
    return value if isinstance(value, str) and value.isprintable() and len(value) <= SHOWN_CHARS else shown(value)


def reserved(name: str) -> bool:
    """Whether ``name`` is a name of the suite's own files or a Windows device name (module docstring)."""
    low = name.lower()
    return low in RESERVED_NAMES or low.endswith(RESERVED_SUFFIXES) or low.split(".")[0] in WINDOWS_DEVICES


def check_id(value, what: str = "id") -> str:
    """``value`` if it is an id (module docstring), else ``ValueError`` naming ``what`` and the rule."""
    if not isinstance(value, str) or not ID_PATTERN.fullmatch(value):
        raise ValueError(f"{what}={shown(value)} is out of range: allowed {ID_RULE}")
    if reserved(value):
        raise ValueError(f"{what}={shown(value)} is a reserved name: allowed {ID_RULE}")
    return value


def check_tolerance(value, what: str = "tolerance") -> float:
    """A tolerance (absolute or relative) as a float: a number, not a bool, ``0 <= value <``
    :data:`MAX_TOLERANCE`; else ``ValueError`` naming ``what`` and the range.  Every tolerance read from
    a suite goes through here (a case's ``tolerances``, an orbit record's, per-row tolerances)."""
    ok = isinstance(value, (int, float)) and not isinstance(value, bool)
    if ok:  # (an int is compared as it is: float() of a 400-digit one overflows)
        ok = (
            (0 <= value < MAX_TOLERANCE)
            if isinstance(value, int)
            else (math.isfinite(value) and 0.0 <= value < MAX_TOLERANCE)
        )
    if not ok:
        raise ValueError(f"{what}={shown(value)} is out of range: allowed a number 0 <= {what} < {MAX_TOLERANCE:g}")
    return float(value)


def member(folder, cid: str, suffix: str = ""):
    """The path ``folder/<cid><suffix>`` of a validated id (:func:`check_id`: ``ValueError`` otherwise),
    checked to lie directly inside ``folder`` (links are the reader's business:
    :func:`.textformat.read_bytes` with ``inside=folder``)."""
    from pathlib import Path

    name = check_id(cid) + suffix
    path = Path(folder) / name
    if path.parent != Path(folder) or path.name != name:  # (cannot happen for an id: no separator, no dot-name)
        raise ValueError(f"{shown(name)} does not name a file inside {shown(str(folder))}")
    return path
