"""The suite within reach of any implementation (docs/reference/golden_commands.md, "In CI"): where the
installed suite's folders are, as data (``gear-rattle check --suite-version --json FILE``), and the
files of a copy of it with its format description (``gear-rattle check --export-suite DIR``), for an
implementation that cannot import Python.

The description (:func:`describe`) names, per part (``cases``, ``orbits``), its folder, its index,
its digest and whether it is the recorded version's, and its ids (the cases by level); and the format
description ``FORMAT.md`` (the sections of docs/golden.md an implementation needs: the file formats,
the model's conventions, the orbit records' and values' layouts; shipped with the package,
.ci/golden_format.py writes it).  An export (:func:`export_files`) holds ``cases/`` (with its
``index.json``), ``orbits/``, ``FORMAT.md`` and ``suite.json`` (the description, folders relative to
the export): byte for byte the installed files, so that its digests are the recorded ones.  Standard
library only; the writing is the command's (validation/io's atomic writer).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..paths import GOLDEN
from .jsonformat import read_json
from .version import INDEX_NAME, SuiteInfo, combined_digest, recorded, suite_files

#: The description's format name.
FORMAT = "gear-rattle golden suite description, version 1"
#: The format description shipped with the suite (an extract of docs/golden.md).
FORMAT_DOC = GOLDEN / "FORMAT.md"
#: The description's name in an export.
DESCRIPTION = "suite.json"
#: What an implementation writes for each part (docs/golden.md).
OUTPUTS = {
    "cases": "<case-id>.csv per case: header n,tau,tau_mod_2pi,wall,sdot,kind, one row per event",
    "orbits": "<id>.json per record: points, multipliers (periodic orbits), value (bifurcation points)",
}


def _levels(folder: Path, ids: list[str]) -> dict[str, list[str]]:
    """``{level: [ids]}`` of a case folder (each case's ``settings.json``; cases without a level under
    ``"none"``)."""
    out: dict[str, list[str]] = {}
    for cid in ids:
        level = read_json(folder / cid / "settings.json").value.get("level")
        out.setdefault(str(level) if level is not None else "none", []).append(cid)
    return dict(sorted(out.items()))


def part_entry(info: SuiteInfo, ids: list[str]) -> dict:
    """One part of the description: its folder, index, digests, ids and (cases) ids by level."""
    index = info.folder / INDEX_NAME if info.part == "cases" else info.folder.parent / "cases" / INDEX_NAME
    out: dict[str, Any] = {
        "folder": str(info.folder),
        "index": str(index) if index.is_file() else None,
        "version": info.version,
        "label": info.label,
        "digest": info.digest,
        "recorded_digest": info.recorded_digest,
        "digest_matches": info.matches,
        "outputs": OUTPUTS[info.part],
        "ids": ids,
    }
    if info.part == "cases":
        out["levels"] = _levels(info.folder, ids)
    return out


def describe(parts: dict[str, tuple[SuiteInfo, list[str]]]) -> dict:
    """The description of the suite's parts (``{part: (SuiteInfo, ids)}``): name, version, label, the
    suite's digest (where both parts are described), whether every part is its recorded version, the
    parts (:func:`part_entry`) and the format description's path (None where it is not there)."""
    infos = [info for info, _ in parts.values()]
    both = "cases" in parts and "orbits" in parts
    return {
        "format": FORMAT,
        "name": infos[0].name,
        "version": infos[0].version,
        "label": infos[0].label,
        "digest": combined_digest(parts["cases"][0].digest, parts["orbits"][0].digest) if both else None,
        "recorded_digest": recorded(parts["cases"][0].folder / INDEX_NAME).get("digest") if both else None,
        "digest_matches": all(i.matches for i in infos),
        **{part: part_entry(info, ids) for part, (info, ids) in parts.items()},
        "format_description": str(FORMAT_DOC) if FORMAT_DOC.is_file() else None,
    }


def exported(doc: dict) -> dict:
    """The description of an export (:func:`export_files`' layout): the same, its paths relative to the
    export's folder."""
    out = dict(doc)
    for part in ("cases", "orbits"):
        if part in out:
            out[part] = dict(out[part], folder=part, index=f"cases/{INDEX_NAME}" if out[part]["index"] else None)
    out["format_description"] = FORMAT_DOC.name if doc["format_description"] else None
    return out


def export_files(cases: Path, orbits: Path) -> list[tuple[str, Path]]:
    """``(relative path in the export, source file)`` of every file an export copies: the case folders'
    files and ``cases/index.json``, the records, and ``FORMAT.md``."""
    out = [(f"cases/{rel}", cases / rel) for rel in suite_files(cases)]
    if (cases / INDEX_NAME).is_file():
        out.append((f"cases/{INDEX_NAME}", cases / INDEX_NAME))
    out += [(f"orbits/{rel}", orbits / rel) for rel in suite_files(orbits)]
    if FORMAT_DOC.is_file():
        out.append((FORMAT_DOC.name, FORMAT_DOC))
    return out
