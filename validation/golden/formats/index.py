"""The catalogue of the golden suite: bug classes, levels, and the case index ``cases/index.json``.

Every case says in its ``settings.json`` which **bug classes** it exists to catch (``catches``) and
its **level** (1: the impact map; 2: the sticking policy; 3: hard contacts and orbit endings).  The
index lists, per case, its id, level, tags, bug classes, the walls it touches and the kind of
ending, so another implementation can select the cases it supports (as the SBML test suite's
levels and tags do).  It is generated from the case folders (:func:`build_index`); a test checks
that the committed file matches them.  numpy-free, no interval library.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from .version import INDEX_NAME


#: Bug classes: id -> what an implementation with that bug does wrong.
BUG_CLASSES: dict[str, str] = {
    "flight-or-impact-law": "a wrong flight (Eqs. 7-8), impact law (Eq. 11) or event bookkeeping in general",
    "float64-drift": "event times located too loosely (e.g. to 1e-9): errors amplified along a chaotic orbit "
    "leave the tolerance",
    "cancellation": "the printed Eq. (7) evaluated as it stands: gamma/beta^2 cancellations for small beta",
    "free-flight-start": "a start in free flight handled as a pre-impact state (impact 0 not searched)",
    "lower-wall-conventions": "wall code or velocity sign wrong on the lower wall s = -1, or gamma < 0 mishandled",
    "return-to-start-wall": "a flight that returns to the wall it left is missed or tunnels through",
    "skipped-graze": "a finder that samples the flight (fixed-step sign change) misses a short excursion beyond "
    "a wall: every step from 1e-3 to 1 misses one of the grazes",
    "contact-tolerance": "a contact accepted where the gap is below a tolerance (near misses at 2e-7, 1e-9, 1e-11)",
    "release-departure": "the t^3 trap: a spurious impact (or a spurious row) right after a release",
    "sticking-threshold": "the accumulation time t_acc or its threshold STICK_TIME wrong (scaled by 0.99 .. 1.5)",
    "release-delay": "the condition 'release delay > t_acc' ignored: a chatter that must bounce sticks",
    "lower-wall-sticking": "sticking on s = -1 missing, with the wrong pressing sign, or released on the wrong "
    "branch of the contact force's zeros",
    "stuck-forever": "the never-release condition |gamma| >= R on the pressing side tested on the wrong side",
    "elastic-r1": "r = 1 mishandled (e.g. a safe division (1 - r) f_in = 0 -> t_acc = 0: every pressing impact sticks)",
    "no-impact-ending": "rows invented (a placeholder or an impact at the search horizon) or dropped when the "
    "last flight never lands",
    "trailing-rows": "stick/release rows written for the impact after the last counted one",
}

#: Levels: what an implementation must support to run a case.
LEVELS: dict[int, str] = {
    1: "the impact map: flights, impacts and wall conventions; every impact bounces",
    2: "the sticking policy: stick, release and stuck_forever rows, and its decisions",
    3: "hard contacts and endings: grazes, near misses (finder robustness) and orbits that end with no_impact",
}

#: Kinds of ending of a case (``expected_status`` ``active`` means the orbit reached ``n_impacts``).
ENDINGS = {"active": "n_impacts", "stuck_forever": "stuck_forever", "no_impact": "no_impact"}


def case_entry(folder: Path, inside: Path | None = None) -> dict:
    """The index entry of one case folder (its ``settings.json`` and ``expected.csv`` read and checked as
    ``check`` reads them, :func:`.cases.load_case`, inside the folder ``inside``)."""
    from .cases import load_case

    case = load_case(folder, inside)
    settings, exp = case.settings, case.expected
    impact_walls = sorted({int(w) for w, k in zip(exp.wall, exp.kind) if k == "impact"}, reverse=True)
    stick_walls = sorted({int(w) for w, k in zip(exp.wall, exp.kind) if k == "stick"}, reverse=True)
    if case.row_tol is not None:  # the smallest tolerance of any row (docs/reference/golden_formats.md, "File formats")
        tol = min(float(x) for v in case.row_tol.values() for x in v if math.isfinite(x))
    else:
        tol = min(v["abs"] for v in settings["tolerances"].values())
    return {
        "id": settings["id"],
        "level": settings.get("level"),
        "tags": settings.get("tags", []),
        "catches": settings.get("catches", []),
        "walls": impact_walls,
        "stick_walls": stick_walls,
        "ending": ENDINGS[settings["expected_status"]],
        "rows": settings["expected_rows"],
        "n_impacts": settings["n_impacts"],
        "tolerance": tol,
    }


def case_folders(suite: Path, overlay: dict[str, Path] | None = None) -> dict[str, Path]:
    """``{id: folder}`` of the suite's cases (:func:`.cases.case_ids`), those of ``overlay``
    (``{"<id>/<file>": file}``: cases about to be moved in) from where they wait."""
    from .cases import case_ids

    folders = {cid: Path(suite) / cid for cid in case_ids(suite)}
    for rel, f in (overlay or {}).items():
        if "/" in rel:
            folders[rel.split("/")[0]] = Path(f).parent
    return folders


def build_index(suite: Path, overlay: dict[str, Path] | None = None) -> dict:
    """The index of every case folder under ``suite`` (sorted by id); with ``overlay`` (``{relative path:
    file}``) the index the suite will have once those files are moved in."""
    from .version import suite_block

    folders = case_folders(suite, overlay)
    return {
        "format": "gear-rattle golden suite index, version 1",
        "suite": suite_block(suite, overlay),
        "fields": {
            "level": "1, 2 or 3 (see levels)",
            "tags": "situations the case exercises",
            "catches": "bug classes the case exists to catch (see bug_classes)",
            "walls": "walls with impact rows (0 upper s = 0, -1 lower s = -1)",
            "stick_walls": "walls with stick rows",
            "ending": "n_impacts (reached), stuck_forever or no_impact",
            "rows": "rows of expected.csv",
            "n_impacts": "impacts to compute after impact 0",
            "tolerance": "smallest absolute tolerance of any row of the case",
        },
        "levels": {str(k): v for k, v in LEVELS.items()},
        "bug_classes": BUG_CLASSES,
        "cases": [case_entry(folders[cid], folders[cid].parent) for cid in sorted(folders)],
    }


def index_text(suite: Path) -> str:
    return json.dumps(build_index(suite), indent=1) + "\n"


def write_index(suite: Path) -> Path:
    """Write ``suite/index.json`` from the case folders; returns its path."""
    path = Path(suite) / INDEX_NAME
    path.write_text(index_text(suite))
    return path
