"""The tolerance of every row of a golden case (docs/golden_tolerances.md, "Tolerances from the conditioning"):
:data:`SAFETY <.conditioning.SAFETY>` times the error a correct float64 implementation can make at that row
(:func:`.conditioning.row_errors`) plus the row's printed radius (:func:`.conditioning.tolerances`), as
:class:`RowTolerances`.  The same rule for the shipped cases (:mod:`..catalog.build`) and for a case on
demand (:mod:`..oracle.ondemand`, which adds the horizon rule on top).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ....mapimpl import certified as cert
from ..formats.case_writer import certified_rows, printed_rows
from ..formats.cases import ROW_TOLERANCE_COLUMNS, TOLERANCE_COLUMNS
from ..formats.spec import Spec
from . import conditioning

__all__ = ["RADIUS_LIMIT", "RowTolerances", "row_tolerances"]

#: A certified run stops where a ball's radius exceeds this (the shipped cases' balls are below 1e-80; a
#: row's tolerance includes its printed radius).
RADIUS_LIMIT = 1e-15


@dataclass(frozen=True)
class RowTolerances:
    """The absolute tolerance of every row of a certified orbit per tolerance column (NaN where a row has no
    value: ``sdot`` of a stick or release row), from the error a correct float64 implementation can make at
    that row (:func:`conditioning.row_errors`) and the row's printed radius (:func:`conditioning.tolerances`)."""

    values: dict
    errors: conditioning.RowErrors

    def loosest(self) -> dict:
        """``settings.json``'s ``tolerances``: per column the loosest row's ``abs``, ``rel`` 0."""
        return {c: {"abs": float(np.nanmax(self.values[c])), "rel": 0.0} for c in TOLERANCE_COLUMNS}

    def cells(self, row: int) -> list[str]:
        """The row's ``tau_tol, tau_mod_2pi_tol, sdot_tol`` cells of ``expected.csv`` (empty: no value)."""
        return ["" if math.isnan(v) else "%.2g" % v for v in (self.values[c][row] for c in TOLERANCE_COLUMNS)]

    def note(self) -> dict:
        """``notes.tolerances`` of the settings: the rule and, per column, the loosest row (its line of
        ``expected.csv`` and, for the times, the impact whose error contributes most there)."""
        largest = {}
        for c in TOLERANCE_COLUMNS:
            k = int(np.nanargmax(self.values[c]))
            largest[c] = {"tolerance": float(self.values[c][k]), "line": k + 2}
            if c != "sdot":
                largest[c]["from_impact"] = int(self.errors.source[k])
        return {
            "per_row": "expected.csv, columns " + ", ".join(ROW_TOLERANCE_COLUMNS.values()),
            "largest": largest,
            "rule": f"{conditioning.SAFETY:g} x the error a correct float64 implementation can make at the row "
            f"(gap error {conditioning.GAP_ULPS} 2^-52 + {conditioning.FLIGHT_ERROR:g} h max(1, dt / 2 pi) per contact, "
            "carried to the row by the map's Jacobians and summed over the contacts; the representation of "
            "tau and its phase) plus the row's printed radius, rounded up to "
            f"{conditioning.TOLERANCE_DIGITS} digits (docs/golden.md, tolerances from the conditioning)",
        }


def row_tolerances(spec: Spec, orb: cert.CertifiedOrbit) -> RowTolerances:
    """The :class:`RowTolerances` of a certified orbit (its rows and printed radii as ``expected.csv`` has them)."""
    free = None if spec.s0 is None else (spec.tau0, spec.s0, spec.sdot0)
    errors = conditioning.row_errors(spec.params, certified_rows(orb), free)
    radii: dict = {c: [] for c in TOLERANCE_COLUMNS}
    for row in printed_rows(orb):
        for c, r in zip(TOLERANCE_COLUMNS, row[3:]):
            radii[c].append(float(r) if r else math.nan)
    return RowTolerances(conditioning.tolerances(errors, radii), errors)
