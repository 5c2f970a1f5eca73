"""What ``gear-rattle check`` reports, as data: one result per case or orbit record, its verdict, the
counts, the JSON document and the JUnit XML file (docs/golden.md, "Using the suite in CI").  The table,
the summary line and the details of each failure on the terminal are :mod:`.results_text`'s.

Each case or orbit record of the suite becomes one plain result (:func:`case_result`,
:func:`orbit_result`, :func:`skipped_result`): ``id``, ``level``, ``verdict`` (:data:`VERDICTS`),
``passed`` (whether its output passed the scoring; None when not scored), ``digits`` per column,
``worst_over_tolerance`` (the largest ``|error| / tolerance`` over the scored values: < 1 passes),
``first_failing`` (the first failure, structured: :class:`.differences.Difference` as a dict: file,
line, column, expected and actual rows or values, error, tolerance, context rows), ``note`` (one line)
and ``reason`` (why it was skipped or is a known failure).  The reports are built from those results
only, so the impact cases and the orbit records share them (the scores, columns and levels come from
:mod:`.suite` and :mod:`.orbit_suite`; numpy and the standard library only, as the light install has).
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from typing import Any

# The columns and levels are the scorers' own (one definition each): the tolerance columns, the exact
# columns of a case; the columns and the level of an orbit record.
from .orbit_suite import COLUMNS as ORBIT_COLUMNS, LEVEL as ORBIT_LEVEL
from .suite import EXACT_COLUMNS, TOLERANCE_COLUMNS as CASE_COLUMNS

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


def _as_dict(diff) -> dict | None:
    return None if diff is None else diff.as_dict()


def _verdict(score) -> str:
    if score.passed:
        return "pass"
    first = score.first_failing
    return "error" if first is not None and first.kind in ERROR_KINDS else "fail"


def case_result(case, score) -> dict:
    """The result of one impact case (``case``: :class:`suite.Case`, ``score``: :class:`suite.CaseScore`)."""
    level = getattr(score, "level", None) or case.settings.get("level")
    cols = score.columns if score.compared_rows else {}
    verdict = _verdict(score)
    return {
        "id": score.case,
        "level": level,
        "verdict": verdict,
        "passed": verdict != "error" and bool(score.passed),
        "digits": {c: (_finite(cols[c].digits) if c in cols else None) for c in CASE_COLUMNS},
        "exact_columns_match": bool(cols)
        and score.event_difference is None
        and all(c in cols and cols[c].passed for c in EXACT_COLUMNS),
        "worst_over_tolerance": _finite(score.worst_ratio),
        "compared_rows": score.compared_rows,
        "first_failing": _as_dict(score.first_failing),
        "event_difference": _as_dict(score.event_difference),
        "worst": _as_dict(score.worst),
        "note": score.message,
        "reason": None,
    }


def orbit_result(record, score) -> dict:
    """The result of one orbit record (:class:`orbit_suite.Record`, :class:`orbit_suite.OrbitScore`)."""
    cols = score.columns
    verdict = _verdict(score)
    return {
        "id": score.id,
        "level": getattr(score, "level", None) or ORBIT_LEVEL,
        "verdict": verdict,
        "passed": verdict != "error" and bool(score.passed),
        "digits": {c: (_finite(cols[c].digits) if c in cols else None) for c in ORBIT_COLUMNS},
        "worst_over_tolerance": _finite(score.worst_ratio),
        "first_failing": _as_dict(score.first_failing),
        "note": score.message,
        "reason": None,
    }


def skipped_result(id_: str, level: int | None, reason: str, orbits: bool = False) -> dict:
    """The result of a case or record that was not selected: not scored, ``reason`` says why."""
    out: dict[str, Any] = {"id": id_, "level": level, "verdict": "skipped", "passed": None}
    out["digits"] = {c: None for c in (ORBIT_COLUMNS if orbits else CASE_COLUMNS)}
    if not orbits:
        out.update(exact_columns_match=False, worst_over_tolerance=None, compared_rows=0)
        out.update(first_failing=None, event_difference=None, worst=None)
    else:
        out.update(worst_over_tolerance=None, first_failing=None)
    out.update(note=f"skipped: {reason}", reason=reason)
    return out


def known_failure(result: dict, reason: str, source: str) -> dict:
    """``result`` as a known failure (``reason``, from the file ``source``): a failing or erring one is an
    expected failure (``xfail``), a passing one an unexpected pass (``xpass``, which fails the run, as
    pytest's strict xfail)."""
    out = dict(result, reason=reason)
    if result["verdict"] == "pass":
        out["verdict"] = "xpass"
        out["note"] = f"known failure now passes: remove it from {source} (its reason: {reason})"
    elif result["verdict"] in ("fail", "error"):
        out["verdict"] = "xfail"
        out["note"] = f"known failure ({reason}): {result['note']}"
    return out


def counts(results: list[dict]) -> dict:
    """``{"tests": N, "passed": .., "failed": .., "errors": .., "skipped": .., "xfailed": .., "xpassed": ..}``
    (each result in exactly one count)."""
    out = {"tests": len(results)}
    for verdict, (_, name) in VERDICTS.items():
        out[name] = sum(r["verdict"] == verdict for r in results)
    return out


def exit_status(results: list[dict]) -> int:
    """0 when no result fails the run (passes, skipped cases and expected failures only), else 1."""
    return 1 if any(r["verdict"] in FAILING for r in results) else 0


# ------------------------------------------------------------------------------------------ files


def document(results: list[dict], suite: dict, *, orbits: bool, source: str, selection: dict | None = None) -> dict:
    """The JSON document of ``--json``: the format, the suite (name, version, digests), what was
    scored (``source``: the output directory or our own track), how cases were selected
    (``selection``), the counts and the results."""
    return {
        "format": FORMAT,
        "suite": suite,
        "scored": "orbits" if orbits else "cases",
        "source": source,
        "selection": selection or {},
        **counts(results),
        "results": results,
    }


#: Characters XML 1.0 does not allow (a file name may hold them): replaced by U+FFFD in the JUnit file.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _x(text: str) -> str:
    return _NOT_XML.sub("\ufffd", text)


def _property(value) -> str:
    """A property's value: booleans ``true``/``false`` (as XML Schema writes them), nothing for None."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return ""
    if isinstance(value, (list, tuple)):
        return ",".join(map(str, value))
    return str(value)


def _testcase(ts: ET.Element, r: dict, classname: str, time: float, details) -> None:
    """One ``<testcase>``: a failing one holds ``<failure>`` (its message the note, its text the
    details), an erring one ``<error>``, a skipped one or a known failure ``<skipped>``; ``file`` and
    ``line`` name the output file and line of the first failure, where there is one."""
    attrs = {"classname": classname, "name": _x(r["id"]), "time": f"{time:.6f}"}
    first = r.get("first_failing") or {}
    if r["verdict"] in ("fail", "error", "xfail") and first.get("file"):
        attrs["file"] = _x(first["file"])
        if first.get("line") is not None:
            attrs["line"] = str(first["line"])
    tc = ET.SubElement(ts, "testcase", attrs)
    v = r["verdict"]
    note = _x(r["note"] or v)
    if v in ("fail", "xpass"):
        kind = "xpass" if v == "xpass" else (first.get("kind") or "mismatch")
        el = ET.SubElement(tc, "failure", {"message": note, "type": f"golden.{kind}"})
        el.text = _x("\n".join(details(r)))
    elif v == "error":
        el = ET.SubElement(tc, "error", {"message": note, "type": f"golden.{first.get('kind') or 'malformed'}"})
        el.text = _x("\n".join(details(r)))
    elif v in ("skipped", "xfail"):
        el = ET.SubElement(tc, "skipped", {"message": note, "type": f"golden.{v}"})
        if v == "xfail":
            el.text = _x("\n".join(details(r)))


def junit_xml(doc: dict, times: dict | None = None, details=None) -> str:
    """The JUnit XML text of ``--junit-xml`` for a :func:`document`: ``<testsuites>`` holding one
    ``<testsuite>`` (the suite's name, version and digests, and the selection, as ``<properties>``) with
    one ``<testcase>`` per case or record of the suite (``classname`` the suite and the kind, ``name``
    the id, ``time`` seconds spent scoring it, from ``times``; ``file`` and ``line`` of the first
    failure): a ``<failure>`` for a failing one and for a known failure that now passes, an ``<error>``
    for a malformed output, ``<skipped>`` for one not selected and for an expected failure (as pytest
    writes an xfail) -- the layout of the JUnit schema that Jenkins, GitLab and the GitHub test
    reporters read.  ``details(result)``: the lines of a failure's text (:func:`.results_text.details`)."""
    suite = doc["suite"]
    times = times or {}
    details = details or (lambda r: [r["note"]])
    name = _x(f"{suite['name']} {suite['label']} ({doc['scored']})")
    total = sum(times.values())
    attrs = {
        "tests": str(doc["tests"]),
        "failures": str(doc["failed"] + doc["xpassed"]),
        "errors": str(doc["errors"]),
        "time": f"{total:.6f}",
    }
    root = ET.Element("testsuites", {"name": "gear-rattle check", **attrs})
    skipped = str(doc["skipped"] + doc["xfailed"])
    ts = ET.SubElement(root, "testsuite", {"name": name, **attrs, "skipped": skipped})
    props = ET.SubElement(ts, "properties")
    for key in ("name", "version", "label", "part", "digest", "recorded_digest", "digest_matches", "folder"):
        ET.SubElement(props, "property", {"name": f"suite.{key}", "value": _x(_property(suite.get(key)))})
    ET.SubElement(props, "property", {"name": "source", "value": _x(doc["source"])})
    for key, value in doc.get("selection", {}).items():
        ET.SubElement(props, "property", {"name": f"selection.{key}", "value": _x(_property(value))})
    classname = f"gear-rattle.golden.{doc['scored']}"
    for r in doc["results"]:
        _testcase(ts, r, classname, times.get(r["id"], 0.0), details)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
