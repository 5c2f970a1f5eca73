"""A run of ``gear-rattle check``, below the command line (docs/reference/golden_commands.md, "In CI"): which
items of a suite are selected (the others skipped, with the reason: :func:`plan`), the known failures
(:func:`known_failures`),
each output file read on its own (:func:`read_outputs`: a missing file is "no output", a malformed one an
error of its item alone), each item scored and made a typed result (:func:`score_items`).  The impact
cases and the orbit records differ only in their :class:`Scorer` (:data:`CASES`, :data:`ORBITS`); the
command composes these steps with the reports (:mod:`.text_report`, :mod:`.junit`, the JSON document
:meth:`.results.CheckRun.as_dict`).  Only numpy: ``check`` scores anywhere.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from ..boundary import member
from ..formats.cases import MalformedFile, MissingFile, read_sequence, select_ids
from ..formats.known_failures import read_known_failures
from ..formats.orbits import read_values
from . import cases as case_scores, orbits as orbit_scores
from .results import Result, Selection, case_result, known_failure, orbit_result, skipped_result

__all__ = [
    "Scorer",
    "CASES",
    "ORBITS",
    "Ready",
    "Plan",
    "NothingSelected",
    "known_failures",
    "plan",
    "Outputs",
    "read_outputs",
    "score_items",
]


class Scorer(Protocol):
    """What differs between the impact cases and the orbit records: the output files' suffix, how one is
    read (a regular file inside the folder ``root``), scored, scored when missing or unreadable, and
    made a result."""

    @property
    def orbits(self) -> bool: ...

    @property
    def suffix(self) -> str: ...

    def read(self, path: Path, item: Any, root: Path) -> Any: ...

    def score(self, item: Any, got: Any) -> Any: ...

    def no_output(self, item: Any, path: Path) -> Any: ...

    def problem(self, item: Any, kind: str, message: str, path=None, line=None, column=None) -> Any: ...

    def result(self, item: Any, score: Any) -> Result: ...


@dataclass(frozen=True)
class _CaseScorer:
    """The impact cases: ``<case-id>.csv`` (:mod:`..formats.cases`, :mod:`.cases`)."""

    orbits: bool = False
    suffix: str = ".csv"

    def read(self, path: Path, item: Any, root: Path) -> Any:
        return read_sequence(path, inside=root)

    score = staticmethod(case_scores.score_sequence)
    no_output = staticmethod(case_scores.no_output_score)
    problem = staticmethod(case_scores.problem_score)
    result = staticmethod(case_result)


@dataclass(frozen=True)
class _OrbitScorer:
    """The orbit records: ``<id>.json`` (:mod:`..formats.orbits`, :mod:`.orbits`)."""

    orbits: bool = True
    suffix: str = ".json"

    def read(self, path: Path, item: Any, root: Path) -> Any:
        return read_values(path, item, root)

    score = staticmethod(orbit_scores.score_values)
    no_output = staticmethod(orbit_scores.no_output_score)
    problem = staticmethod(orbit_scores.problem_score)
    result = staticmethod(orbit_result)


#: The scorer of the impact cases.
CASES: Scorer = _CaseScorer()
#: The scorer of the orbit records.
ORBITS: Scorer = _OrbitScorer()


@dataclass(frozen=True)
class Ready:
    """A score decided without scoring values: no output, a malformed file, a crash."""

    score: Any


class NothingSelected(Exception):
    """The selection holds no item of the suite (one line naming the suite and the selection)."""


@dataclass(frozen=True)
class Plan:
    """Which items are scored (``selected``, in the suite's order), which not (``skipped``: ``{id: reason}``)
    and which are known failures (``known``: ``{id: reason}``)."""

    selected: list
    skipped: dict[str, str]
    known: dict[str, str]


def _skip_reasons(items: Sequence, selection: Selection, where, what: str) -> dict[str, str]:
    """``{id: reason}`` of the items not selected by ``--cases``, ``--level`` and ``--exclude``; an unknown
    id there is a :class:`MalformedFile` naming the known ones."""
    ids = [i.id for i in items]
    select_ids(ids, list(selection.cases or ()), where, what)
    select_ids(ids, list(selection.exclude or ()), where, what)
    levels = ",".join(map(str, sorted(set(selection.levels or []))))
    out = {}
    for item in items:
        level = getattr(item, "level", None)
        if selection.cases and item.id not in selection.cases:
            out[item.id] = "not selected by --cases"
        elif selection.levels and level not in selection.levels:
            out[item.id] = f"level {level}, not selected by --level {levels}"
        elif selection.exclude and item.id in selection.exclude:
            out[item.id] = "excluded by --exclude"
    return out


def _nothing_selected(what: str, selection: Selection, where) -> NothingSelected:
    how = " and ".join(
        x
        for x in (
            f"--cases {' '.join(selection.cases)}" if selection.cases else "",
            f"--level {','.join(map(str, sorted(set(selection.levels))))}" if selection.levels else "",
            f"--exclude {' '.join(selection.exclude)}" if selection.exclude else "",
        )
        if x
    )
    return NothingSelected(
        f"{what} {str(where)!r} has no {'record' if 'orbit' in what else 'case'}"
        + (f" selected by {how}" if how else "")
    )


def known_failures(items: Sequence, selection: Selection, scorer: Scorer) -> dict[str, str]:
    """``{id: reason}`` of the known-failures file (:func:`..formats.known_failures.read_known_failures`;
    empty without one); a malformed file is a :class:`MalformedFile` (one line)."""
    if selection.known_failures is None:
        return {}
    return read_known_failures(selection.known_failures, [i.id for i in items], "orbit" if scorer.orbits else "case")


def plan(items: Sequence, selection: Selection, where, scorer: Scorer, known: dict[str, str]) -> Plan:
    """The :class:`Plan` of a run over ``items`` (the suite's, in order; ``where``: the suite's folder, for
    messages; ``known``: :func:`known_failures`).  Raises :class:`MalformedFile` for an unknown id in the
    selection (one line naming the known ones) and :class:`NothingSelected` where nothing is selected."""
    what = "orbit" if scorer.orbits else "case"
    skipped = _skip_reasons(items, selection, where, what)
    selected = [i for i in items if i.id not in skipped]
    if not selected:
        raise _nothing_selected("orbit suite" if scorer.orbits else "suite", selection, where)
    return Plan(selected, skipped, known)


@dataclass(frozen=True)
class Outputs:
    """``{id: output or Ready(score)}`` of the selected items, the one-line message of each malformed file
    (in the items' order), and whether the output folder was missing (every item then "no output")."""

    values: dict = field(default_factory=dict)
    malformed: list[str] = field(default_factory=list)
    folder_missing: bool = False


def read_outputs(folder: str | Path, items: Sequence, scorer: Scorer) -> Outputs:
    """Each output file of ``folder`` read on its own: a path built from the item's validated id, a regular
    file inside ``folder`` (:func:`..boundary.member`).  A missing file is "no output"; a malformed one an
    error of its item alone (its message cut to 500 characters).  A folder that does not exist: every item
    "no output"."""
    root = Path(folder)
    if not root.is_dir():
        values = {i.id: Ready(scorer.no_output(i, member(root, i.id, scorer.suffix))) for i in items}
        return Outputs(values, [], True)
    out: dict = {}
    malformed = []
    for item in items:
        path = member(root, item.id, scorer.suffix)  # a path built from a validated id, inside the folder
        try:
            out[item.id] = scorer.read(path, item, root)  # a regular file inside the folder, its links resolved
        except MissingFile:
            out[item.id] = Ready(scorer.no_output(item, path))
        except MalformedFile as e:
            text = " ".join(str(e).split())
            text = text if len(text) <= 500 else text[:500] + " ... (cut)"
            malformed.append(text)
            place = e.path or str(path)
            out[item.id] = Ready(scorer.problem(item, "malformed", text, place, e.line, e.column))
    return Outputs(out, malformed)


def score_items(
    items: Sequence, plan: Plan, outputs: dict, scorer: Scorer, known_source: str | None = None
) -> tuple[list[Result], dict[str, float]]:
    """``(results, times)``: a result for every item of the suite, in order -- skipped, or its output
    (``outputs[id]``: read, or a :class:`Ready` score) scored, a known failure marked as such
    (``known_source``: the known-failures file, for the notes) -- and the seconds spent on each scored."""
    results: list[Result] = []
    times: dict[str, float] = {}
    for item in items:
        if item.id in plan.skipped:
            results.append(skipped_result(item.id, getattr(item, "level", None), plan.skipped[item.id], scorer.orbits))
            continue
        t0 = time.perf_counter()
        got = outputs[item.id]
        sc = got.score if isinstance(got, Ready) else scorer.score(item, got)
        r = scorer.result(item, sc)
        results.append(known_failure(r, plan.known[item.id], str(known_source)) if item.id in plan.known else r)
        times[item.id] = time.perf_counter() - t0
    return results, times
