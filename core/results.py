"""The result types every track returns, and the :class:`Track` protocol they come out of.

Three tracks compute the same orbits of the paper's model: the closed-form impact map (Eqs. 7-8,
12-13, :mod:`mapimpl`) and Eq. (3) integrated numerically with the impact law Eqs. (9)-(11) by scipy
and by diffrax (:mod:`reference`).  They all speak the types defined here:

* :class:`ImpactSequence` -- the events of one orbit (impacts, and the ``"stick"`` / ``"release"``
  rows of the sticking policy) with its CSV and JSON writers (columns :data:`COLUMNS`, kinds
  :data:`KINDS`, final status one of :data:`gear_rattle.core.status.TRACK_STATUSES`);
* :class:`StepJacobian` -- one impact-to-impact step with ``d(tau_{n+1}, sdot_{n+1})/d(tau_n, sdot_n)``;
* :class:`Track` -- what a track offers: ``name``, ``orbit(...)`` and ``step_jacobian(...)``;
  :class:`TrackFunctions` makes one from two functions.

This module depends on nothing but numpy and :class:`core.params.Params`, so every track (and
the golden suite's file format) can import it.
"""

from __future__ import annotations

import csv
import io
import json
from dataclasses import dataclass, field
from typing import Callable, NamedTuple, Protocol, runtime_checkable

import numpy as np

from .checks import InputTypeError
from .outcome import Outcome, short_repr, check_lengths, check_status, describe, is_ok, status_codes
from .params import Params
from .registry import TRACKS
from .status import TRACK_STATUSES, Status

#: Event kinds of an :class:`ImpactSequence` row.
KINDS = ("impact", "stick", "release")
#: Columns of the CSV form of an :class:`ImpactSequence` (and of the golden suite's files).
COLUMNS = ("n", "tau", "tau_mod_2pi", "wall", "sdot", "kind")


@dataclass
class ImpactSequence(Outcome):
    """Events of one orbit (numpy arrays of equal length, time-ordered).

    Impact 0 is the initial pre-impact state (or, for a start in free flight, the first impact
    reached); impacts 1..N follow.  Sticking rows carry the index of the impact after which the
    tooth sticks.

    ``n``: impact index; ``tau``: the time of the event (absolute: impact 0 of a start at an impact is at
    ``tau0``, not 0); ``theta``: tau mod 2 pi; ``wall``: 0 or -1;
    ``sdot``: velocity just before the impact (NaN for stick/release rows); ``kind``: event kind
    (:data:`KINDS`).  ``status``: final orbit status, a :class:`~gear_rattle.core.status.Status` label
    (:data:`~gear_rattle.core.status.TRACK_STATUSES`), with ``ok`` and ``message``
    (:class:`~gear_rattle.core.outcome.Outcome`: every ending but ``step_cap`` is an answer); ``track``: which
    track produced it; ``meta``: the call's arguments and solver options.
    """

    params: Params
    n: np.ndarray
    tau: np.ndarray
    theta: np.ndarray
    wall: np.ndarray
    sdot: np.ndarray
    kind: np.ndarray
    status: str = Status.ACTIVE.label
    track: str = "map"
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Refuse what no track returns (``ValueError``, ``TypeError`` naming the argument): ``params`` not a
        :class:`Params`, a ``status`` not one of :data:`~gear_rattle.core.status.TRACK_STATUSES`, columns that
        are not 1-D arrays of one length, a ``kind`` outside :data:`KINDS` or a ``wall`` other than 0 and -1."""
        if not isinstance(self.params, Params):
            raise InputTypeError(f"params={self.params!r} is a {type(self.params).__name__}: allowed a Params")
        check_status(self.status, [Status.from_label(s) for s in TRACK_STATUSES])
        cols = ("n", "tau", "theta", "wall", "sdot", "kind")
        check_lengths(f"one row per event in {', '.join(cols)}", **{k: getattr(self, k) for k in cols})
        kind, wall = np.asarray(self.kind), np.asarray(self.wall)
        if not ((kind == "impact") | (kind == "stick") | (kind == "release")).all():
            raise ValueError(f"kind={short_repr(self.kind)} is out of range: allowed values {', '.join(KINDS)}")
        if wall.dtype.kind not in "iuf" or not ((wall == 0) | (wall == -1)).all():
            raise ValueError(f"wall={short_repr(self.wall)} is out of range: allowed values 0 (s = 0) and -1 (s = -1)")

    @property
    def impacts(self) -> np.ndarray:
        """Boolean mask of the impact rows."""
        return self.kind == "impact"

    @property
    def n_sticking(self) -> int:
        """Number of sticking episodes in the orbit."""
        return int(np.sum(self.kind == "stick"))

    def impact_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(tau, theta, sdot, wall)`` of the impact rows only."""
        m = self.impacts
        return self.tau[m], self.theta[m], self.sdot[m], self.wall[m]

    def rows(self) -> list[dict]:
        """The events as a list of dicts with the :data:`COLUMNS` keys."""
        return [
            {
                "n": int(n),
                "tau": float(t),
                "tau_mod_2pi": float(th),
                "wall": int(w),
                "sdot": (None if np.isnan(v) else float(v)),
                "kind": str(k),
            }
            for n, t, th, w, v, k in zip(self.n, self.tau, self.theta, self.wall, self.sdot, self.kind)
        ]

    def table(self) -> tuple[list[str], list[list]]:
        """``(header, rows)``: the :data:`COLUMNS` and one row per event (``sdot`` None on stick/release
        rows), for a CSV writer."""
        return list(COLUMNS), [[r[c] for c in COLUMNS] for r in self.rows()]

    def arrays(self) -> dict:
        """The events as arrays (``kind`` as text), the parameters, track and status: an NPZ file's
        content."""
        p = self.params
        return dict(
            n=self.n,
            tau=self.tau,
            tau_mod_2pi=self.theta,
            wall=self.wall,
            sdot=self.sdot,
            kind=np.asarray(self.kind, dtype=str),
            **p.as_dict(),
            track=self.track,
            status=self.status,
        )

    def as_dict(self) -> dict:
        """The parameters, status, track, the call's arguments (``meta``) and the event rows: a JSON
        file's content (:meth:`to_json`)."""
        p = self.params
        return {
            "params": p.as_dict(),
            "track": self.track,
            "status": self.status,
            "n_sticking": self.n_sticking,
            "meta": self.meta,
            "events": self.rows(),
        }

    def to_csv(self) -> str:
        """CSV text, one row per event, columns :data:`COLUMNS` (17 significant digits)."""
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        header, rows = self.table()
        w.writerow(header)
        for row in rows:
            w.writerow(["" if v is None else repr(v) if isinstance(v, float) else v for v in row])
        return buf.getvalue()

    def to_json(self) -> str:
        """Strict JSON text of :meth:`as_dict` (a NaN in ``meta`` raises ``ValueError``)."""
        return json.dumps(self.as_dict(), indent=1, allow_nan=False)


