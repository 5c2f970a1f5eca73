"""The documentation is ordered by what a reader needs: quick starts first, then how-to guides,
reference, explanation, and the measurements apart in the validation record (docs/record/).

A page outside the record states what holds and links the record entry that measured it: no paragraph
of it carries a date, a machine load, a commit or an issue number (.ci/docs_narrative.py measures
that share per page).  Each record entry has its date, commit and machine, and is linked from a page."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("docs_narrative", ROOT / ".ci" / "docs_narrative.py")
dn = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(dn)

LABEL = re.compile(r"^\((record-[\w-]+)\)=$", re.M)


def _pages() -> list[Path]:
    return dn.default_pages()


def _prose_pages() -> list[Path]:
    return [p for p in _pages() if not str(p.relative_to(ROOT)).startswith("docs/record/")]


@pytest.mark.parametrize("page", _prose_pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_no_measurement_narrative_outside_the_record(page):
    found = dn.narrative_paragraphs(page.read_text(encoding="utf-8"))
    assert not found, (
        f"{page.relative_to(ROOT)}: paragraphs with a date, a load, a commit or an issue number (move the "
        f"measurement to docs/record/ and link it): " + "; ".join(f"{m} in '{first[:60]}'" for m, first in found)
    )


def test_the_narrative_measure_catches_what_it_is_for():
    assert dn.markers("Measured on 2026-11-24, idle.") == ["date"]
    assert dn.markers("(2-core machine, load average 13-15)") == ["load"]
    assert dn.markers("the machine otherwise idle") == ["load"]
    assert dn.markers("the code of a8c2cf5 gave") == ["commit"]
    assert dn.markers("alternating with commit 1252113") == ["commit"]
    assert dn.markers("issue 12 asks for 60 s") == ["issue"]
    assert dn.markers("(scipy issue 9228, diffrax issue 507)") == []
    assert dn.markers("a lock `held since 2026-11-27T11:40:02Z` by pid 4242") == []
    assert dn.markers("1e-3, 0.5 ulps, 4096 points, deadbeef") == []
    assert dn.markers("sdot 1.4858389142989202e-06, 4.880376939265131") == []  # a float's digits, not a commit
    text = "one\n\nmeasured 2026-11-24\nacross two lines\n\n```bash\nx\n\ny\n```\n"
    assert dn.share(text) == (2, 7)


def _entries() -> list[tuple[Path, str, str]]:
    """(page, label, the entry's text up to the next label) of every record entry."""
    out = []
    for page in sorted((ROOT / "docs" / "record").glob("*.md")):
        text = page.read_text(encoding="utf-8")
        marks = list(LABEL.finditer(text))
        for m, nxt in zip(marks, marks[1:] + [None]):
            out.append((page, m.group(1), text[m.end() : nxt.start() if nxt else len(text)]))
    return out


def test_record_entries_say_when_what_and_where():
    entries = _entries()
    assert len(entries) >= 20
    labels = [label for _, label, _ in entries]
    assert len(labels) == len(set(labels)), "a record label used twice"
    for page, label, body in entries:
        heading, _, rest = body.strip().partition("\n")
        meta = rest.strip().split("\n\n")[0]
        where = f"{page.relative_to(ROOT)}: {label}"
        assert heading.startswith("## "), f"{where}: a label stands before its heading"
        assert meta.startswith("*") and meta.endswith("*"), f"{where}: no metadata line after the heading"
        assert "ommit" in meta, f"{where}: the metadata names no commit (or says it is not recorded)"
        assert re.search(r"load|idle|machine|core", meta), f"{where}: the metadata names no machine or load"
        dated = re.match(r"## 20\d\d-\d\d-\d\d", heading)
        assert dated or "engine by engine" in heading, f"{where}: the heading has no date"
        if dated:
            assert dated.group(0)[3:] in label, f"{where}: the label does not carry the entry's date"


def test_every_record_entry_is_linked_from_a_page():
    prose = "".join(p.read_text(encoding="utf-8") for p in _prose_pages())
    orphans = [label for _, label, _ in _entries() if label not in prose]
    assert not orphans, f"record entries that no page links: {orphans}"


def test_quick_starts_come_first():
    index = (ROOT / "docs" / "index.md").read_text(encoding="utf-8")
    captions = re.findall(r"^:caption: (.+)$", index, re.M)
    assert captions[0] == "Quick starts" and captions[1:4] == ["How-to guides", "Reference", "Explanation"]
    first_toctree = index.split("```{toctree}")[1]
    assert re.findall(r"<(start/\w+)>", first_toctree) == ["start/reproduce", "start/extend", "start/ci"]
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    after_commands = readme[readme.index("**Tests**") :]
    first_links = re.findall(r"\]\((docs/[^)#]+)", after_commands)[:3]
    assert first_links == ["docs/start/reproduce.md", "docs/start/extend.md", "docs/start/ci.md"], first_links


def test_every_page_is_in_a_toctree():
    """Sphinx warns (an error under -W) about a page no toctree lists; this says it without Sphinx."""
    listed = set()
    for index in ROOT.glob("docs/**/index.md"):
        for block in index.read_text(encoding="utf-8").split("```{toctree}")[1:]:
            for entry in re.findall(r"^(?:.*<)?([\w/]+)>?$", block.split("```")[0], re.M):
                listed.add((index.parent / entry).resolve().relative_to(ROOT).as_posix())
    pages = {p.relative_to(ROOT).with_suffix("").as_posix() for p in _pages() if p.parent != ROOT}
    generated = {"docs/reference/commands"}  # generated at build, listed too
    assert pages - listed - {"docs/index"} == set()
    assert generated <= listed


def test_the_conventions_list_every_status():
    from gear_rattle.core.status import FlightOutcome, Status

    text = (ROOT / "docs" / "reference" / "conventions.md").read_text(encoding="utf-8")
    for s in Status:
        row = f"| `{s.label}` | {s.value} | "
        assert row in text, f"docs/reference/conventions.md: no row {row!r}"
        assert f"| {'yes' if s.ok else 'no'} |" in text.split(row)[1].split("\n")[0]
    for f in FlightOutcome:
        assert f"`{f.label}`" in text
