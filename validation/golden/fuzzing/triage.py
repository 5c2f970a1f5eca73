"""The fuzzer's triage (``gear-rattle fuzz``; docs/reference/golden_commands.md, "Fuzzing an implementation"): failures grouped
by cause, one folder per group, and the reports.

* :class:`Signature`: what the first difference of a failing input is -- a value of a column beyond its
  tolerance, a wrong ``wall``, ``kind`` or ``n``, a different number of events (and whether the first
  differing event differs in kind or wall, or one sequence is a prefix of the other), a crash (its exit
  status or signal), a timeout, a malformed or a missing output file -- and the kind of the expected row
  where it shows (an impact, stick or release row).  A **group** is a signature: one defect that fails many
  inputs is one group with a count, whatever the scenarios that drew them (counted per scenario).
* :class:`Group`: its smallest member (shrunk), how many inputs failed with it, and what the implementation
  left on that member: its output file, stdout, stderr and exit status.
* :class:`GroupWriter`: writes a group's folder ``OUT/<group id>/`` -- a golden-format case
  (``settings.json``, ``expected.csv``, ``provenance.json``; ``notes.fuzz`` says how it was found) and
  ``fuzz/`` (``group.json``, ``output.csv``, ``stdout.txt``, ``stderr.txt``), then ``OUT/index.json``.
  The first member is written as soon as it is found (before it is shrunk), the shrunk one replaces it;
  a file that cannot be written is one line in the group's ``unwritten`` (the failure stays in the JSON
  summary) -- nothing found is lost, no empty folder is left.
* :func:`junit_xml`: the JUnit XML of ``--junit-xml`` (one testcase per group).
"""

from __future__ import annotations

import contextlib
import json
import re
import shutil
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Protocol

from ..boundary import check_id
from ..formats.case_writer import write_case
from ..formats.cases import COLUMNS, EXACT_COLUMNS
from ..oracle.inputs import CaseInput
from ..oracle.ondemand import UserCase, update_index
from ..scoring.junit import xml_text
from .process import RunStatus

#: The kinds of a signature, in the order a report lists them.
KINDS = ("crash", "timeout", "missing output", "malformed", "row count", "n", "wall", "kind", "value")
#: Members of a group listed by id and input in its ``group.json`` (the count counts them all).
MAX_MEMBERS = 50
#: The folder of a group's kept files, inside its case folder (not a file of the case: the suite's digest
#: and ``check`` read ``*.json`` and ``*.csv`` at depth 1-2 of a suite only).
KEPT = "fuzz"


@dataclass(frozen=True)
class Signature:
    """The cause of a failure (module docstring): ``kind`` (:data:`KINDS`), the ``column`` where it shows
    (a value's column; for a different number of events ``kind`` or ``wall`` of the first differing event,
    or ``extra rows`` / ``missing rows``), the ``row``: the kind of the expected row there (``impact``,
    ``stick``, ``release``; None where there is none), and a ``detail`` (a crash's ``exit 101`` or
    ``SIGSEGV``)."""

    kind: str
    column: str | None = None
    detail: str | None = None
    row: str | None = None

    def text(self) -> str:
        """``a value of tau beyond its tolerance (at an impact row)``, ``crash (exit 101)``, ..."""
        at = f" (at {'an' if self.row == 'impact' else 'a'} {self.row} row)" if self.row else ""
        if self.kind == "value":
            return f"a value of {self.column} beyond its tolerance{at}"
        if self.kind in EXACT_COLUMNS:
            return f"a wrong {self.kind}{at}"
        if self.kind == "row count":
            return f"a different number of events ({self.column}{', ' + at[2:-1] if at else ''})"
        return self.kind + (f" ({self.detail})" if self.detail else "")

    def slug(self) -> str:
        """The signature in a folder name: ``value-tau-impact``, ``crash-exit-101``, ``row-count-kind-stick``."""
        words = dict.fromkeys(w for w in (self.kind, self.column, self.detail, self.row) if w)
        return re.sub(r"[^a-z0-9]+", "-", " ".join(words).lower()).strip("-")

    def as_dict(self) -> dict:
        return {"kind": self.kind, "column": self.column, "row": self.row, "detail": self.detail, "text": self.text()}


