"""What ``gear-rattle check`` reports: the aligned text table, the summary line, the JSON document and
the JUnit XML file (docs/golden.md, "Using the suite in CI").

Each scored case or orbit record becomes one plain result (:func:`case_result`, :func:`orbit_result`):
``id``, ``level``, ``passed``, ``digits`` per column, ``worst_over_tolerance`` (the largest
``|error| / tolerance`` over the scored values: < 1 passes) and ``first_failing`` (where the first
failure is: a file line and column for a case, a column for an orbit record), with the ``note`` of
the table.  The reports are built from those results only, so the impact cases and the orbit
records share them (the scores, columns and levels come from :mod:`.suite` and :mod:`.orbit_suite`;
numpy and the standard library only, as the light install has).
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

# The columns and levels are the scorers' own (one definition each): the tolerance columns, the exact
# columns of a case; the columns and the level of an orbit record.
from .orbit_suite import COLUMNS as ORBIT_COLUMNS, LEVEL as ORBIT_LEVEL
from .suite import EXACT_COLUMNS, TOLERANCE_COLUMNS as CASE_COLUMNS

#: The JSON document's format name.
FORMAT = "gear-rattle check results, version 1"


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def _case_worst_over_tolerance(score) -> float | None:
    """The largest ``|error| / tolerance`` over the tolerance columns (each row against its own
    tolerance); None where not comparable (a wrong number of events)."""
    if not score.columns:
        return None
    return max((score.columns[c].worst_ratio for c in CASE_COLUMNS if c in score.columns), default=0.0)


def case_result(case, score) -> dict:
    """The result of one impact case (``case``: :class:`suite.Case`, ``score``: :class:`suite.CaseScore`)."""
    level = getattr(score, "level", None) or case.settings.get("level")
    cols = score.columns
    return {
        "id": score.case,
        "level": level,
        "passed": bool(score.passed),
        "digits": {c: (_finite(cols[c].digits) if c in cols else None) for c in CASE_COLUMNS},
        "exact_columns_match": bool(cols) and all(c in cols and cols[c].passed for c in EXACT_COLUMNS),
        "worst_over_tolerance": _finite(_case_worst_over_tolerance(score)),
        "first_failing": None if score.passed else score.first_failing,
        "note": score.message,
    }


def orbit_result(record, score) -> dict:
    """The result of one orbit record (:class:`orbit_suite.Record`, :class:`orbit_suite.OrbitScore`)."""
    cols = score.columns
    ratios = [c.error / max(c.tolerance, 1e-300) for c in cols.values()]
    bad = [c for c in ORBIT_COLUMNS if c in cols and not cols[c].passed]
    return {
        "id": score.id,
        "level": getattr(score, "level", None) or ORBIT_LEVEL,
        "passed": bool(score.passed),
        "digits": {c: (_finite(cols[c].digits) if c in cols else None) for c in ORBIT_COLUMNS},
        "worst_over_tolerance": _finite(max(ratios)) if ratios else None,
        "first_failing": None if score.passed else ({"column": bad[0]} if bad else None),
        "note": score.message,
    }


def malformed_result(id_: str, level: int | None, problem: str | None, orbits: bool = False) -> dict:
    """The result of a case or record when output files are malformed (exit status 2): its own file's
    problem (``problem``, one line naming file, line and column) is an error; where its file was read
    but another was malformed (``problem`` None) it is not scored."""
    cols = ORBIT_COLUMNS if orbits else CASE_COLUMNS
    out = {
        "id": id_,
        "level": level or (ORBIT_LEVEL if orbits else None),
        "passed": False,
        "digits": {c: None for c in cols},
    }
    if not orbits:
        out["exact_columns_match"] = False
    out.update(
        {
            "worst_over_tolerance": None,
            "first_failing": None,
            "malformed": problem is not None,
            "note": problem if problem is not None else "not scored: other output files are malformed",
        }
    )
    return out


# ------------------------------------------------------------------------------------------ text


def aligned(rows: list[list[str]], right: set[int]) -> list[str]:
    """Lines of ``rows`` (the first is the header) in columns as wide as their widest cell, two spaces
    apart (columns in ``right`` right-aligned; the last column is not padded)."""
    widths = [max(len(r[k]) for r in rows) for k in range(len(rows[0]))]
    out = []
    for r in rows:
        cells = [
            c.rjust(w) if k in right else (c if k == len(r) - 1 else c.ljust(w))
            for k, (c, w) in enumerate(zip(r, widths))
        ]
        out.append("  ".join(cells).rstrip())
    return out


def _digits_cell(d: float | None) -> str:
    return "-" if d is None else f"{d:.1f}"


def table(results: list[dict], orbits: bool = False) -> list[str]:
    """The table's lines: header, rule, one line per result (columns aligned for any id length)."""
    cols = ORBIT_COLUMNS if orbits else CASE_COLUMNS
    names = {"tau_mod_2pi": "tau%2pi", "multipliers": "mult"}
    head = ["orbit / bifurcation point" if orbits else "case", "result", *(names.get(c, c) for c in cols)]
    head += ["note"] if orbits else ["n/wall/kind", "note"]
    rows = [head]
    for r in results:
        row = [r["id"], "PASS" if r["passed"] else "FAIL", *(_digits_cell(r["digits"][c]) for c in cols)]
        if not orbits:
            row.append("ok" if r["exact_columns_match"] else "MISMATCH")
        rows.append(row + [r["note"]])
    lines = aligned(rows, right=set(range(2, 2 + len(cols))))
    return [lines[0], "-" * len(lines[0])] + lines[1:]


