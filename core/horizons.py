"""The flight horizons: how long a flight is followed before it is declared to reach no wall.

Two horizons, defined here once and imported by every track (the map's finder, the engine, the scipy
and diffrax tracks, the certified track and the certified single-flight search):

* :data:`T_MAX` -- the **orbit horizon**.  A flight of an orbit that reaches no wall within ``T_MAX``
  ends the orbit with status ``no_impact`` (``core.status``).  It is part of the model's output, so
  every track that computes an orbit uses the same value (map, engine, scipy, diffrax and the certified
  track's :func:`mapimpl.certified.track.certified_orbit`): the tracks then agree on which orbits
  end and where.
* :data:`CERTIFIED_FLIGHT_T_MAX` -- the **search horizon of one certified flight**
  (:func:`mapimpl.certified.contact.certified_flight` and the certified steps built on it: the golden
  cases' impacts, the post-release flights of a certified ``T_post``).  It is a fifth of
  :data:`T_MAX` because a certified flight pays for its horizon: the interval cover of ``[0, t_max]``
  that proves "no wall yet" uses steps of at most 1/2 time unit, two enclosures each, so its cost
  grows linearly with ``t_max`` (at least ``4 t_max`` enclosures at a few hundred bits).  Those flights
  are short, and a flight not certified within this horizon raises ``NoContactError`` (a
  ``CertificationError``): a user's golden case then ends at its last certified impact, a ``T_post``
  attempt ends ``failed`` with that reason -- it is never reported as the orbit status ``no_impact``
  (the suite's ``no_impact`` case is proven for all time, ``certify_no_impact_orbit``).  So the shorter
  horizon bounds the cost of a search that is going nowhere without changing what an orbit means; the
  committed golden cases were certified with this value.  A caller that needs the orbit meaning passes
  ``t_max=T_MAX``, as the certified track does.
"""

from __future__ import annotations

#: Longest flight of an orbit (units of tau) before the orbit ends with ``no_impact``: every track's rule.
T_MAX = 2000.0

#: Longest flight searched by one certified flight (units of tau): a fifth of :data:`T_MAX`, see the
#: module docstring for why it is shorter.
CERTIFIED_FLIGHT_T_MAX = T_MAX / 5

__all__ = ["T_MAX", "CERTIFIED_FLIGHT_T_MAX"]