class StepJacobian(NamedTuple):
    """One impact-to-impact step with its Jacobian (every track's ``step_jacobian``).

    ``tau``, ``sdot``, ``wall``: the next pre-impact state (NaN when the orbit ended in this step);
    ``jac = d(tau_{n+1}, sdot_{n+1}) / d(tau_n, sdot_n)`` (2x2; 0 if the step sticks: a sticking step
    forgets its input, NaN if the flight failed); ``stuck``: the step stuck to the wall; ``status``:
    the orbit status after the step (:data:`~gear_rattle.core.status.TRACK_STATUSES`), with ``ok`` and
    ``message``.
    """

    tau: float
    sdot: float
    wall: int
    jac: np.ndarray
    stuck: bool
    status: str

    @property
    def ok(self) -> bool:
        """Whether the step worked (:class:`~gear_rattle.core.outcome.Outcome`: not ``step_cap``)."""
        return is_ok(self.status)

    @property
    def message(self) -> str:
        """What ``status`` means, in one line."""
        return describe(status_codes(self.status))


@runtime_checkable
class Track(Protocol):
    """What every track offers (the map, ``reference.scipy_track.TRACK``, ``reference.diffrax_track.TRACK``).

    ``orbit``: impact 0 plus ``n_impacts`` impacts from the pre-impact state ``(tau0, sdot0)`` (with
    ``-1 <= s0 <= 0``: from the free-flight state ``(tau0, s0, sdot0)``); ``step_jacobian``: one step
    from the pre-impact state ``(tau, sdot)`` on ``wall`` (default: the wall ``sdot`` points to) with
    its Jacobian.  ``options`` are the track's solver options; a bad argument or option raises a
    ``ValueError`` that names it.
    """

    @property
    def name(self) -> str: ...

    def orbit(
        self, params: Params, tau0: float, sdot0: float, n_impacts: int, s0: float | None = None, **options
    ) -> ImpactSequence: ...

    def step_jacobian(
        self, params: Params, tau: float, sdot: float, wall: int | None = None, **options
    ) -> StepJacobian: ...


@dataclass(frozen=True)
class TrackFunctions:
    """A :class:`Track` made of a name and two functions with the protocol's signatures."""

    name: str
    orbit: Callable[..., ImpactSequence]
    step_jacobian: Callable[..., StepJacobian]


__all__ = ["TRACKS", "KINDS", "COLUMNS", "ImpactSequence", "StepJacobian", "Track", "TrackFunctions"]
