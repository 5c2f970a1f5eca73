"""The file of the crisis analyses (:mod:`gear_rattle.validation.dynamics.crises`): ``crises.json`` with
every scan row, bracket, fit and their cost (impacts, wall and CPU seconds per engine run) of r2, r1 and
alpha1 (each result's ``as_dict()``)."""

from __future__ import annotations

from pathlib import Path

from .formats import write_json
from .transients import out_dir


def write_crises(outdir, profile: str, r2, r1, a1) -> list[Path]:
    """``crises.json`` in ``outdir`` (created)."""
    return [
        write_json(
            out_dir(outdir) / "crises.json",
            {"profile": profile, "r2": r2.as_dict(), "r1": r1.as_dict(), "alpha1": a1.as_dict()},
        )
    ]


__all__ = [
    "write_crises",
]
