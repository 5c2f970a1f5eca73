"""One vocabulary for how a flight search and an orbit end, shared by every kernel of the project
(the finder, the map step, the engine, the reference tracks): the same name always carries the same
integer.

:class:`Flight` -- outcome of one first-impact search (:func:`gear_rattle.mapimpl.finder.first_impact`).
:class:`Orbit` -- state of an orbit: ``ACTIVE`` orbits go on; the others are terminal.  The engine
(:mod:`gear_rattle.mapimpl.engine`) adds the reasons it stops an orbit that is still active:
``STOPPED`` (its observer's criterion was met: captured by the periodic orbit, escaped from the
bands, all samples taken), ``CAPPED`` (the impact cap was reached) and ``STUCK`` (stopped at its
first sticking episode, to be continued by the one post-release orbit, see
:func:`gear_rattle.mapimpl.sticking.release_phase`).  The names shared by the two enums
(``NO_IMPACT``, ``STEP_CAP``) have the same values.
"""

from __future__ import annotations

from enum import IntEnum


class Flight(IntEnum):
    """Outcome of a first-impact search."""

    HIT = 0        #: a wall is reached (transversal impact)
    GRAZE = 1      #: the wall is touched at zero normal velocity to within rounding
    NO_IMPACT = 2  #: no wall within the flight horizon T_MAX
    STEP_CAP = 3   #: the search used up its step budget


class Orbit(IntEnum):
    """State of an orbit (the map's ``MapState.status``, the engine's per-orbit result)."""

    NOT_RUN = -1       #: engine: never started (e.g. a free-flight start that reaches no wall)
    ACTIVE = 0         #: goes on
    STUCK_FOREVER = 1  #: stuck to a wall whose contact force never changes sign
    NO_IMPACT = 2      #: a flight reaches no wall within T_MAX
    STEP_CAP = 3       #: a first-impact search used up its step budget
    STOPPED = 4        #: engine: the observer's stop criterion was met
    CAPPED = 5         #: engine: the impact cap was reached, orbit still active
    STUCK = 6          #: engine: stopped at its first sticking episode (continued by the release orbit)


def orbit_name(code: int) -> str:
    """Lower-case name of an :class:`Orbit` code (``"active"``, ``"stuck_forever"``, ...)."""
    return Orbit(int(code)).name.lower()


#: ``{code: name}`` for every :class:`Orbit` code.
ORBIT_NAMES = {int(s): s.name.lower() for s in Orbit}
