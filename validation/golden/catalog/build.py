"""The shipped cases certified and written (``python -m gear_rattle.validation.golden.generate``): every case
of the catalogue (:mod:`.specs`) is certified from scratch with ball arithmetic (:mod:`mapimpl.certified`),
its rows given their tolerances (:mod:`..rules.tolerances`) and written in the suite's formats
(:mod:`..formats.case_writer`: ``settings.json``, ``expected.csv``, ``provenance.json``).  Deterministic:
the same software writes byte-identical files.  The map and scipy tracks are run on every case and their
deviations recorded in the provenance ("agreed by two tracks"); they never feed the expected numbers.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

from ....mapimpl import certified as cert
from ....mapimpl.sticking import STICK_TIME
from ..formats.case_writer import expected_csv, provenance_json, radius_stats, settings_json
from ..formats.cases import Case, load_case, sequence_from_impacts
from ..formats.spec import Spec
from ..rules.tolerances import RADIUS_LIMIT, row_tolerances
from ..scoring.cases import score_sequence
from ..self_check import run_case
from . import contacts

__all__ = ["certified_policy", "track_agreement", "closest_approach", "certify_spec", "build_case"]


def certified_policy(spec: Spec) -> dict:
    """The sticking decision at impact 0 (a pre-impact state), in balls: ``t_acc / STICK_TIME`` and
    the release delay, as 6-digit decimals of the certified enclosures."""
    wall = 0 if spec.sdot0 > 0 else -1
    with cert.precision(spec.prec):
        m = cert.Model(spec.params)
        tau, d = cert.exact(spec.tau0), (1 if wall == 0 else -1)
        f_in = d * m.forcing(tau)
        t_acc = 2 * m.r * abs(cert.exact(spec.sdot0)) / ((1 - m.r) * f_in)
        delay = cert.release_delay(m, tau, wall)
        ratio = t_acc / cert.exact(STICK_TIME)
        return {
            "wall": wall,
            "pressing": bool(f_in > 0),
            "t_acc_over_stick_time": f"{float(ratio.mid()):.6g}",
            "release_delay": "never" if delay is None else f"{float(delay.mid()):.6g}",
            "t_acc": f"{float(t_acc.mid()):.6g}",
            "meaning": "the policy's quantities at impact 0, certified (ball radii < 1e-80)",
        }


def track_agreement(case: Case, tracks=("map", "scipy")) -> dict:
    out = {}
    for tr in tracks:
        try:
            seq = run_case(case, tr)
        except ImportError as e:  # pragma: no cover - environment dependent
            out[tr] = {"available": False, "reason": str(e)}
            continue
        got = sequence_from_impacts(seq, f"<{tr} track>")
        if len(got) != len(case.expected):
            out[tr] = {"rows": len(got), "agrees": False, "reason": "different number of rows"}
            continue
        sc = score_sequence(case, got)
        out[tr] = {
            "agrees": sc.passed,
            "status": seq.status,
            "max_abs_error": {c: float("%.1e" % sc.columns[c].max_error) for c in ("tau", "tau_mod_2pi", "sdot")},
            "digits": {c: round(sc.columns[c].digits, 1) for c in ("tau", "tau_mod_2pi", "sdot")},
        }
    return out


def closest_approach(spec: Spec) -> tuple[str, str]:
    """``(note key, text)``: certified enclosure of the smallest distance to the wall the first flight
    turns back from (where ``s' = 0``), for the near-miss cases (:func:`contacts.certified_closest_approach`)."""
    wall, gap = contacts.certified_closest_approach(spec.params, spec.tau0, spec.sdot0, spec.prec)
    key = f"closest_approach_to_{'lower' if wall == -1 else 'upper'}_wall"
    return key, f"{float(gap.mid()):.6e} (certified enclosure radius {float(gap.rad()):.1e})"


def certify_spec(spec: Spec, radius_limit: float) -> cert.CertifiedOrbit:
    """The certified orbit of a case, with the certifier of its kind of ending."""
    if spec.ending == "no_impact":
        # the map track says after which impact the orbit ends (a search hint); the certification proves it
        from ....mapimpl.tracks import orbit

        hint = orbit(spec.params, spec.tau0, spec.sdot0, spec.n_impacts, s0=spec.s0, track="map")
        if hint.status != "no_impact":
            raise cert.CertificationError(f"{spec.id}: the map track ends with status {hint.status!r}, not 'no_impact'")
        last = int(hint.n[hint.kind == "impact"][-1])
        return cert.certify_no_impact_orbit(
            spec.params,
            spec.tau0,
            spec.sdot0,
            last,
            s0=spec.s0,
            prec=spec.prec,
            radius_limit=radius_limit,
            stick_time=spec.stick_time,
        )
    return cert.certify_orbit(
        spec.params,
        spec.tau0,
        spec.sdot0,
        spec.n_impacts,
        s0=spec.s0,
        prec=spec.prec,
        radius_limit=radius_limit,
        stick_time=spec.stick_time,
    )


def build_case(spec: Spec, *, tracks: bool = True) -> tuple[dict, str, dict]:
    """Certify one case; returns ``(settings, expected_csv_text, provenance)``."""
    orb = certify_spec(spec, RADIUS_LIMIT)
    if orb.stop_reason.startswith("radius"):
        raise cert.CertificationError(f"{spec.id}: {orb.stop_reason}: lower n_impacts or raise prec")
    if orb.status != spec.ending and not (spec.ending == "active" and orb.status == "stuck_forever"):
        raise cert.CertificationError(f"{spec.id}: certified status {orb.status!r}, expected {spec.ending!r}")
    tols = row_tolerances(spec, orb)
    if tols.errors.fragile is not None:
        raise cert.CertificationError(
            f"{spec.id}: line {tols.errors.fragile + 2}: a graze whose excursion beyond the wall a correct float64 "
            "implementation may miss (docs/golden.md, tolerances from the conditioning)"
        )
    spec = replace(spec, notes={**spec.notes, "tolerances": tols.note()})
    if "excursion" in spec.extras:
        spec.notes["excursion"] = contacts.certified_excursion(spec.params, spec.tau0, spec.sdot0, spec.prec)
    if "policy" in spec.extras:
        spec.notes["policy_at_impact_0"] = certified_policy(spec)
    text = expected_csv(orb, tols)
    settings = settings_json(spec, orb, tols)
    radii = radius_stats(text, orb)
    radii.pop("_rows")
    if "chaotic" in spec.tags:
        imp = [(e.n, float(e.tau.rad())) for e in orb.events if e.kind == "impact" and e.n >= 1]
        xs = [n for n, r in imp if r > 0]
        ys = [math.log(r) for n, r in imp if r > 0]
        xm, ym = sum(xs) / len(xs), sum(ys) / len(ys)
        slope = sum((x - xm) * (y - ym) for x, y in zip(xs, ys)) / sum((x - xm) ** 2 for x in xs)
        spec.notes["certified_radius_growth_per_impact"] = (
            f"{slope:.2f} (least-squares slope of ln(tau ball radius) over the impacts; compare lambda1)"
        )
    if "near-miss" in spec.id:
        key, approach = closest_approach(spec)
        spec.notes[key] = approach
    agreement = None
    if tracks:
        import tempfile

        with tempfile.TemporaryDirectory() as d:
            folder = Path(d, spec.id)  # a case's id names its folder (load_case checks it)
            folder.mkdir()
            (folder / "expected.csv").write_text(text)
            (folder / "settings.json").write_text(json.dumps(settings))
            agreement = track_agreement(load_case(folder))
    return settings, text, provenance_json(spec, orb, radii, agreement)
