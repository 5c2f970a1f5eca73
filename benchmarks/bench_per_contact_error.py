"""The error each track makes at one contact, against the certified answer from the same float64 start: the
evidence for the gap-error model of the tolerances (validation/golden/rules/conditioning.py, docs/golden_tolerances.md,
"Tolerances from the conditioning").

For every impact reached by a flight in the inputs (the shipped cases, and fuzzed inputs drawn as
``gear-rattle fuzz`` draws them), the track runs one step from the previous certified pre-impact state, its
phase as the float64 start (a pre-impact start in ``[0, 2 pi)``: the representation of a large ``tau`` is
modelled apart), and the certified track proves the answer from that same start.  Reported per contact: the
gap error ``|dtau| |v|`` (the flight's own error: the time error times the impact speed) and the velocity's
own error ``|dsdot - a dtau|``, against the model ``e = GAP_ULPS 2^-52 + FLIGHT_ERROR h max(1, dt / 2 pi)``
and ``FLIGHT_ERROR max(|v_start|, |v|, F)``.  Contacts a case would not hold are left out: a different event
(a decision at a threshold), and grazes a correct implementation may miss (:func:`conditioning.local_error`).

Usage: ``python benchmarks/bench_per_contact_error.py [--tracks map,scipy,diffrax] [--fuzz SEED:COUNT ...]
[--out FILE]``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

import numpy as np
from flint import arb

from gear_rattle.core.params import Params
from gear_rattle.mapimpl import certified as cert
from gear_rattle.mapimpl.tracks import orbit
from gear_rattle.validation.golden.rules import conditioning as C
from gear_rattle.validation.golden.paths import DEFAULT_SUITE
from gear_rattle.validation.golden.formats.cases import case_ids, load_case


def suite_inputs() -> list[tuple]:
    out = []
    for cid in case_ids():
        s = load_case(DEFAULT_SUITE / cid).settings
        ini = s["initial_state"]
        out.append((cid[:4], Params(**s["params"]), ini["tau0"], ini["sdot0"], ini.get("s0"), int(s["n_impacts"])))
    return out


def fuzz_inputs(seed: int, count: int) -> list[tuple]:
    from gear_rattle.validation.golden.fuzzing.scenarios import construct, draw_recipes

    out = []
    for k, rec in enumerate(draw_recipes(seed, count)):
        inp = construct(rec, f"f{seed}-{k}")
        if inp is not None:
            out.append(
                (f"f{seed}-{k}:{rec['scenario']}", inp.params, inp.tau0, inp.sdot0, inp.s0, min(inp.impacts, 40))
            )
    return out


def _starts(orb, tau0, sdot0, s0):
    """``(tau0, sdot0, s0)`` of one step to each impact reached by a flight (its phase as ``tau0``)."""
    starts, prev = [], None
    for i, e in enumerate(orb.events):
        if e.kind != "impact":
            continue
        if prev is None:
            if s0 is not None:
                starts.append((tau0, sdot0, s0))
        else:
            p = orb.events[prev]
            starts.append((cert.nearest_float(p.theta), cert.nearest_float(p.sdot), None))
        prev = i
    return starts


def contact(p: Params, start: tuple, tracks: list[str]) -> list[dict]:
    """The errors of each track at the first contact reached from ``start``."""
    t0, v0, s0 = start
    one = cert.certify_orbit(p, t0, v0, 0 if s0 is not None else 1, s0=s0)
    imp = [e for e in one.events if e.kind == "impact"]
    if s0 is None and len(imp) < 2:
        return []
    e1 = imp[-1]
    rel = [e for e in one.events if e.kind == "release"]
    if s0 is not None:
        th0, vs, ts = t0 % C.TWO_PI, v0, t0
    elif rel:
        th0, vs, ts = cert.nearest_float(rel[0].theta), 0.0, cert.nearest_float(rel[0].tau)
    else:
        th0, vs, ts = t0 % C.TWO_PI, -p.r * v0, t0
    tau, v = cert.nearest_float(e1.tau), cert.nearest_float(e1.sdot)
    dt = tau - ts
    h = C.flight_height(p, th0, vs, dt)
    e = C.gap_error(h, dt)
    a = C.forcing(p, tau) - p.beta * v
    if C.local_error(p, e, tau, v, e1.wall, vs) is None:  # a graze a correct implementation may miss
        return []
    out = []
    for tr in tracks:
        seq = orbit(p, t0, v0, 0 if s0 is not None else 1, s0=s0, track=tr)
        kk = [j for j in range(len(seq.kind)) if seq.kind[j] == "impact"]
        if len(kk) != len(imp):
            out.append({"track": tr, "different_event": True})
            continue
        dtau = float(arb(float(seq.tau[kk[-1]])) - e1.tau) + math.floor(tau / C.TWO_PI) * C.TWO_PI_GAP
        dsdot = float(arb(float(seq.sdot[kk[-1]])) - e1.sdot)
        if abs(dtau) > 1e-9:  # another event: a decision at its threshold
            out.append({"track": tr, "different_event": True})
            continue
        scale = max(abs(vs), abs(v), C.largest_force(p))
        out.append(
            {
                "track": tr,
                "h": h,
                "dt": dt,
                "v": v,
                "gap": abs(dtau) * abs(v),
                "gap_over_model": abs(dtau) * abs(v) / e,
                "own_velocity_over_model": abs(dsdot - a * dtau) / (C.FLIGHT_ERROR * scale),
            }
        )
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tracks", default="map,scipy,diffrax")
    ap.add_argument("--fuzz", nargs="*", default=["1:60", "2:60", "3:60", "4:60"], metavar="SEED:COUNT")
    ap.add_argument("--out", default=None, help="JSON file of the summary")
    a = ap.parse_args(argv)
    tracks = a.tracks.split(",")
    inputs = suite_inputs()
    for f in a.fuzz:
        seed, count = f.split(":")
        inputs += fuzz_inputs(int(seed), int(count))
    t = time.time()
    rows: list[dict] = []
    for name, p, tau0, sdot0, s0, n in inputs:
        try:
            orb = cert.certify_orbit(p, tau0, sdot0, n, s0=s0)
        except (cert.CertificationError, ValueError):
            continue
        for st in _starts(orb, tau0, sdot0, s0):
            try:
                rows += [dict(r, input=name) for r in contact(p, st, tracks)]
            except (cert.CertificationError, ValueError):
                continue
    summary = {
        "model": {"GAP_ULPS": C.GAP_ULPS, "FLIGHT_ERROR": C.FLIGHT_ERROR},
        "inputs": len(inputs),
        "seconds": round(time.time() - t, 1),
    }
    for tr in tracks:
        r = [x for x in rows if x["track"] == tr and not x.get("different_event")]
        g = np.array([x["gap_over_model"] for x in r])
        w = np.array([x["own_velocity_over_model"] for x in r])
        worst = r[int(np.argmax(g))]
        summary[tr] = {
            "contacts": len(r),
            "different_events": sum(1 for x in rows if x["track"] == tr and x.get("different_event")),
            "gap_over_model": {
                "median": float(np.median(g)),
                "p99": float(np.percentile(g, 99)),
                "max": float(g.max()),
            },
            "largest_gap_ulps": float(max(x["gap"] for x in r) / C.POSITION_STEP),
            "worst": {k: worst[k] for k in ("input", "h", "dt", "v", "gap")},
            "own_velocity_over_model": {"median": float(np.median(w)), "max": float(w.max())},
        }
    text = json.dumps(summary, indent=1)
    print(text)
    if a.out:
        with open(a.out, "w") as fh:
            fh.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
