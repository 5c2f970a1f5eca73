"""The golden suite's version and content digest (docs/reference/golden_formats.md, "Versions of the suite").

The suite -- the case folders of ``cases/`` and the records of ``orbits/`` -- has a semantic version,
:data:`SUITE_VERSION`, and a content digest; ``cases/index.json`` records both (its ``suite`` block,
written by :func:`.index.build_index`), ``gear-rattle check`` prints them in its header, its JSON
and JUnit reports, and ``gear-rattle check --suite-version`` / ``gear-rattle --version``.

**The digest of a folder** (:func:`folder_digest`): SHA-256 over its suite files -- every file
``*.json`` or ``*.csv`` at depth 1 or 2 except the top-level ``index.json`` (which records the
digest), i.e. ``<case-id>/settings.json``, ``expected.csv``, ``provenance.json`` and ``<id>.json``
-- in the order of their relative paths (``/``-separated, compared as UTF-8 bytes); each file adds
its relative path in UTF-8, a NUL byte, its size in bytes as decimal ASCII, a NUL byte, then its
bytes.  **The suite's digest** is the SHA-256 of ``cases:<hex>\\norbits:<hex>\\n`` (the two folders'
hex digests).  Digests are written ``sha256:<64 hex digits>``.

**The version** changes with every change of a suite file: MAJOR when an output that passed the
previous version can fail this one (an expected value or row count changed, a tolerance tightened,
a case or record removed), MINOR when cases or records are added or tolerances loosened (what passed
still passes), PATCH when only provenance or notes changed (every verdict the same).  A test
(tests/test_check_ci.py) fails when the files change without the digest in ``index.json``, the version
and the changelog (docs/record/golden_changelog.md) changing with them.  Only the standard library is used here.
"""

from __future__ import annotations

import hashlib
import os
import re
from dataclasses import dataclass
from pathlib import Path

from ..boundary import printable
from ..paths import DEFAULT_ORBITS, DEFAULT_SUITE
from .jsonformat import read_json
from .textformat import MAX_BYTES, MalformedFile, open_regular

#: The suite's semantic version: raise it, and add its changelog entry to docs/record/golden_changelog.md (docs/reference/golden_formats.md, "Versions
#: of the suite"), whenever a file of ``cases/`` or ``orbits/`` changes; then regenerate
#: ``cases/index.json`` (``python -m gear_rattle.validation.golden.generate`` or :func:`.index.write_index`).
SUITE_VERSION = "2.0.0"
#: The suite's name in reports.
SUITE_NAME = "gear-rattle golden suite"
#: The folders of the suite (beside each other in the package: ``validation/golden/``).
PARTS = {"cases": DEFAULT_SUITE, "orbits": DEFAULT_ORBITS}
#: The index file: not part of the digest (it records it).
INDEX_NAME = "index.json"
SUFFIXES = (".json", ".csv")
#: The largest suite file digested (a case's provenance.json grows with its impacts: ~0.2 MB per 1000).
MAX_FILE_BYTES = 64 * 1024 * 1024


#: A command's record of the files it wrote into a folder (``<command>.manifest.json``, the output
#: writer's, validation/io/atomic.py MANIFEST): bookkeeping, not a file of the suite.
MANIFEST_SUFFIX = ".manifest.json"


def suite_files(folder: str | Path) -> list[str]:
    """The relative paths of ``folder``'s suite files, in the digest's order (module docstring); a name
    starting with ``.`` (a hidden file, a writer's temporary file or staging folder) is never one."""
    folder = Path(folder)
    found = []
    top = [p for p in folder.iterdir() if not p.name.startswith(".")]
    for p in top + [q for d in top if d.is_dir() for q in d.iterdir() if not q.name.startswith(".")]:
        rel = p.relative_to(folder).as_posix()
        if p.is_file() and p.suffix in SUFFIXES and rel != INDEX_NAME and not rel.endswith(MANIFEST_SUFFIX):
            found.append(rel)
    return sorted(found, key=lambda r: r.encode("utf-8"))


