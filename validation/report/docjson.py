"""The report's document model as JSON (``document.json``): :func:`document_json` writes the run's
header, each section's status and blocks and the arguments of every row; :func:`sections_from_json`
reads it back, every row judged again by :func:`.verdict.row` (:func:`.builder.rerender`).
Above :mod:`.document` (the model) and :mod:`.verdict` (the rows, built on the model): the model
imports neither, so the three make no circle."""

from __future__ import annotations

import math
from pathlib import Path

from .document import Section
from .verdict import row


#: The ``format`` of ``document.json``; a reader refuses any other.
DOCUMENT_FORMAT = "gear-rattle report document 1"


def _enc(x):
    """A row argument for JSON: numbers as Python numbers (NaN and infinities as the strings "nan",
    "inf", "-inf", so that they come back), pairs as lists, the rest as it is."""
    if isinstance(x, (tuple, list)):
        return [_enc(v) for v in x]
    if x is None or isinstance(x, (bool, str)):
        return x
    if isinstance(x, int) or (hasattr(x, "dtype") and getattr(x.dtype, "kind", "") in "iu"):
        return int(x)
    f = float(x)
    return f if math.isfinite(f) else str(f)


def _dec(x):
    if isinstance(x, list):
        return [_dec(v) for v in x]
    return float(x) if x in ("nan", "inf", "-inf") else x


_NUMERIC_SPEC = ("value", "error", "tolerance", "enclosure")


def document_json(header: dict, sections: list[Section], out_dir: Path) -> dict:
    """The document model for ``document.json``: the run's header, and per section its status, blocks
    (figures by their path relative to ``out_dir``) and the arguments of every row."""
    from ..paper import PAPER

    for s in sections:
        for n in s.numbers:
            if n.paper_value is not None and PAPER.get(n.paper_value.key) is not n.paper_value:
                raise ValueError(
                    f"row {n.key!r} compares with a paper value that is not paper.PAPER[{n.paper_value.key!r}]"
                )

    def block(b):
        if b[0] != "fig":
            return list(b)
        return ["fig", Path(b[1]).resolve().relative_to(out_dir.resolve()).as_posix(), b[2]]

    return {
        "format": DOCUMENT_FORMAT,
        "header": header,
        "sections": [
            {
                "key": s.key,
                "title": s.title,
                "ok": s.ok,
                "error": s.error,
                "seconds": s.seconds,
                "blocks": [block(b) for b in s.blocks],
                "rows": [{k: (_enc(v) if k in _NUMERIC_SPEC else v) for k, v in n.spec.items()} for n in s.numbers],
            }
            for s in sections
        ],
    }


def sections_from_json(data: dict, out_dir: Path) -> tuple[dict, list[Section]]:
    """Read :func:`document_json`'s output back: ``(header, sections)``, every row judged again by
    :func:`.verdict.row` (so a change of the verdict rules or of the page applies without computing)."""
    if not isinstance(data, dict) or data.get("format") != DOCUMENT_FORMAT:
        raise ValueError(
            f"document format={data.get('format') if isinstance(data, dict) else data!r} is not "
            f"known: allowed {DOCUMENT_FORMAT!r}"
        )
    sections = []
    for d in data["sections"]:
        sec = Section(d["key"], d["title"], ok=d["ok"], error=d["error"], seconds=d["seconds"])
        for b in d["blocks"]:
            sec.blocks.append(("fig", str(out_dir / b[1]), b[2]) if b[0] == "fig" else tuple(b))
        for spec in d["rows"]:
            sec.numbers.append(row(**{k: (_dec(v) if k in _NUMERIC_SPEC else v) for k, v in spec.items()}))
        sections.append(sec)
    return data["header"], sections


__all__ = [
    "DOCUMENT_FORMAT",
    "document_json",
    "sections_from_json",
]
