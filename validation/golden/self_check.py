"""What ``gear-rattle check --self`` scores: our own solvers as an implementation under test (docs/golden.md).

* A case: one of our tracks (``map``, ``scipy``, ``diffrax``, ``certified``) on its ``settings.json``
  (:func:`run_case`, :func:`run_settings`); the catalogue's provenance records the agreement of two of them
  (:mod:`.catalog.build`), ``gear-rattle trackimpl`` runs them under the suite's protocol.
* An orbit record: our float64 solvers (:func:`float64_values`).  For each record: a *guess* printed with a
  few digits (:data:`GUESS_DIGITS`: the record's first point and, for a bifurcation point, its parameter),
  then our float64 Newton solvers -- :func:`mapimpl.periodic.find_periodic` for an orbit,
  :func:`mapimpl.continuation.locate` on the extended system for a fold or period doubling -- and the
  result in the layout of :mod:`.formats.orbits`.  This scores the accuracy of the converged float64
  answers, not how the orbits are found (the generator's seeds, :func:`.catalog.orbits.float64_seeds`, do
  that).

The solvers are imported when they run: importing this module loads numpy alone.
"""

from __future__ import annotations

import numpy as np

from ...core.params import Params
from .formats.cases import Case
from .formats.orbits import Record, Values, values_from_dict

__all__ = ["run_case", "run_settings", "float64_values", "GUESS_DIGITS"]


def run_case(case: Case, track: str = "map"):
    """Run one of our tracks on a case's settings; returns the :class:`ImpactSequence`."""
    return run_settings(case.settings, track)


def run_settings(s: dict, track: str = "map"):
    """Run one of our tracks on a case's ``settings.json`` data (its parameters, initial state, impacts
    and sticking threshold ``stick_time``, default :data:`mapimpl.sticking.STICK_TIME`); returns the
    :class:`ImpactSequence`."""
    from ...mapimpl.sticking import STICK_TIME
    from ...mapimpl.tracks import orbit

    p = Params(**s["params"])
    ini = s["initial_state"]
    return orbit(
        p,
        ini["tau0"],
        ini["sdot0"],
        int(s["n_impacts"]),
        s0=ini.get("s0"),
        track=track,
        stick_time=s.get("stick_time", STICK_TIME),
    )


#: Significant digits of the guesses (the first point, the parameter of a bifurcation point).
GUESS_DIGITS = 4
_LOCATE_KIND = {"fold": "fold", "period-doubling": "flip"}


def _guess(x: float) -> float:
    return float(f"{x:.{GUESS_DIGITS}g}")


def float64_values(rec: Record) -> tuple[dict, Values]:
    """``(values as a JSON-ready dict, Values)`` of our float64 solvers for one record."""
    from ...mapimpl.periodic import find_periodic
    from ...mapimpl.continuation import locate, orbit_states

    params = Params(**{k: float(v) for k, v in rec.data["params"].items()})
    impacts, turns = int(rec.data["impacts_per_period"]), int(rec.data["turns"])
    tau0 = _guess(float(np.mean(rec.points[0, :2])))
    sdot0 = _guess(float(np.mean(rec.points[0, 2:])))
    d: dict = {}
    if rec.kind == "periodic-orbit":
        o = find_periodic(params, tau0, sdot0, impacts, turns)
        th, sd, walls, mult = o.theta, o.sdot, o.walls, o.multipliers
        if not o.converged:
            d["note"] = f"find_periodic did not converge (residual {o.residual:.2g})"
    else:
        name = rec.data["parameter"]
        assert rec.value is not None, "a bifurcation record has its value (load_record)"
        mu0 = _guess(float(np.mean(rec.value)))
        f = locate(params.replace(**{name: mu0}), name, _LOCATE_KIND[rec.kind], tau0, sdot0, mu0, impacts, turns)
        th, sd = orbit_states(params.replace(**{name: f.mu}), f.theta, f.sdot, impacts)
        walls = np.where(np.asarray(sd) > 0, 0, -1)
        mult = f.multipliers
        d["value"] = float(f.mu)
        if not f.converged:
            d["note"] = f"locate did not converge (residual {f.residual:.2g})"
    d["points"] = [
        {"tau_mod_2pi": float(t) % (2 * np.pi), "sdot": float(v), "wall": int(w)} for t, v, w in zip(th, sd, walls)
    ]
    d["multipliers"] = [{"re": float(complex(z).real), "im": float(complex(z).imag)} for z in mult]
    return d, values_from_dict(d, f"<map track, {rec.id}>")
