"""The capture rule of an orbit that sticks (Figs. 9-11), written once, and the typed source of its
post-release duration.

Every orbit that sticks to a wall is released at that wall's canonical phase with sdot = 0
(:func:`mapimpl.sticking.release_phase`), so all of them continue on ONE post-release orbit per wall.
The engine (:func:`.transients.transient_times`) returns raw facts: ``hit`` (the first iteration within
each capture distance before the orbit first stuck), ``first_stick`` and ``stick_wall``, and per wall
the float64 post-release orbit it ran once (:class:`PostReleaseOrbit`).  A duration is composed from them by
ONE function, :func:`compose_durations`, with a :class:`TPost`: the post-release duration ``T_post``
of every wall at one capture distance, each with the :class:`ReleaseSource` it came from -- the float64
engine's own post-release orbit (a sample of a chaotic orbit) or a value certified in ball arithmetic
(:mod:`.t_post` builds either).  The rule itself, ``first_stick + T_post`` censored beyond the cap, is
:func:`compose_release`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum
from typing import TYPE_CHECKING, Any

import numpy as np

from ...core.deprecation import renamed_names

if TYPE_CHECKING:
    from ..certified.duration import ReleaseDuration

#: The walls an orbit can stick to (0: s = 0, -1: s = -1).
WALLS = (0, -1)


class ReleaseSource(StrEnum):
    """Where the post-release duration ``T_post`` of the orbits that stick comes from."""

    #: The float64 engine's own post-release orbit: a sample of a chaotic orbit, not a value.
    FLOAT64 = "float64"
    #: Certified in ball arithmetic for the parameters' decimals as printed (``"1.245"``).
    CERTIFIED = "certified"
    #: Certified in ball arithmetic for the float64 roundings of those decimals (exact binary values).
    CERTIFIED_FLOAT64_ROUNDING = "certified-float64-rounding"

    @classmethod
    def of(cls, value: Any, name: str = "release") -> ReleaseSource:
        """``value`` (a member or its string) as a member; ``ValueError`` naming ``name`` otherwise."""
        try:
            return cls(value)
        except ValueError:
            raise ValueError(
                f"{name}={value!r} is out of range: allowed one of {', '.join(repr(m.value) for m in cls)}"
            ) from None

    @property
    def rounding(self) -> str | None:
        """The rounding of a certified source (``"decimal"``, ``"float64"``); None for the float64 sample."""
        return {ReleaseSource.CERTIFIED: "decimal", ReleaseSource.CERTIFIED_FLOAT64_ROUNDING: "float64"}.get(self)


@dataclass(frozen=True, eq=False)
class PostReleaseOrbit:
    """One wall's post-release orbit as the float64 engine ran it, once: followed from initial
    condition ``ic`` (which first stuck at impact ``first_stick``); ``t_post[j]``: its duration within
    ``deltas[j]`` counted from the release (its first impact is 1; -1: beyond the cap); ``impacts``:
    impacts it ran after the release."""

    wall: int
    ic: int
    first_stick: int
    t_post: np.ndarray
    impacts: int

    def as_dict(self) -> dict:
        """The entry of :meth:`.transients.TransientResult.summary` (``T_post`` as a list)."""
        return {
            "wall": self.wall,
            "ic": self.ic,
            "first_stick": self.first_stick,
            "T_post": self.t_post.tolist(),
            "impacts": self.impacts,
        }


#: The fields of a certification kept in a result's files (:meth:`WallTPost.as_dict`).
CERTIFIED_FIELDS = (
    "params",
    "rounding",
    "wall",
    "delta",
    "status",
    "value",
    "precision",
    "confirmed",
    "lower_bound",
    "release_phase",
    "seconds",
)


def certified_dict(c: ReleaseDuration) -> dict:
    """The fields :data:`CERTIFIED_FIELDS` of a certification, for a result's files."""
    d = c.to_dict()
    return {k: d[k] for k in CERTIFIED_FIELDS}


