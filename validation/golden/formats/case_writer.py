"""The files of a certified case, written (docs/reference/golden_formats.md, "File formats"): ``expected.csv`` (the rows, their
printed radii and tolerances: :func:`expected_csv`), ``settings.json`` (:func:`settings_json`) and
``provenance.json`` (:func:`provenance_json`, :func:`radius_stats`), and a case folder (:func:`write_case`).

A certified value is printed as the float64 nearest to its ball, with a rigorous bound of ``|printed -
true|`` (:func:`printed_rows`); :func:`certified_rows` gives the printed rows as a
:class:`.cases.Sequence`, on which the tolerance rules (:mod:`..rules`) work.  Deterministic: the same
software writes byte-identical files.  The catalogue (``python -m gear_rattle.validation.golden.generate``)
and the oracle (``gear-rattle case``) write through this module.
"""

from __future__ import annotations

import json
import math
import platform
from pathlib import Path
from typing import Callable, Protocol

import numpy as np
from flint import arb

from ....mapimpl import certified as cert
from .cases import COLUMNS, RADIUS_COLUMNS, ROW_TOLERANCE_COLUMNS, ROW_TOLERANCES_POINTER, Sequence
from .spec import Spec

__all__ = [
    "RowCells",
    "printed_rows",
    "certified_rows",
    "expected_csv",
    "settings_json",
    "provenance_json",
    "radius_stats",
    "write_plain",
    "write_case",
]


class RowCells(Protocol):
    """What the writer needs of a case's tolerances (:class:`..rules.tolerances.RowTolerances`): each row's
    tolerance cells of ``expected.csv`` and the loosest per column, for ``settings.json``."""

    def cells(self, row: int) -> list[str]: ...

    def loosest(self) -> dict: ...


def certified_rows(orb: cert.CertifiedOrbit) -> Sequence:
    """The rows of a certified orbit as printed in ``expected.csv`` (float64 nearest to each ball)."""
    ev = orb.events
    return Sequence(
        "<certified>",
        np.array([e.n for e in ev]),
        np.array([cert.nearest_float(e.tau) for e in ev]),
        np.array([cert.nearest_float(e.theta) for e in ev]),
        np.array([e.wall for e in ev]),
        np.array([math.nan if e.sdot is None else cert.nearest_float(e.sdot) for e in ev]),
        np.array([e.kind for e in ev], dtype=object),
    )


def _g(x: float) -> str:
    return "%.17g" % x


def _radius(x: float) -> str:
    """Upper bound with 3 significant digits (never below ``x``)."""
    return "%.2e" % (x * 1.01) if x > 0 else "0"


def printed_value(ball: arb) -> tuple[float, float]:
    """The float64 to print and a rigorous bound of ``|printed - true|`` (ball radius + rounding)."""
    x = cert.nearest_float(ball)
    err = abs(arb(x) - ball)
    return x, 0.0 if err.is_zero() else cert.upper_float(err)


def printed_rows(orb: cert.CertifiedOrbit) -> list[tuple[str, str, str, str, str, str]]:
    """Per event the printed ``tau, tau_mod_2pi, sdot`` and their radii (``""``: no velocity)."""
    out = []
    for e in orb.events:
        tau, rt = printed_value(e.tau)
        th, rth = printed_value(e.theta)
        if e.sdot is None:
            sd, rsd = "", ""
        else:
            v, r = printed_value(e.sdot)
            sd, rsd = _g(v), _radius(r)
        out.append((_g(tau), _g(th), sd, _radius(rt), _radius(rth), rsd))
    return out


def expected_csv(orb: cert.CertifiedOrbit, tols: RowCells) -> str:
    """``expected.csv``: the rows, their radii and their tolerances (docs/reference/golden_formats.md, "File formats")."""
    lines = [",".join(COLUMNS + RADIUS_COLUMNS + tuple(ROW_TOLERANCE_COLUMNS.values()))]
    for k, (e, (tau, th, sd, rt, rth, rsd)) in enumerate(zip(orb.events, printed_rows(orb))):
        lines.append(",".join([str(e.n), tau, th, str(e.wall), sd, e.kind, rt, rth, rsd, *tols.cells(k)]))
    return "\n".join(lines) + "\n"


def settings_json(spec: Spec, orb: cert.CertifiedOrbit, tols: RowCells) -> dict:
    p = spec.params
    ini = (
        {"kind": "pre-impact", "tau0": spec.tau0, "sdot0": spec.sdot0}
        if spec.s0 is None
        else {"kind": "free-flight", "tau0": spec.tau0, "s0": spec.s0, "sdot0": spec.sdot0}
    )
    return {
        "id": spec.id,
        "description": spec.description,
        "tags": list(spec.tags),
        "level": spec.level,
        "catches": list(spec.catches),
        "params": p.as_dict(),
        "initial_state": ini,
        "n_impacts": spec.n_impacts,
        "stick_time": spec.stick_time,
        "expected_rows": len(orb.events),
        "expected_status": orb.status,
        "tolerances": tols.loosest(),
        "row_tolerances": ROW_TOLERANCES_POINTER,
        "exact_columns": ["n", "wall", "kind"],
        "notes": dict(spec.notes),
    }


