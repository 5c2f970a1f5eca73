"""How much of each documentation page is measurement narrative: the share of its lines that sit in
paragraphs carrying a date, a machine load, a commit or an issue number of this project.

    python .ci/docs_narrative.py [PAGE.md ...]     # default: README.md and every page of docs/

A paragraph is a run of non-blank lines (a fenced code block is one paragraph, searched like the
rest); the share is the paragraph's non-blank lines over the page's non-blank lines.  Inline code
(`...`) is left out of the search, so that an example message that prints a time stamp is not a
date of the page.  The markers:

* a date: ``2026-11-24`` (any ``20YY-MM``), or the month written ``Nov``/``November``;
* a machine load: ``load 7``, ``load average 13-15``, ``load average ~5``, ``machine otherwise idle``,
  ``shared with other work`` / ``with ~7 other jobs``;
* a commit: a word of 7-40 hexadecimal digits with a digit and a letter (``a8c2cf5``; not the digits
  after a decimal point, as in ``1.4858389142989202e-06``), or ``commit`` followed by 7-40 hexadecimal
  digits (``commit 1252113``);
* an issue number of this project: ``issue 12``, ``issues 10``; another project's issue (``scipy issue
  9228``) is a citation, not history.

tests/test_docs_layout.py holds the pages outside docs/record/ (the validation record) to zero.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

DATE = re.compile(r"\b20\d\d-[01]\d\b|\bNov(?:ember)?\b")
LOAD = re.compile(
    r"\bload(?: average)?s?\s+(?:of\s+)?~?\d|\botherwise idle\b|\bmachine idle\b"
    r"|\bshared with (?:~?\d+ )?other (?:work|jobs)\b",
    re.I,
)
COMMIT = re.compile(r"(?<!\.)\b(?=[0-9a-f]*\d)(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}\b|\bcommits? [0-9a-f]{7,40}\b")
ISSUE = re.compile(r"(\w+\s+)?\bissues? \d+", re.I)
OTHER_PROJECTS = ("scipy", "diffrax", "jax", "numpy", "xla", "zarr", "dask")
INLINE_CODE = re.compile(r"(`+)(?:(?!\1).)+?\1", re.S)


def markers(text: str) -> list[str]:
    """The kinds of marker (``date``, ``load``, ``commit``, ``issue``) found in ``text``."""
    prose = INLINE_CODE.sub(" ", text)
    found = [name for name, rx in (("date", DATE), ("load", LOAD), ("commit", COMMIT)) if rx.search(prose)]
    for m in ISSUE.finditer(prose):
        before = (m.group(1) or "").strip().lower().rstrip("'s")
        if before not in OTHER_PROJECTS:
            found.append("issue")
            break
    return found


def paragraphs(text: str) -> list[list[str]]:
    """The page's paragraphs: runs of non-blank lines; a fenced code block is one, blank lines included."""
    out: list[list[str]] = []
    cur: list[str] = []
    fence = None
    for line in text.splitlines():
        stripped = line.strip()
        if fence is not None:
            cur.append(line)
            if stripped.startswith(fence):
                fence = None
            continue
        if stripped.startswith(("```", "~~~")):
            fence = stripped[:3]
            cur.append(line)
        elif stripped:
            cur.append(line)
        elif cur:
            out.append(cur)
            cur = []
    if cur:
        out.append(cur)
    return out


def share(text: str) -> tuple[int, int]:
    """(narrative lines, non-blank lines) of a page."""
    total = sum(1 for ln in text.splitlines() if ln.strip())
    narrative = sum(sum(1 for ln in p if ln.strip()) for p in paragraphs(text) if markers("\n".join(p)))
    return narrative, total


def narrative_paragraphs(text: str) -> list[tuple[list[str], str]]:
    """The paragraphs that carry a marker, each with its first line (to name it in a message)."""
    return [(markers("\n".join(p)), p[0].strip()) for p in paragraphs(text) if markers("\n".join(p))]


#: What a command or the docs build writes: not pages of the docs' prose
GENERATED = ("docs/report/", "docs/_build/", "docs/api/generated/", "docs/reference/commands.md")


def default_pages() -> list[Path]:
    """README.md and every page of docs/, the generated ones left out."""
    pages = [p for p in (ROOT / "docs").rglob("*.md") if not str(p.relative_to(ROOT)).startswith(GENERATED)]
    return [ROOT / "README.md"] + sorted(pages)


def main(argv: list[str]) -> int:
    pages = [Path(a) for a in argv] or default_pages()
    n_all = t_all = 0
    print(f"{'page':40s} {'lines':>6s} {'narrative':>9s} {'share':>6s}")
    for page in pages:
        n, t = share(page.read_text(encoding="utf-8"))
        n_all, t_all = n_all + n, t_all + t
        name = str(page.resolve().relative_to(ROOT)) if page.resolve().is_relative_to(ROOT) else str(page)
        print(f"{name:40s} {t:6d} {n:9d} {100 * n / max(t, 1):5.1f}%")
    print(f"{'all':40s} {t_all:6d} {n_all:9d} {100 * n_all / max(t_all, 1):5.1f}%")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
