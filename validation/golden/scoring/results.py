"""What ``gear-rattle check`` reports, as typed data: one result per case (:class:`CaseResult`) or orbit record
(:class:`OrbitResult`), its verdict, the counts, and the run's document (:class:`CheckRun`) --
docs/reference/golden_commands.md, "In CI".  Every report is built from these objects: the table, the summary line and
the details on the terminal (:mod:`.text_report`), the JUnit XML file (:mod:`.junit`) and the JSON document, which is
:meth:`CheckRun.as_dict`: the results are serialised there, at the edge, and nowhere before.

A result holds ``id``, ``level``, ``verdict`` (:data:`VERDICTS`), ``passed`` (whether its output passed the
scoring; None when not scored), ``digits`` per column, ``worst_over_tolerance`` (the largest ``|error| /
tolerance`` over the scored values: < 1 passes), ``first_failing`` (the first failure, placed and
structured: a :class:`.differences.Difference`: file, line, column, expected and actual rows or values,
error, tolerance, context rows), ``note`` (one line) and ``reason`` (why it was skipped or is a known
failure); a case's result also whether its exact columns match, the rows compared, where the event
sequences part and the worst value.  The scores, columns and levels come from :mod:`.cases`,
:mod:`.orbits` and the formats; numpy and the standard library only, as the light install has.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

from ..formats.cases import EXACT_COLUMNS, TOLERANCE_COLUMNS as CASE_COLUMNS, Case
from ..formats.orbits import COLUMNS as ORBIT_COLUMNS, LEVEL as ORBIT_LEVEL, Record
from ..formats.version import SuiteInfo
from .cases import CaseScore
from .differences import Difference
from .orbits import OrbitScore

__all__ = [
    "FORMAT",
    "VERDICTS",
    "FAILING",
    "ERROR_KINDS",
    "CaseResult",
    "OrbitResult",
    "Result",
    "Selection",
    "CheckRun",
    "case_result",
    "orbit_result",
    "skipped_result",
    "known_failure",
    "counts",
    "exit_status",
]

#: The JSON document's format name (version 2: verdicts, skipped cases, known failures, structured
#: differences; version 1 had ``first_failing`` as ``{"line", "column"}`` and no verdicts).
FORMAT = "gear-rattle check results, version 2"
#: Verdicts: what each means, and its count's name in the JSON document.
VERDICTS = {
    "pass": ("its output passes", "passed"),
    "fail": ("its output fails: a value beyond its tolerance, another event sequence, or no output", "failed"),
    "error": ("its output could not be scored: a malformed file (or, with --self, our track raised)", "errors"),
    "skipped": ("not selected (--cases, --level, --exclude): not scored", "skipped"),
    "xfail": ("a known failure (--known-failures) that fails, as expected", "xfailed"),
    "xpass": ("a known failure that now passes: the run fails until it is removed from the file", "xpassed"),
}
#: Verdicts that fail the run (exit status 1).
FAILING = ("fail", "error", "xpass")
#: Kinds of difference that are errors (the output was not scored), not failures.
ERROR_KINDS = ("malformed", "crash")


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def _as_dict(diff: Difference | None) -> dict | None:
    return None if diff is None else diff.as_dict()


@dataclass(frozen=True)
class CaseResult:
    """The result of one impact case (module docstring); :meth:`as_dict` is its JSON form."""

    id: str
    level: int | None
    verdict: str
    passed: bool | None
    digits: dict[str, float | None]
    exact_columns_match: bool
    worst_over_tolerance: float | None
    compared_rows: int
    first_failing: Difference | None
    event_difference: Difference | None
    worst: Difference | None
    note: str
    reason: str | None

    def as_dict(self) -> dict:
        """The JSON form: the fields in order, each difference as :meth:`.differences.Difference.as_dict`."""
        out: dict[str, Any] = dict(vars(self))
        for k in ("first_failing", "event_difference", "worst"):
            out[k] = _as_dict(out[k])
        return out


@dataclass(frozen=True)
class OrbitResult:
    """The result of one orbit record (module docstring); :meth:`as_dict` is its JSON form."""

    id: str
    level: int | None
    verdict: str
    passed: bool | None
    digits: dict[str, float | None]
    worst_over_tolerance: float | None
    first_failing: Difference | None
    note: str
    reason: str | None

    def as_dict(self) -> dict:
        """The JSON form: the fields in order, the first failure as :meth:`.differences.Difference.as_dict`."""
        return dict(vars(self), first_failing=_as_dict(self.first_failing))


#: The result of a case or of an orbit record.
Result = CaseResult | OrbitResult


def _verdict(score: CaseScore | OrbitScore) -> str:
    if score.passed:
        return "pass"
    first = score.first_failing
    return "error" if first is not None and first.kind in ERROR_KINDS else "fail"


def case_result(case: Case, score: CaseScore) -> CaseResult:
    """The result of one impact case."""
    level = getattr(score, "level", None) or case.settings.get("level")
    cols = score.columns if score.compared_rows else {}
    verdict = _verdict(score)
    return CaseResult(
        id=score.case,
        level=level,
        verdict=verdict,
        passed=verdict != "error" and bool(score.passed),
        digits={c: (_finite(cols[c].digits) if c in cols else None) for c in CASE_COLUMNS},
        exact_columns_match=bool(cols)
        and score.event_difference is None
        and all(c in cols and cols[c].passed for c in EXACT_COLUMNS),
        worst_over_tolerance=_finite(score.worst_ratio),
        compared_rows=score.compared_rows,
        first_failing=score.first_failing,
        event_difference=score.event_difference,
        worst=score.worst,
        note=score.message,
        reason=None,
    )


def orbit_result(record: Record, score: OrbitScore) -> OrbitResult:
    """The result of one orbit record."""
    cols = score.columns
    verdict = _verdict(score)
    return OrbitResult(
        id=score.id,
        level=getattr(score, "level", None) or ORBIT_LEVEL,
        verdict=verdict,
        passed=verdict != "error" and bool(score.passed),
        digits={c: (_finite(cols[c].digits) if c in cols else None) for c in ORBIT_COLUMNS},
        worst_over_tolerance=_finite(score.worst_ratio),
        first_failing=score.first_failing,
        note=score.message,
        reason=None,
    )


def skipped_result(id_: str, level: int | None, reason: str, orbits: bool = False) -> Result:
    """The result of a case or record that was not selected: not scored, ``reason`` says why."""
    note = f"skipped: {reason}"
    if orbits:
        digits: dict[str, float | None] = {c: None for c in ORBIT_COLUMNS}
        return OrbitResult(id_, level, "skipped", None, digits, None, None, note, reason)
    none: dict[str, float | None] = {c: None for c in CASE_COLUMNS}
    return CaseResult(id_, level, "skipped", None, none, False, None, 0, None, None, None, note, reason)


def known_failure(result: Result, reason: str, source: str) -> Result:
    """``result`` as a known failure (``reason``, from the file ``source``): a failing or erring one is an
    expected failure (``xfail``), a passing one an unexpected pass (``xpass``, which fails the run, as
    pytest's strict xfail)."""
    if result.verdict == "pass":
        note = f"known failure now passes: remove it from {source} (its reason: {reason})"
        return replace(result, verdict="xpass", note=note, reason=reason)
    if result.verdict in ("fail", "error"):
        return replace(result, verdict="xfail", note=f"known failure ({reason}): {result.note}", reason=reason)
    return replace(result, reason=reason)


def counts(results: list[Result]) -> dict:
    """``{"tests": N, "passed": .., "failed": .., "errors": .., "skipped": .., "xfailed": .., "xpassed": ..}``
    (each result in exactly one count)."""
    out = {"tests": len(results)}
    for verdict, (_, name) in VERDICTS.items():
        out[name] = sum(r.verdict == verdict for r in results)
    return out


def exit_status(results: list[Result]) -> int:
    """0 when no result fails the run (passes, skipped cases and expected failures only), else 1."""
    return 1 if any(r.verdict in FAILING for r in results) else 0


@dataclass(frozen=True)
class Selection:
    """How the cases or records of a run were selected (``--cases``, ``--level``, ``--exclude``, each in the
    order given, None where not given) and the known-failures file (``--known-failures``)."""

    cases: tuple[str, ...] | None = None
    levels: tuple[int, ...] | None = None
    exclude: tuple[str, ...] | None = None
    known_failures: str | None = None

    def as_dict(self) -> dict:
        """The JSON form (the levels sorted, each once)."""
        return {
            "cases": list(self.cases) if self.cases else None,
            "levels": sorted(set(self.levels)) if self.levels else None,
            "exclude": list(self.exclude) if self.exclude else None,
            "known_failures": self.known_failures,
        }


@dataclass(frozen=True)
class CheckRun:
    """One run of ``check``: the suite scored against (:class:`.formats.version.SuiteInfo`), whether its orbit
    records were scored, what was scored (``source``: the output directory or our own track), how the items
    were selected, a result per item of the suite (in the suite's order) and the seconds spent scoring each
    (``times``, for the JUnit file; not part of the JSON document)."""

    suite: SuiteInfo
    orbits: bool
    source: str
    selection: Selection
    results: tuple[Result, ...]
    times: dict[str, float] = field(default_factory=dict)

    @property
    def scored(self) -> str:
        """``cases`` or ``orbits``."""
        return "orbits" if self.orbits else "cases"

    def counts(self) -> dict:
        """:func:`counts` of the results."""
        return counts(list(self.results))

    def exit_status(self) -> int:
        """:func:`exit_status` of the results."""
        return exit_status(list(self.results))

    def as_dict(self) -> dict:
        """The JSON document of ``--json``: the format, the suite (name, version, digests), what was scored,
        how the items were selected, the counts and the results."""
        return {
            "format": FORMAT,
            "suite": self.suite.as_dict(),
            "scored": self.scored,
            "source": self.source,
            "selection": self.selection.as_dict(),
            **self.counts(),
            "results": [r.as_dict() for r in self.results],
        }
