"""One vocabulary for how a flight search and an orbit end, shared by every track and kernel of the
project (the finder, the map step, the engine, the reference tracks, the certified track): the same
name always carries the same integer, and every code has a message (as diffrax's ``RESULTS``).

:class:`Status` -- state of an orbit: ``ACTIVE`` orbits go on; the others are terminal.  The engine
(:mod:`gear_rattle.mapimpl.engine`) adds the reasons it stops an orbit that is still active:
``STOPPED`` (its observer's criterion was met: captured by the periodic orbit, escaped from the
bands, all samples taken), ``CAPPED`` (the impact cap was reached) and ``STUCK`` (stopped at its
first sticking episode, to be continued by the one post-release orbit, see
:func:`gear_rattle.mapimpl.sticking.release_phase`).  A Newton search for a periodic orbit ends
``CONVERGED`` or ``NOT_CONVERGED``.  :attr:`Status.ok` says whether a code is an answer; every result
type says whether it worked through it (:class:`gear_rattle.core.outcome.Outcome`: ``ok``, ``status``,
``message``).

:class:`FlightOutcome` -- outcome of one first-impact search (:func:`gear_rattle.mapimpl.finder.first_impact`,
the reference tracks' event search).  The names shared by the two enums (``NO_IMPACT``,
``STEP_CAP``) have the same values: a flight that ends so ends its orbit with that status.

Kernels carry the integer codes (``jnp.where(ok, Status.ACTIVE, ...)``); results and files carry
the lower-case names (:attr:`Coded.label`: ``"active"``, ``"stuck_forever"``, ... -- part of the
CSV/JSON formats and of the golden suite, unchanged).
"""

from __future__ import annotations

from enum import IntEnum


class Coded(IntEnum):
    """An integer code with a file name (:attr:`label`) and a sentence (:attr:`message`): the base of
    :class:`Status` and :class:`FlightOutcome`."""

    @property
    def label(self) -> str:
        """The code's name in files and results: the member name in lower case."""
        return self.name.lower()

    @property
    def message(self) -> str:
        """What the code means, in one sentence."""
        return _MESSAGES[type(self).__name__][self.name]

    @classmethod
    def from_label(cls, label: str):
        """The member whose :attr:`label` is ``label`` (``ValueError`` naming the allowed ones)."""
        for m in cls:
            if m.label == label:
                return m
        raise ValueError(f"status={label!r} is out of range: allowed one of {', '.join(m.label for m in cls)}")


class Status(Coded):
    """State of an orbit (the map's ``MapState.status``, the engine's per-orbit result, every track)."""

    NOT_RUN = -1
    ACTIVE = 0
    STUCK_FOREVER = 1
    NO_IMPACT = 2
    STEP_CAP = 3
    STOPPED = 4
    CAPPED = 5
    STUCK = 6
    CONVERGED = 7
    NOT_CONVERGED = 8

    @property
    def ok(self) -> bool:
        """Whether a computation that ends with this code worked: it did what was asked, or the model
        itself ended the orbit (stuck forever, no wall within the horizon, captured, censored at the cap).
        Not ok: :data:`NOT_OK` (never run, a search's step budget used up, Newton not converged)."""
        return self not in NOT_OK


class FlightOutcome(Coded):
    """Outcome of a first-impact search."""

    HIT = 0
    GRAZE = 1
    NO_IMPACT = 2
    STEP_CAP = 3


_MESSAGES = {
    "Status": {
        "NOT_RUN": "never started (engine: e.g. a free-flight start that reaches no wall)",
        "ACTIVE": "the orbit goes on",
        "STUCK_FOREVER": "stuck to a wall whose contact force never changes sign",
        "NO_IMPACT": "a flight reaches no wall within the longest flight searched (T_MAX)",
        "STEP_CAP": "a first-impact search used up its step budget",
        "STOPPED": "engine: the observer's stop criterion was met (captured, escaped, all samples taken)",
        "CAPPED": "engine: the impact cap was reached, the orbit still active",
        "STUCK": "engine: stopped at its first sticking episode (continued by the release orbit)",
        "CONVERGED": "Newton's method reached its tolerance (a periodic orbit)",
        "NOT_CONVERGED": "Newton's method did not reach its tolerance within max_iter iterations",
    },
    "FlightOutcome": {
        "HIT": "a wall is reached (transversal impact)",
        "GRAZE": "the wall is touched at zero normal velocity to within rounding",
        "NO_IMPACT": "no wall within the flight horizon T_MAX",
        "STEP_CAP": "the search used up its step budget",
    },
}

#: The codes of a computation that did not work (:attr:`Status.ok` is False): the rest are answers.
NOT_OK = frozenset({Status.NOT_RUN, Status.STEP_CAP, Status.NOT_CONVERGED})

#: The statuses an orbit of a track (:class:`gear_rattle.core.results.Track`) can end with, by label.
TRACK_STATUSES = tuple(s.label for s in (Status.ACTIVE, Status.STUCK_FOREVER, Status.NO_IMPACT, Status.STEP_CAP))

__all__ = ["Status", "FlightOutcome", "NOT_OK", "TRACK_STATUSES"]
