"""The JUnit XML file of ``gear-rattle check --junit-xml`` (docs/reference/golden_commands.md, "In CI"), written
from a typed run (:class:`.results.CheckRun`): ``<testsuites>`` holding one ``<testsuite>`` with one
``<testcase>`` per case or record of the suite -- the layout of the JUnit schema that Jenkins, GitLab and
the GitHub test reporters read.  Standard library only.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

from .results import CheckRun, Result
from .text_report import details

__all__ = ["xml_text", "junit_xml"]

#: Characters XML 1.0 does not allow (a file name may hold them): replaced by U+FFFD in the JUnit file.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def xml_text(text: str) -> str:
    """``text`` with the characters XML 1.0 does not allow replaced by U+FFFD (a file name may hold them)."""
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


def _testcase(ts: ET.Element, r: Result, classname: str, time: float) -> None:
    """One ``<testcase>``: a failing one holds ``<failure>`` (its message the note, its text the
    details), an erring one ``<error>``, a skipped one or a known failure ``<skipped>``; ``file`` and
    ``line`` name the output file and line of the first failure, where there is one."""
    attrs = {"classname": classname, "name": xml_text(r.id), "time": f"{time:.6f}"}
    first = r.first_failing
    if r.verdict in ("fail", "error", "xfail") and first is not None and first.file:
        attrs["file"] = xml_text(first.file)
        if first.line is not None:
            attrs["line"] = str(first.line)
    tc = ET.SubElement(ts, "testcase", attrs)
    v = r.verdict
    note = xml_text(r.note or v)
    kind = first.kind if first is not None else None
    if v in ("fail", "xpass"):
        el = ET.SubElement(
            tc, "failure", {"message": note, "type": f"golden.{'xpass' if v == 'xpass' else kind or 'mismatch'}"}
        )
        el.text = xml_text("\n".join(details(r)))
    elif v == "error":
        el = ET.SubElement(tc, "error", {"message": note, "type": f"golden.{kind or 'malformed'}"})
        el.text = xml_text("\n".join(details(r)))
    elif v in ("skipped", "xfail"):
        el = ET.SubElement(tc, "skipped", {"message": note, "type": f"golden.{v}"})
        if v == "xfail":
            el.text = xml_text("\n".join(details(r)))


def junit_xml(run: CheckRun) -> str:
    """The JUnit XML text of a run: ``<testsuites>`` holding one ``<testsuite>`` (the suite's name, version
    and digests, and the selection, as ``<properties>``) with one ``<testcase>`` per case or record of the
    suite (``classname`` the suite and the kind, ``name`` the id, ``time`` seconds spent scoring it;
    ``file`` and ``line`` of the first failure): a ``<failure>`` for a failing one and for a known failure
    that now passes, an ``<error>`` for a malformed output, ``<skipped>`` for one not selected and for an
    expected failure (as pytest writes an xfail); the text of a failure is its details
    (:func:`.text_report.details`)."""
    info, n = run.suite, run.counts()
    name = xml_text(f"{info.name} {info.label} ({run.scored})")
    total = sum(run.times.values())
    attrs = {
        "tests": str(n["tests"]),
        "failures": str(n["failed"] + n["xpassed"]),
        "errors": str(n["errors"]),
        "time": f"{total:.6f}",
    }
    root = ET.Element("testsuites", {"name": "gear-rattle check", **attrs})
    skipped = str(n["skipped"] + n["xfailed"])
    ts = ET.SubElement(root, "testsuite", {"name": name, **attrs, "skipped": skipped})
    props = ET.SubElement(ts, "properties")
    suite = {
        "name": info.name,
        "version": info.version,
        "label": info.label,
        "part": info.part,
        "digest": info.digest,
        "recorded_digest": info.recorded_digest,
        "digest_matches": info.matches,
        "folder": str(info.folder),
    }
    for key, value in suite.items():
        ET.SubElement(props, "property", {"name": f"suite.{key}", "value": xml_text(_property(value))})
    ET.SubElement(props, "property", {"name": "source", "value": xml_text(run.source)})
    for key, value in run.selection.as_dict().items():
        ET.SubElement(props, "property", {"name": f"selection.{key}", "value": xml_text(_property(value))})
    classname = f"gear-rattle.golden.{run.scored}"
    for r in run.results:
        _testcase(ts, r, classname, run.times.get(r.id, 0.0))
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
