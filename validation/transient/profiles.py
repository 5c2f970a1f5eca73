"""Run sizes of the Figs. 9-11 analyses per profile, in one place: ``"quick"`` (well under a minute per
experiment on 2 cores) and ``"paper"`` (the paper's scale where it states one).

* ``basins`` (Fig. 9): ``nx`` x ``ny`` mesh of the whole phase circle.  The paper does not state Fig. 9's
  resolution; 300 x 300 bounds the paper profile's cost (the 400 x 400 of Fig. 11 is the paper's own,
  and is kept there).
* ``uncertainty`` (Fig. 10): ``n_points`` random points, ``n_eps`` log-spaced eps values in 1e-9..1e-3.
* ``transients`` (Fig. 11): ``n`` x ``n`` mesh of the paper's box, ``cap`` iterations per orbit.
* ``alt_ic``: the mesh side of the alternative initial-condition reading of Fig. 11 (free flight from
  s = -1); ``None``: the ``transients`` mesh.  The paper profile uses 200 x 200 of the 400 x 400 box (a
  comparison of readings, not the headline <n>; bounds the cost).
* ``stick_time``: ``stride`` of the sub-mesh of the Fig. 11 run used by the chatter-threshold
  sensitivity (every ``stride``-th row and column).
* ``horizon``: ``n_side`` x ``n_side`` orbits of ``impacts`` impacts for the transient Lyapunov exponent.
* ``confirm``: repeat each certification of ``T_post`` at the next precision.
"""

from __future__ import annotations

PROFILES = {
    "quick": {"basins": {"nx": 120, "ny": 60}, "uncertainty": {"n_points": 300, "n_eps": 7},
              "transients": {"n": 60, "cap": 20000}, "alt_ic": {"n": None}, "stick_time": {"stride": 1},
              "horizon": {"n_side": 6, "impacts": 2000}, "confirm": False},
    "paper": {"basins": {"nx": 300, "ny": 300}, "uncertainty": {"n_points": 3000, "n_eps": 13},
              "transients": {"n": 400, "cap": 20000}, "alt_ic": {"n": 200}, "stick_time": {"stride": 4},
              "horizon": {"n_side": 8, "impacts": 3000}, "confirm": True},
}


def get_profile(profile: str, part: str):
    """The run sizes of ``part`` in ``profile`` (a copy); ``ValueError`` for an unknown profile."""
    if profile not in PROFILES:
        raise ValueError(f"profile={profile!r} is out of range: allowed one of {', '.join(PROFILES)}")
    v = PROFILES[profile][part]
    return dict(v) if isinstance(v, dict) else v