def folder_digest(folder: str | Path, overlay: dict[str, Path] | None = None) -> str:
    """``sha256:<hex>`` of ``folder``'s suite files (module docstring) -- with ``overlay``
    (``{relative path: file}``, files about to be moved in) as they will be once those are in place;
    ``OSError`` if the folder is unreadable, :class:`.textformat.MalformedFile` (one line) for a file that
    is not a regular file inside its folder (:func:`.textformat.open_regular`), larger than
    :data:`MAX_FILE_BYTES` or changed while read."""
    folder = Path(folder)
    files = {rel: (folder / rel, folder) for rel in suite_files(folder)}
    files.update({rel: (Path(f), Path(f).parent) for rel, f in (overlay or {}).items()})
    h = hashlib.sha256()
    for rel in sorted(files, key=lambda r: r.encode("utf-8")):
        path, inside = files[rel]
        with open_regular(path, inside) as fh:
            size = os.fstat(fh.fileno()).st_size
            if size > MAX_FILE_BYTES:
                raise MalformedFile(f"{path}: larger than {MAX_FILE_BYTES} bytes (the limit of a suite file)")
            h.update(rel.encode("utf-8") + b"\0" + str(size).encode("ascii") + b"\0")
            read = 0
            for block in iter(lambda: fh.read(1 << 20), b""):
                read += len(block)
                h.update(block)
            if read != size:
                raise MalformedFile(f"{path}: changed while it was read (run again)")
    return "sha256:" + h.hexdigest()


def combined_digest(cases: str, orbits: str | None) -> str:
    """The suite's digest from its two folders' digests (module docstring)."""
    text = f"cases:{cases.removeprefix('sha256:')}\norbits:{(orbits or '').removeprefix('sha256:')}\n"
    return "sha256:" + hashlib.sha256(text.encode("ascii")).hexdigest()


def suite_block(cases: str | Path, overlay: dict[str, Path] | None = None) -> dict:
    """The ``suite`` block of ``cases/index.json``: name, version and the digests, computed from the
    case folder ``cases`` (with ``overlay``, :func:`folder_digest`) and the ``orbits`` folder beside it
    (None where there is none)."""
    cases = Path(cases)
    orbits = cases.parent / "orbits"
    d_cases = folder_digest(cases, overlay)
    d_orbits = folder_digest(orbits) if orbits.is_dir() else None
    return {
        "name": SUITE_NAME,
        "version": SUITE_VERSION,
        "digest": combined_digest(d_cases, d_orbits),
        "cases_digest": d_cases,
        "orbits_digest": d_orbits,
        "digest_rule": "sha256 over each file (*.json, *.csv at depth 1-2 but index.json and *.manifest.json), sorted by relative "
        "path: path, NUL, size, NUL, bytes; the suite's: sha256 of 'cases:<hex>\\norbits:<hex>\\n' "
        "(docs/golden.md, Versions of the suite)",
    }


def recorded(index: str | Path | None = None) -> dict:
    """The ``suite`` block recorded in an ``index.json`` (default: the package's); ``{}`` if it has none
    or cannot be read."""
    path = Path(index) if index is not None else PARTS["cases"] / INDEX_NAME
    try:  # the strict reader: a regular file inside its folder, within the limits
        block = read_json(path, path.parent, MAX_BYTES).value.get("suite")
    except (MalformedFile, AttributeError):
        return {}
    return block if isinstance(block, dict) else {}


@dataclass
class SuiteInfo:
    """What a run was scored against: ``part`` (``cases`` or ``orbits``) read from ``folder``, its
    computed ``digest``, and the ``version`` and ``recorded_digest`` of the index that describes it."""

    part: str
    folder: Path
    digest: str
    version: str
    recorded_digest: str | None
    name: str = SUITE_NAME

    @property
    def matches(self) -> bool:
        """Whether the folder's files are the recorded version's, byte for byte."""
        return self.digest == self.recorded_digest

    @property
    def label(self) -> str:
        """``2.0.0`` or, for files that differ from the recorded version's, ``2.0.0+modified``; a folder
        whose index records no digest is ``unversioned``."""
        if self.recorded_digest is None:
            return self.version
        return self.version if self.matches else f"{self.version}+modified"

    def line(self) -> str:
        """One line for check's header and ``--suite-version``."""
        if self.recorded_digest is None:
            state = "no index.json with a recorded version and digest describes this folder"
        else:
            state = (
                "matches the digest recorded for this version"
                if self.matches
                else f"DIFFERS from the digest recorded for {self.version} ({self.recorded_digest})"
            )
        return f"{self.name} {self.label}: {self.part} {self.folder} {self.digest} ({state})"

    def as_dict(self) -> dict:
        return {
            "name": self.name,
            "version": self.version,
            "label": self.label,
            "part": self.part,
            "folder": str(self.folder),
            "digest": self.digest,
            "recorded_digest": self.recorded_digest,
            "digest_matches": self.matches,
        }