def _versions() -> dict:
    import flint
    import numpy
    import scipy
    import jax

    from ....core.jax_config import xla_tuning_active

    return {
        "python": ".".join(platform.python_version_tuple()[:2]),
        "python-flint": flint.__version__,
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "jax": jax.__version__,
        "engine_xla_options": xla_tuning_active(),
    }


def provenance_json(spec: Spec, orb: cert.CertifiedOrbit, radii: dict, agreement: dict | None) -> dict:
    rows = []
    fl = {f["impact"]: f for f in orb.flights}
    for k, e in enumerate(orb.events):
        r = {"line": k + 2, "n": e.n, "kind": e.kind, "source": e.note.get("source", "")}
        if e.kind == "impact" and e.n in fl and e.note.get("source") == "certified flight":
            f = fl[e.n]
            r.update(
                {
                    "wall": f["wall"],
                    "root_bracket": ["%.6g" % f["bracket"][0], "%.6g" % f["bracket"][1]],
                    "positive_gap_pieces": f["pieces"],
                    "departure": "%.3g" % f["departure"],
                }
            )
        if e.kind == "release":
            r["pressing_pieces"] = e.note.get("pieces")
        rows.append(r)
    return {
        "id": spec.id,
        "generator": "python -m gear_rattle.validation.golden.generate",
        "method": {
            "impacts": "certified: ball arithmetic (python-flint arb) on the closed-form flight, Eqs. (7)-(8); "
            "(a) unique root: sign change of the gap and derivative enclosure excluding 0 on the root "
            "bracket; (b) no earlier wall contact: [0, t_lo] covered by pieces on which both gap "
            "enclosures are > 0; states propagated impact to impact as balls (mean-value form with the "
            "analytic Jacobian, intersected with the direct enclosure). The certified track: "
            "mapimpl/certified/ (contact.py: one flight; sticking.py: the policy; orbit.py: the sequence; "
            "noimpact.py: a flight that never lands).",
            "initial_state": "exact (float64 inputs are exact binary numbers)",
            "stick_rows": "policy values (tau_n + t_acc, accumulation-point formula of mapimpl/sticking.py), "
            "not solutions of the ODE; the sticking decision itself is certified definite",
            "release_rows": "closed-form zero of the contact force f, certified (sign change, f' excludes 0) and "
            "f certified pressing on the whole stuck interval before it",
            "printed_values": "float64 nearest to the ball midpoint, 17 significant digits; the *_radius columns "
            "bound |printed - true| (ball radius + rounding), rounded up",
        },
        "precision_bits": orb.prec,
        "stop_reason": orb.stop_reason,
        "status": orb.status,
        "radius": radii,
        "notes": spec.notes,
        "tracks_agreement": agreement,
        "software": _versions(),
        "rows": rows,
    }


def radius_stats(text: str, orb: cert.CertifiedOrbit) -> dict:
    """The provenance's ``radius`` statistics of an ``expected.csv`` text (bounds on ``|printed - true|``) and of
    the certified balls; ``_rows``: the number of data rows (removed by the caller)."""
    import csv as _csv

    rows = list(_csv.DictReader(text.splitlines()))
    radii: dict = {}
    for c in RADIUS_COLUMNS:
        vals = sorted(float(r[c]) for r in rows if r[c] != "")
        radii[c] = {"max": "%.2e" % vals[-1], "median": "%.2e" % vals[len(vals) // 2]} if vals else {}
    radii["ball"] = {
        "tau_max": "%.2e" % max(float(e.tau.rad()) for e in orb.events),
        "sdot_max": "%.2e" % max([float(e.sdot.rad()) for e in orb.events if e.sdot is not None] or [0.0]),
        "meaning": "largest certified ball radius (before printing as float64)",
    }
    radii["_rows"] = len(rows)
    return radii


def write_plain(path: Path, text: str) -> None:
    """The default writer of the suite's files (a developer's tool): ``path.write_text(text)``.  The
    commands pass the command line's atomic writer instead (``validation/io/atomic.py``: this layer may
    not import it), so what ``gear-rattle case`` and ``fuzz`` write is whole or not there."""
    path.write_text(text)


def write_case(
    folder: Path, settings: dict, text: str, prov: dict, write: Callable[[Path, str], object] = write_plain
) -> None:
    """A case folder: ``settings.json``, ``expected.csv`` and ``provenance.json``, each through ``write``."""
    folder.mkdir(parents=True, exist_ok=True)
    write(folder / "settings.json", json.dumps(settings, indent=1) + "\n")
    write(folder / "expected.csv", text)
    write(folder / "provenance.json", json.dumps(prov, indent=1) + "\n")