def score_signature(score, got, expected) -> Signature:
    """The signature of a failing score of a well-formed file, from the score's structured fields: its
    ``first_row`` (the first failure's golden row) and ``columns`` (each failing column's ``first_row``);
    where no column fails there (the event sequences part), the sequences ``got`` and ``expected`` at that
    row -- never from its message."""
    k = score.first_row
    row = str(expected.kind[k]) if 0 <= k < len(expected) else None
    failing = [c for c in COLUMNS if c in score.columns and not score.columns[c].passed]
    if failing:
        first = min(failing, key=lambda c: (score.columns[c].first_row, COLUMNS.index(c)))
        if score.columns[first].first_row == k:
            return Signature(first, row=row) if first in EXACT_COLUMNS else Signature("value", first, row=row)
    column = None
    if 0 <= k < min(len(got), len(expected)):
        column = next((c for c in ("kind", "wall") if getattr(got, c)[k] != getattr(expected, c)[k]), None)
    if len(got) == len(expected) and column is not None:
        return Signature(column, row=row)
    if column is None:
        column = "extra rows" if len(got) > len(expected) else "missing rows"
    return Signature("row count", column, row=row)


class Outcome(Protocol):
    """What a group keeps of its member's run (:class:`.runner.Outcome`)."""

    message: str
    output: bytes | None
    output_path: str
    status: RunStatus


class NotWritten(Exception):
    """A file of a group could not be written (one line naming it)."""


# ---------------------------------------------------------------------------------------------
# groups


@dataclass
class Group:
    """A cause of failure (:class:`Signature`) and its smallest member; ``scenario`` is that of its first
    member, ``scenarios`` counts the members per scenario.  ``outcome`` is the smallest member's outcome (``status``: its run, with stdout and stderr; ``output``: the bytes of its output
    file, None where there was none; ``output_path``: where that was; ``message``)."""

    id: str
    signature: Signature
    scenario: str
    case: UserCase
    outcome: Outcome
    original: CaseInput
    found_after_s: float
    count: int = 1
    members: list = field(default_factory=list)
    scenarios: dict = field(default_factory=dict)
    shrink_rounds: int = 0
    shrunk: bool = False
    alone: bool = False
    note: str = ""
    folder: str = ""
    unwritten: list = field(default_factory=list)

    def kept(self) -> dict:
        """The kept files (paths, as the summary names them): None where nothing is kept -- no folder (the
        library without ``out``), or, for ``output``, no regular file written by the implementation."""
        base = Path(self.folder) / KEPT if self.folder else None
        return {
            "output": str(base / "output.csv") if base and self.outcome.output is not None else None,
            "stdout": str(base / "stdout.txt") if base else None,
            "stderr": str(base / "stderr.txt") if base else None,
        }

    def message(self) -> str:
        """The member's failure in one line, naming the kept files (never the run's temporary ones)."""
        kept = self.kept()
        text = self.outcome.message
        if self.outcome.output_path:
            text = text.replace(str(self.outcome.output_path), kept["output"] or f"{self.id}.csv (not kept)")
        if self.signature.kind in ("crash", "timeout") and kept["stderr"]:
            text += f" (its stderr: {kept['stderr']})"
        return text

    def summary(self) -> dict:
        """The group in the JSON summary (and its ``fuzz/group.json``)."""
        return {
            "id": self.id,
            "folder": self.folder,
            "signature": self.signature.as_dict(),
            "scenario": self.scenario,
            "count": self.count,
            "scenarios": dict(self.scenarios),
            "message": self.message(),
            "found_after_s": round(self.found_after_s, 2),
            "impacts": self.case.settings["n_impacts"],
            "rows": self.case.settings["expected_rows"],
            "input": {**self.case.input.as_dict(), "id": self.id},
            "original_input": self.original.as_dict(),
            "shrunk": self.shrunk,
            "shrink_rounds": self.shrink_rounds,
            "run": {**self.outcome.status.as_dict(), "alone": self.alone},
            "kept": self.kept(),
            "note": self.note or None,
            "members": self.members[:MAX_MEMBERS],
            "unwritten": list(self.unwritten),
        }