@dataclass(frozen=True)
class WallTPost:
    """The post-release duration composed for the orbits that stuck to ``wall`` at one capture
    distance: ``value`` (None: never captured) from ``source`` -- the float64 sample when the
    certification asked for was undecided (``undecided``) --, ``float64_sample`` (the engine's own,
    -1: beyond the cap) and ``certified`` (the certification, when one was asked for)."""

    wall: int
    value: int | None
    source: ReleaseSource
    float64_sample: int
    certified: ReleaseDuration | None = None
    undecided: bool = False

    def as_dict(self) -> dict:
        """The entry of a result's JSON: ``float64_sample``, ``certified`` (when asked for), ``used``
        and ``source`` (in words)."""
        out: dict = {"float64_sample": self.float64_sample}
        if self.certified is not None:
            out["certified"] = certified_dict(self.certified)
        words = {
            ReleaseSource.FLOAT64: "float64 sample",
            ReleaseSource.CERTIFIED: "certified",
            ReleaseSource.CERTIFIED_FLOAT64_ROUNDING: "certified (float64 rounding)",
        }[self.source]
        out["used"], out["source"] = self.value, words + (" (certification undecided)" if self.undecided else "")
        return out


@dataclass(frozen=True)
class TPost:
    """What the orbits that stick are composed with at capture distance ``delta``: one
    :class:`WallTPost` per wall stuck to (``walls``), asked from ``source``."""

    source: ReleaseSource
    delta: float
    walls: Mapping[int, WallTPost]

    def t_post(self, wall: int) -> int | None:
        """The ``T_post`` composed for ``wall`` (None: never captured)."""
        return self.walls[wall].value

    def info(self) -> dict:
        """Per wall (``"0"``, ``"-1"``) the entry :meth:`WallTPost.as_dict` of a result's JSON."""
        return {str(w): t.as_dict() for w, t in self.walls.items()}


def compose_release(first_stick, t_post, cap: int) -> np.ndarray:
    """The capture rule of an orbit that sticks (see the module docstring): its duration is
    ``first_stick + T_post`` -- the impact at which it first stuck plus the post-release orbit's own
    duration counted from the release -- or -1 (censored) when ``T_post < 0`` (never captured) or the
    sum exceeds ``cap``.  Broadcasts ``first_stick`` against ``t_post``; returns int64."""
    first = np.asarray(first_stick, np.int64)
    tp = np.asarray(t_post, np.int64)
    comp = first + tp
    return np.where((tp >= 0) & (comp <= int(cap)), comp, -1)


def composed_mask(hit: np.ndarray, first_stick: np.ndarray) -> np.ndarray:
    """The orbits whose duration comes from the release: they stuck (``first_stick >= 0``) before
    coming within the capture distance (``hit < 0``, one column of the raw ``hit``)."""
    return (np.asarray(first_stick) >= 0) & (np.asarray(hit) < 0)


def compose_durations(
    hit: np.ndarray, first_stick: np.ndarray, stick_wall: np.ndarray, cap: int, release: TPost
) -> tuple[np.ndarray, np.ndarray]:
    """``(durations, censored)`` at ``release.delta`` -- THE composition of a duration, used by every
    caller: ``hit`` (the raw first iteration within ``release.delta``, one column), or for an orbit
    that stuck to wall ``w`` before that (:func:`composed_mask`) ``first_stick + T_post[w]``
    (:func:`compose_release`) with the ``T_post`` of ``release``; censored orbits (-1) set to ``cap``."""
    h = np.asarray(hit).astype(np.int64)
    pending = composed_mask(h, first_stick)
    for w, t in release.walls.items():
        sel = pending & (np.asarray(stick_wall) == int(w))
        h = np.where(sel, compose_release(first_stick, -1 if t.value is None else t.value, cap), h)
    censored = h < 0
    return np.where(censored, int(cap), h), censored


def float64_t_post(post_release, deltas: np.ndarray, delta: float, column: int) -> TPost:
    """The :class:`TPost` of the float64 engine's own post-release orbits (``post_release``, a
    sequence of :class:`PostReleaseOrbit`) at ``delta = deltas[column]`` (-1: beyond the cap, never captured)."""
    walls = {}
    for pr in post_release:
        sample = int(np.asarray(pr.t_post)[column])
        walls[int(pr.wall)] = WallTPost(int(pr.wall), sample if sample >= 0 else None, ReleaseSource.FLOAT64, sample)
    return TPost(ReleaseSource.FLOAT64, float(deltas[column]), walls)


#: The old names (one word, "release", named six things: issue 39), kept with a DeprecationWarning.
__getattr__ = renamed_names(
    __name__,
    {"Release": "TPost", "PostRelease": "PostReleaseOrbit", "float64_release": "float64_t_post"},
    globals(),
)

__all__ = [
    "WALLS",
    "ReleaseSource",
    "PostReleaseOrbit",
    "CERTIFIED_FIELDS",
    "certified_dict",
    "WallTPost",
    "TPost",
    "compose_release",
    "composed_mask",
    "compose_durations",
    "float64_t_post",
]
