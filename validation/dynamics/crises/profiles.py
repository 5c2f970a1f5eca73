"""Run sizes of the crisis analyses: ``"quick"`` (about 2 minutes for the three on 2 idle cores; coarse)
and ``"paper"`` (the numbers of docs/dynamics.md; about 10 minutes together on 2 idle cores).

Why these sizes (docs/dynamics.md, "Run sizes"): the engine does ~5e5 impacts/s per idle core on
these orbits when each device holds >= 512 of them (~3.8e5 at 128: a micro-step has a fixed cost),
so the paper profile runs many orbits of moderate length: a bracket run is 1024 orbits x 5e4 impacts
(>= 5e7 impacts, issue 10) rather than 256 x 2e5.  Escapes and band hops are memoryless after the
first few hundred impacts (constant hazard), so the exposure, not the orbit length, sets the
statistics.  The paper profile spends ~1e8-3e8 impacts on each of r1 and alpha1 and ~2e7 on r2.

* ``r2``: ``dr`` -- offsets r - r2 of the laminar-phase runs; ``orbits`` per offset; ``cap`` impacts per
  orbit; ``n_start`` discarded.
* ``r1``: ``r_ref`` (above r1: the 6-band attractor on which the orbits start), ``ics``, ``settle``;
  ``coarse`` -- r values of the first scan; ``fine`` -- offsets below the first estimate of r1;
  ``orbits``/``cap`` of the scans; ``probe_orbits``/``probe_cap`` of each bracket run (their product
  is the exposure of a run that sees no hop); ``max_probes`` -- bracket runs at most; ``target`` --
  the bracket half-width aimed at; ``lyap_orbits`` x ``lyap_n``: the Lyapunov run at the bracket's
  upper end (a chaotic attractor there, not a periodic window).
* ``alpha1``: ``alpha_ref`` (below alpha1: the chaotic attractor on which the orbits start), ``ics``
  (orbits per alpha of the scans), ``probe_ics`` (orbits of each bracket run; default ``ics``),
  ``settle``; ``coarse`` -- alpha values of the first scan (the paper's 1.2437 among them); ``fine`` --
  offsets above the first estimate; ``cap`` of the scans; ``probe_cap``; ``max_probes``; ``target``;
  ``T_deep`` -- a mean lifetime the scans must reach (a probe is placed where the law predicts
  ``alpha1.DEEP_AIM`` = 1.5 times it).
"""

from __future__ import annotations

import numpy as np

from ....core.checks import MAX_AVERAGED, MAX_VALUES, InputTypeError, check_array, check_choice, check_int, check_real
from ....core.params import PARAM_MAX

#: Run sizes by profile (``"quick"``, ``"paper"``) and analysis (``"r2"``, ``"r1"``, ``"alpha1"``).
PROFILES = {
    "quick": {
        "r2": {"dr": np.logspace(-5, -3, 4), "orbits": 8, "cap": 40_000, "n_start": 1000},
        "r1": {"r_ref": 0.7416, "ics": 64, "settle": 3000,
               "coarse": np.array([0.74100, 0.74120, 0.74130, 0.74136]), "fine": np.array([2e-5, 8e-6]),
               "orbits": 32, "cap": 20_000, "probe_orbits": 64, "probe_cap": 40_000, "max_probes": 1,
               "target": 2e-6, "lyap_orbits": 8, "lyap_n": 5000},
        "alpha1": {"alpha_ref": 1.2425, "ics": 64, "settle": 2000,
                   "coarse": np.array([1.2437, 1.2442, 1.2450, 1.2465]), "fine": np.array([4e-5, 1.5e-5]),
                   "cap": 20_000, "probe_cap": 40_000, "max_probes": 1, "target": 1e-5, "T_deep": 1e5},
    },
    "paper": {
        "r2": {"dr": np.logspace(-5.5, -2.5, 7), "orbits": 16, "cap": 100_000, "n_start": 2000},
        "r1": {"r_ref": 0.7416, "ics": 1024, "settle": 5000,
               "coarse": np.array([0.74100, 0.74120, 0.74130, 0.74136, 0.74140]),
               "fine": np.array([3.2e-5, 1.6e-5, 8e-6, 4e-6, 2e-6]),
               "orbits": 128, "cap": 50_000, "probe_orbits": 1024, "probe_cap": 50_000, "max_probes": 4,
               "target": 2e-6, "lyap_orbits": 16, "lyap_n": 20_000},
        "alpha1": {"alpha_ref": 1.2425, "ics": 256, "probe_ics": 1024, "settle": 5000,
                   "coarse": np.array([1.2437, 1.2440, 1.2446, 1.2455, 1.2470]),
                   "fine": np.array([8e-5, 4e-5, 2e-5, 1e-5]),
                   "cap": 50_000, "probe_cap": 50_000, "max_probes": 4, "target": 1e-5, "T_deep": 1e6},
    },
}


def get_profile(name: str, part: str, sizes: dict | None = None) -> dict:
    """The run sizes of ``part`` (``"r2"``, ``"r1"``, ``"alpha1"``) in profile ``name``, with the entries of
    ``sizes`` in place of the profile's (``ValueError`` for a key the part does not have).  Each replaced
    value is checked like the profile's (:mod:`core.checks`): a count ``1 <= n <= MAX_AVERAGED`` (5e7;
    ``n_start`` from 0), a positive finite number, or a 1-D list of at most ``MAX_VALUES`` of them."""
    check_choice("profile", name, tuple(PROFILES))
    out = dict(PROFILES[name][part])
    if sizes is not None and not isinstance(sizes, dict):
        raise InputTypeError(f"sizes is a {type(sizes).__name__}: allowed None or a dict of run sizes")
    allowed = set(out) | ({"probe_ics"} if part == "alpha1" else set())  # optional: default ``ics``
    unknown = sorted(set(sizes or {}) - allowed)
    if unknown:
        raise ValueError(f"sizes={unknown} is out of range: allowed keys of {part!r} are {', '.join(sorted(allowed))}")
    for key, value in (sizes or {}).items():
        like, arg = out.get(key, out.get("ics")), f"sizes[{key!r}]"
        if isinstance(like, np.ndarray):
            out[key] = check_array(arg, value, 0.0, PARAM_MAX, nonzero=True, max_size=MAX_VALUES)
        elif isinstance(like, int):
            out[key] = check_int(arg, value, 0 if key == "n_start" else 1, MAX_AVERAGED)
        else:
            out[key] = check_real(arg, value, 0.0, PARAM_MAX, lo_open=True)
    return out


def label(name: str, sizes: dict | None) -> str:
    """The profile a result records: ``name``, or ``"<name>+sizes"`` where ``sizes`` replaced run sizes."""
    return f"{name}+sizes" if sizes else name