def group_id(seed: int, k: int, sig: Signature) -> str:
    """``fuzz-<seed>-<k>-<signature>``: a valid case id (:func:`.boundary.check_id`)."""
    return check_id(f"fuzz-{seed}-{k:02d}-{sig.slug()}"[:100].rstrip("."), "a group's id")


# ---------------------------------------------------------------------------------------------
# writing


def store_plain(files: dict) -> None:
    """The library's writer of a group's files (``{path: bytes}``, parents created); the command line
    passes one that writes them atomically, all or none."""
    try:
        for path, data in files.items():
            Path(path).parent.mkdir(parents=True, exist_ok=True)
            Path(path).write_bytes(data)
    except OSError as e:
        raise NotWritten(f"cannot write {str(e.filename or path)!r}: {e.strerror or e}") from None


@dataclass
class GroupWriter:
    """Writes groups under ``out`` through ``store`` (``{path: bytes}``: all or none, else
    :class:`NotWritten`), with the seed and the implementation's command line in ``notes.fuzz``."""

    out: Path
    seed: int
    command: str
    store: Callable[[dict], None] = store_plain
    out_existed: bool = field(init=False)

    def __post_init__(self) -> None:
        self.out_existed = Path(self.out).exists()

    def write(self, g: Group) -> None:
        """Write (or replace) the group's folder, then the index; a file that cannot be written goes to
        ``g.unwritten`` (one line) and leaves no folder that was not there before."""
        folder = Path(self.out) / g.id
        g.folder = str(folder)
        existed = folder.exists()
        files: dict = {}
        case = _with_fuzz_notes(g, self.seed, self.command)
        collect = lambda p, text: files.__setitem__(Path(p), text.encode())  # noqa: E731
        write_case(folder, case.settings, case.expected, case.provenance, collect)
        kept = folder / KEPT
        files[kept / "group.json"] = (json.dumps(g.summary(), indent=1) + "\n").encode()
        files[kept / "stdout.txt"] = g.outcome.status.stdout
        files[kept / "stderr.txt"] = g.outcome.status.stderr
        if g.outcome.output is not None:
            files[kept / "output.csv"] = g.outcome.output
        else:
            (kept / "output.csv").unlink(missing_ok=True)
        if not self._store(g, files):
            if not existed:  # nothing of it was there: nothing of it stays, nor an --out made for it
                shutil.rmtree(folder, ignore_errors=True)
                if not self.out_existed:
                    with contextlib.suppress(OSError):
                        Path(self.out).rmdir()
            return
        self.index(g)

    def update(self, g: Group) -> None:
        """Rewrite the group's ``fuzz/group.json`` (its count and members grew)."""
        if g.folder and (Path(g.folder) / "settings.json").is_file():
            self._store(g, {Path(g.folder) / KEPT / "group.json": (json.dumps(g.summary(), indent=1) + "\n").encode()})

    def index(self, g: Group) -> None:
        files: dict = {}
        try:
            update_index(self.out, lambda p, text: files.__setitem__(Path(p), text.encode()))
        except (ValueError, OSError) as e:
            g.unwritten.append(" ".join(str(e).split()))
            return
        self._store(g, files)

    def _store(self, g: Group, files: dict) -> bool:
        try:
            self.store(files)
        except NotWritten as e:
            g.unwritten.append(str(e))
            return False
        return True