def summary_line(results: list[dict], orbits: bool = False, suite: str = "") -> str:
    """``N/M cases pass (suite ...; digits ...)``, and the failing ids: ``; failing: a, b`` (``suite``:
    the suite's version label, so that ``--summary`` alone says what was scored against)."""
    n_pass = sum(r["passed"] for r in results)
    what = "orbits and bifurcation points" if orbits else "cases"
    scale = (
        "min over values of -log10 of the error relative to the scale"
        if orbits
        else "min over rows of -log10 relative error"
    )
    line = f"{n_pass}/{len(results)} {what} pass ({f'golden suite {suite}; ' if suite else ''}digits: {scale}, capped at 17)"
    failing = [r["id"] for r in results if not r["passed"]]
    return line + (f"; failing: {', '.join(failing)}" if failing else "")


# ------------------------------------------------------------------------------------------ files


def document(results: list[dict], suite: dict, *, orbits: bool, source: str) -> dict:
    """The JSON document of ``--json``: the format, the suite (name, version, digests), what was
    scored (``source``: the output directory or our own track), the counts and the results."""
    errors = sum(bool(r.get("malformed")) for r in results)
    return {
        "format": FORMAT,
        "suite": suite,
        "scored": "orbits" if orbits else "cases",
        "source": source,
        "tests": len(results),
        "passed": sum(r["passed"] for r in results),
        "failed": sum(not r["passed"] for r in results) - errors,
        "errors": errors,
        "results": results,
    }


#: Characters XML 1.0 does not allow (a file name may hold them): replaced by U+FFFD in the JUnit file.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _x(text: str) -> str:
    return _NOT_XML.sub("\ufffd", text)


def _failure_text(r: dict) -> str:
    digits = ", ".join(f"{c} {_digits_cell(d)}" for c, d in r["digits"].items())
    lines = [r["note"], f"digits: {digits}"]
    if r["worst_over_tolerance"] is not None:
        lines.append(f"worst |error| / tolerance: {r['worst_over_tolerance']:.3g}")
    if r["first_failing"]:
        lines.append("first failing: " + ", ".join(f"{k} {v}" for k, v in r["first_failing"].items()))
    return "\n".join(lines)


def junit_xml(doc: dict, times: dict | None = None) -> str:
    """The JUnit XML text of ``--junit-xml`` for a :func:`document`: ``<testsuites>`` holding one
    ``<testsuite>`` (the suite's name, version and digests as ``<properties>``) with one ``<testcase>``
    per case or record (``classname`` the suite and the kind, ``name`` the id, ``time`` seconds spent
    scoring it, from ``times``) and a ``<failure message type>`` holding the note and the digits for
    each failing one -- the layout of the JUnit schema that Jenkins, GitLab and the GitHub test
    reporters read."""
    suite = doc["suite"]
    times = times or {}
    name = _x(f"{suite['name']} {suite['label']} ({doc['scored']})")
    total = sum(times.values())
    attrs = {
        "tests": str(doc["tests"]),
        "failures": str(doc["failed"]),
        "errors": str(doc.get("errors", 0)),
        "time": f"{total:.6f}",
    }
    root = ET.Element("testsuites", {"name": "gear-rattle check", **attrs})
    ts = ET.SubElement(root, "testsuite", {"name": name, **attrs, "skipped": "0"})
    props = ET.SubElement(ts, "properties")
    for key in ("name", "version", "label", "part", "digest", "recorded_digest", "digest_matches", "folder"):
        ET.SubElement(props, "property", {"name": f"suite.{key}", "value": _x(str(suite.get(key)))})
    ET.SubElement(props, "property", {"name": "source", "value": _x(doc["source"])})
    classname = f"gear-rattle.golden.{doc['scored']}"
    for r in doc["results"]:
        tc = ET.SubElement(
            ts, "testcase", {"classname": classname, "name": _x(r["id"]), "time": f"{times.get(r['id'], 0.0):.6f}"}
        )
        if r.get("malformed"):
            e = ET.SubElement(tc, "error", {"message": _x(r["note"]), "type": "golden.malformed"})
            e.text = _x(r["note"])
        elif not r["passed"]:
            f = ET.SubElement(tc, "failure", {"message": _x(r["note"] or "failed"), "type": "golden.mismatch"})
            f.text = _x(_failure_text(r))
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
