"""Run sizes of every analysis per profile, in one place, and the one way to read them (:func:`get_profile`).

Two profiles: ``"quick"`` (the report's quick setting and the commands' default: minutes on 2 cores) and
``"paper"`` (the paper's scale where it states one).  :data:`PROFILES` ``[profile][part]`` holds the
sizes of one analysis (``part``); :func:`get_profile` returns a copy, with the entries of ``sizes`` in
place of the profile's where a caller asks for other sizes, each checked like the profile's.

**Figs. 2-8** (:mod:`validation.dynamics`, the report's sections):

* ``motion`` (Figs. 2-3, :mod:`validation.dynamics.motion`): ``impacts`` of the orbit, ``lyap_n`` of
  the Lyapunov average;
* ``diagrams`` (Figs. 4 and 8 with their exponents): ``fig4_values``, ``fig8_values`` parameter values,
  ``transient`` impacts discarded, ``keep`` recorded per value, ``lyap_n`` impacts of each exponent;
* ``timeseries`` (Figs. 5-7): ``ts_n`` impacts of each series (after
  :data:`validation.dynamics.scans.TS_TRANSIENT`);
* ``settling``: ``settle_ics`` orbits of ``settle_n`` impacts for each settling run
  (:func:`validation.dynamics.settling.settle`).

**The crises** (:mod:`validation.dynamics.crises`; ``quick``: about 2 minutes for the three on 2 idle
cores, coarse; ``paper``: the numbers of docs/dynamics.md, about 10 minutes together).  The engine does
~5e5 impacts/s per idle core on these orbits when each device holds >= 512 of them (~3.8e5 at 128: a
micro-step has a fixed cost), so the paper profile runs many orbits of moderate length: a bracket run is
1024 orbits x 5e4 impacts (>= 5e7 impacts, issue 10) rather than 256 x 2e5.  Escapes and band hops are
memoryless after the first few hundred impacts (constant hazard), so the exposure, not the orbit length,
sets the statistics.  The paper profile spends ~1e8-3e8 impacts on each of r1 and alpha1 and ~2e7 on r2.

* ``r2``: ``dr`` -- offsets r - r2 of the laminar-phase runs; ``orbits`` per offset; ``cap`` impacts per
  orbit; ``n_start`` discarded.
* ``r1``: ``r_ref`` (above r1: the 6-band attractor on which the orbits start), ``ics``, ``settle``;
  ``coarse`` -- r values of the first scan; ``fine`` -- offsets below the first estimate of r1;
  ``orbits``/``cap`` of the scans; ``probe_orbits``/``probe_cap`` of each bracket run (their product
  is the exposure of a run that sees no hop); ``max_probes`` -- bracket runs at most; ``target`` --
  the bracket half-width aimed at; ``lyap_orbits`` x ``lyap_n``: the Lyapunov run at the bracket's
  upper end (a chaotic attractor there, not a periodic window).
* ``alpha1``: ``alpha_ref`` (below alpha1: the chaotic attractor on which the orbits start), ``ics``
  (orbits per alpha of the scans), ``probe_ics`` (orbits of each bracket run; default ``ics``:
  :data:`OPTIONAL`), ``settle``; ``coarse`` -- alpha values of the first scan (the paper's 1.2437 among
  them); ``fine`` -- offsets above the first estimate; ``cap`` of the scans; ``probe_cap``;
  ``max_probes``; ``target``; ``T_deep`` -- a mean lifetime the scans must reach (a probe is placed
  where the law predicts ``alpha1.DEEP_AIM`` = 1.5 times it).

**Figs. 9-11** (:mod:`validation.transient`; ``quick``: well under a minute per experiment on 2 cores):

* ``basins`` (Fig. 9): ``nx`` x ``ny`` mesh of the whole phase circle.  The paper does not state Fig. 9's
  resolution; 300 x 300 bounds the paper profile's cost (the 400 x 400 of Fig. 11 is the paper's own,
  and is kept there).
* ``uncertainty`` (Fig. 10): ``n_points`` random points, ``n_eps`` log-spaced eps values in 1e-9..1e-3.
* ``transients`` (Fig. 11): ``n`` x ``n`` mesh of the paper's box, ``cap`` iterations per orbit.
* ``alt_ic``: the mesh side ``n`` of the alternative initial-condition reading of Fig. 11 (free flight
  from s = -1); ``None``: the ``transients`` mesh.  The paper profile uses 200 x 200 of the 400 x 400 box
  (a comparison of readings, not the headline <n>; bounds the cost).
* ``stick_time``: ``stride`` of the sub-mesh of the Fig. 11 run used by the chatter-threshold
  sensitivity (every ``stride``-th row and column).
* ``horizon``: ``n_side`` x ``n_side`` orbits of ``impacts`` impacts for the transient Lyapunov exponent.
* ``confirm``: repeat each certification of ``T_post`` at the next precision (a flag, not a dict).

**Track agreement** (:mod:`validation.crosscheck`): ``crosscheck`` -- random states compared by
``one_step`` and ``jacobian``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.checks import MAX_AVERAGED, MAX_VALUES, InputTypeError, check_array, check_choice, check_int, check_real
from ..core.params import PARAM_MAX

#: Run sizes by profile and part (the module docstring).
PROFILES: dict[str, dict[str, Any]] = {
    "quick": {
        "motion": {"impacts": 600, "lyap_n": 20000},
        "diagrams": {"fig4_values": 120, "fig8_values": 120, "transient": 1000, "keep": 150, "lyap_n": 4000},
        "timeseries": {"ts_n": 1500},
        "settling": {"settle_ics": 8, "settle_n": 20000},
        "r2": {"dr": np.logspace(-5, -3, 4), "orbits": 8, "cap": 40_000, "n_start": 1000},
        "r1": {
            "r_ref": 0.7416,
            "ics": 64,
            "settle": 3000,
            "coarse": np.array([0.74100, 0.74120, 0.74130, 0.74136]),
            "fine": np.array([2e-5, 8e-6]),
            "orbits": 32,
            "cap": 20_000,
            "probe_orbits": 64,
            "probe_cap": 40_000,
            "max_probes": 1,
            "target": 2e-6,
            "lyap_orbits": 8,
            "lyap_n": 5000,
        },
        "alpha1": {
            "alpha_ref": 1.2425,
            "ics": 64,
            "settle": 2000,
            "coarse": np.array([1.2437, 1.2442, 1.2450, 1.2465]),
            "fine": np.array([4e-5, 1.5e-5]),
            "cap": 20_000,
            "probe_cap": 40_000,
            "max_probes": 1,
            "target": 1e-5,
            "T_deep": 1e5,
        },
        "basins": {"nx": 120, "ny": 60},
        "uncertainty": {"n_points": 300, "n_eps": 7},
        "transients": {"n": 60, "cap": 20000},
        "alt_ic": {"n": None},
        "stick_time": {"stride": 1},
        "horizon": {"n_side": 6, "impacts": 2000},
        "confirm": False,
        "crosscheck": {"one_step": 16, "jacobian": 6},
    },
    "paper": {
        "motion": {"impacts": 5000, "lyap_n": 200000},
        "diagrams": {"fig4_values": 600, "fig8_values": 600, "transient": 5000, "keep": 400, "lyap_n": 20000},
        "timeseries": {"ts_n": 4000},
        "settling": {"settle_ics": 32, "settle_n": 100000},
        "r2": {"dr": np.logspace(-5.5, -2.5, 7), "orbits": 16, "cap": 100_000, "n_start": 2000},
        "r1": {
            "r_ref": 0.7416,
            "ics": 1024,
            "settle": 5000,
            "coarse": np.array([0.74100, 0.74120, 0.74130, 0.74136, 0.74140]),
            "fine": np.array([3.2e-5, 1.6e-5, 8e-6, 4e-6, 2e-6]),
            "orbits": 128,
            "cap": 50_000,
            "probe_orbits": 1024,
            "probe_cap": 50_000,
            "max_probes": 4,
            "target": 2e-6,
            "lyap_orbits": 16,
            "lyap_n": 20_000,
        },
        "alpha1": {
            "alpha_ref": 1.2425,
            "ics": 256,
            "probe_ics": 1024,
            "settle": 5000,
            "coarse": np.array([1.2437, 1.2440, 1.2446, 1.2455, 1.2470]),
            "fine": np.array([8e-5, 4e-5, 2e-5, 1e-5]),
            "cap": 50_000,
            "probe_cap": 50_000,
            "max_probes": 4,
            "target": 1e-5,
            "T_deep": 1e6,
        },
        "basins": {"nx": 300, "ny": 300},
        "uncertainty": {"n_points": 3000, "n_eps": 13},
        "transients": {"n": 400, "cap": 20000},
        "alt_ic": {"n": 200},
        "stick_time": {"stride": 4},
        "horizon": {"n_side": 8, "impacts": 3000},
        "confirm": True,
        "crosscheck": {"one_step": 200, "jacobian": 40},
    },
}
#: The profiles' names.
PROFILE_NAMES = tuple(PROFILES)
#: Entries a profile may leave out, per part: ``{key: the entry whose value it then takes}``.
OPTIONAL = {"alpha1": {"probe_ics": "ics"}}
#: Counts that may be 0 (every other count is at least 1).
ZERO_ALLOWED = ("n_start", "transient")


def get_profile(profile: str, part: str, sizes: dict | None = None) -> Any:
    """The run sizes of ``part`` (a key of :data:`PROFILES` ``[profile]``) in ``profile`` (``"quick"`` or
    ``"paper"``): a copy of the dict (a flag such as ``"confirm"`` as it is), with the entries of
    ``sizes`` in place of the profile's.  Each replaced value is checked like the profile's
    (:mod:`core.checks`): a count ``1 <= n <= MAX_AVERAGED`` (5e7; from 0 for :data:`ZERO_ALLOWED`), a
    positive finite number, or a 1-D list of at most ``MAX_VALUES`` of them.  ``ValueError`` for an
    unknown profile, part, or a key the part does not have."""
    check_choice("profile", profile, PROFILE_NAMES)
    check_choice("part", part, tuple(PROFILES[profile]))
    value = PROFILES[profile][part]
    if sizes is not None and not isinstance(sizes, dict):
        raise InputTypeError(f"sizes is a {type(sizes).__name__}: allowed None or a dict of run sizes")
    if not isinstance(value, dict):
        if sizes:
            raise ValueError(f"sizes={sorted(sizes)} is out of range: {part!r} is a flag, allowed no sizes")
        return value
    out = dict(value)
    optional = OPTIONAL.get(part, {})
    allowed = set(out) | set(optional)
    unknown = sorted(set(sizes or {}) - allowed)
    if unknown:
        raise ValueError(f"sizes={unknown} is out of range: allowed keys of {part!r} are {', '.join(sorted(allowed))}")
    for key, given in (sizes or {}).items():
        like, arg = out.get(key, out.get(optional.get(key, ""))), f"sizes[{key!r}]"
        if isinstance(like, np.ndarray):
            out[key] = check_array(arg, given, 0.0, PARAM_MAX, nonzero=True, max_size=MAX_VALUES)
        elif like is None or isinstance(like, int):
            out[key] = check_int(arg, given, 0 if key in ZERO_ALLOWED else 1, MAX_AVERAGED)
        else:
            out[key] = check_real(arg, given, 0.0, PARAM_MAX, lo_open=True)
    return out


def label(profile: str, sizes: dict | None) -> str:
    """The profile a result records: ``profile``, or ``"<profile>+sizes"`` where ``sizes`` replaced run sizes."""
    return f"{profile}+sizes" if sizes else profile


__all__ = [
    "PROFILES",
    "PROFILE_NAMES",
    "OPTIONAL",
    "ZERO_ALLOWED",
    "get_profile",
    "label",
]