def _with_fuzz_notes(g: Group, seed: int, command: str) -> UserCase:
    """The group's case under its id, with ``notes.fuzz`` (how it was found) in its settings: a regression
    case to keep."""
    from .shrinker import renamed

    case = renamed(g.case, g.id)
    notes = {
        **case.settings["notes"],
        "fuzz": {
            "found_by": f"gear-rattle fuzz --seed {seed}",
            "implementation": command,
            "scenario": g.scenario,
            "signature": g.signature.as_dict(),
            "failure": g.message(),
            "original_input": g.original.as_dict(),
            "shrunk": g.shrunk,
            "shrink_rounds": g.shrink_rounds,
        },
    }
    settings = {**case.settings, "notes": notes, "tags": [*case.settings["tags"], "fuzz", g.scenario]}
    return UserCase(case.input, settings, case.expected, case.provenance, case.truncation)


# ---------------------------------------------------------------------------------------------
# JUnit XML


def junit_xml(doc: dict) -> str:
    """The JUnit XML of ``--junit-xml`` for the JSON summary ``doc``: one ``<testsuite>`` ("gear-rattle
    fuzz", the implementation, seed and counts as properties) with one ``<testcase>`` per group (``name``
    its id, ``classname`` ``gear-rattle.fuzz.<kind>``) failing with its signature, count, message and
    kept files; a run that found nothing is one passing testcase (``search``), a run that could not run the
    implementation one testcase with an ``<error>``."""
    groups = doc["groups"]
    error = doc.get("error")
    tests = len(groups) + (1 if error or not groups else 0)
    attrs = {
        "tests": str(tests),
        "failures": str(len(groups)),
        "errors": "1" if error else "0",
        "time": f"{doc['elapsed_s']:.3f}",
    }
    root = ET.Element("testsuites", {"name": "gear-rattle fuzz", **attrs})
    ts = ET.SubElement(root, "testsuite", {"name": "gear-rattle fuzz", **attrs, "skipped": "0"})
    props = ET.SubElement(ts, "properties")
    for key in ("implementation", "seed", "budget_s", "cases", "failed_inputs", "out"):
        ET.SubElement(props, "property", {"name": key, "value": xml_text(str(doc.get(key)))})
    for g in groups:
        classname = "gear-rattle.fuzz." + re.sub(r"[^a-z0-9]+", "-", g["signature"]["kind"])
        tc = ET.SubElement(ts, "testcase", {"classname": classname, "name": xml_text(g["id"])})
        head = f"{g['signature']['text']}: {g['count']} input(s) failed"
        f = ET.SubElement(
            tc, "failure", {"message": xml_text(f"{head}; {g['message']}"), "type": f"fuzz.{g['signature']['kind']}"}
        )
        f.text = xml_text(_failure_text(g))
    if error or not groups:
        tc = ET.SubElement(ts, "testcase", {"classname": "gear-rattle.fuzz", "name": "search"})
        if error:
            e = ET.SubElement(tc, "error", {"message": xml_text(error), "type": "fuzz.error"})
            e.text = xml_text(error)
        else:
            ET.SubElement(tc, "system-out").text = f"{doc['cases']} cases, no failure"
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _failure_text(g: dict) -> str:
    lines = [
        g["message"],
        f"signature: {g['signature']['text']}; {g['count']} input(s) failed with it, by scenario "
        + ", ".join(f"{k} {v}" for k, v in g["scenarios"].items()),
        f"smallest member: {json.dumps(g['input'])} ({g['impacts']} impacts, {g['rows']} rows)",
        f"first found: {json.dumps(g['original_input'])}",
        "kept: " + ", ".join(f"{k} {v}" for k, v in g["kept"].items() if v),
        "run: " + ", ".join(f"{k} {v}" for k, v in g["run"].items()),
    ]
    lines += [f"not written: {u}" for u in g["unwritten"]]
    return "\n".join(lines)