def suite_info(folder: str | Path, part: str) -> SuiteInfo:
    """:class:`SuiteInfo` of a ``cases`` or ``orbits`` folder: its digest, computed, and the version
    recorded in the ``index.json`` beside it (a case folder's own; an orbit folder's ``../cases``; the
    package's for its own folders), with the suite's name from that block; ``OSError`` if the folder
    cannot be read."""
    if part not in PARTS:
        raise ValueError(f"part={part!r} is out of range: allowed one of {', '.join(PARTS)}")
    folder = Path(folder)
    index = folder / INDEX_NAME if part == "cases" else folder.parent / "cases" / INDEX_NAME
    block = recorded(index)
    if not block and _same(folder, PARTS[part]):
        block = recorded()
    # a suite of one's own (gear-rattle case) names itself in its index; one without a block is unversioned
    return SuiteInfo(
        part,
        folder,
        folder_digest(folder),
        printable(block.get("version", "unversioned")),
        block.get(f"{part}_digest"),
        printable(block.get("name", "suite without a recorded version")),
    )


#: The forms of ``check --require-suite`` (docs/reference/golden_commands.md, "Pinning a suite version").
REQUIRE_FORMS = "MAJOR (1), MAJOR.MINOR (1.0), ~=MAJOR.MINOR (~=1.0), ~=MAJOR.MINOR.PATCH or MAJOR.MINOR.PATCH (1.0.0)"
_SPEC = re.compile(r"(~=)?(0|[1-9][0-9]{0,8})(?:\.(0|[1-9][0-9]{0,8}))?(?:\.(0|[1-9][0-9]{0,8}))?")


def parse_requirement(spec: str) -> tuple[str, tuple[int, ...]]:
    """``(operator, numbers)`` of a version requirement: ``("", (1,))`` for ``1``, ``("~=", (1, 0))`` for
    ``~=1.0``; a ``ValueError`` naming the allowed forms (:data:`REQUIRE_FORMS`) otherwise (``~=`` needs
    two or three numbers)."""
    m = _SPEC.fullmatch(spec.strip()) if isinstance(spec, str) else None
    nums = tuple(int(x) for x in m.groups()[1:] if x is not None) if m else ()
    if m is None or (m.group(1) and len(nums) < 2):
        raise ValueError(f"{spec!r} is not a suite version requirement: allowed {REQUIRE_FORMS}")
    return m.group(1) or "", nums


def satisfies(version: str, spec: str) -> bool:
    """Whether the suite version ``version`` (``MAJOR.MINOR.PATCH``) meets the requirement ``spec``: a
    prefix (``1``: any 1.x.y; ``1.0``: any 1.0.y; ``1.0.0``: exactly) or a compatible release as pip's
    ``~=`` (``~=1.0``: 1.0 or later within MAJOR 1; ``~=1.0.2``: 1.0.2 or later within 1.0).  A version
    that is not ``MAJOR.MINOR.PATCH`` (``unversioned``) meets none."""
    op, want = parse_requirement(spec)
    m = re.fullmatch(r"(\d+)\.(\d+)\.(\d+)", version)
    if m is None:
        return False
    have = tuple(int(x) for x in m.groups())
    if not op:
        return have[: len(want)] == want
    fixed = len(want) - 1  # ~=X.Y fixes X; ~=X.Y.Z fixes X.Y
    return have[:fixed] == want[:fixed] and have[: len(want)] >= want


def _same(a: Path, b: Path) -> bool:
    try:
        return a.resolve() == Path(b).resolve()
    except OSError:
        return False


def version_line() -> str:
    """``golden suite 2.0.0`` (the package's recorded version) for ``gear-rattle --version``."""
    return f"golden suite {recorded().get('version', 'unversioned')}"
