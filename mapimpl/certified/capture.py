"""The capture target of the release orbit and the certified capture decision.

An orbit is *captured* at the first pre-impact state within ``delta`` of the stable 4-impact
period-1 orbit of the Figs. 9-11 setting: sup norm of ``(wrapped phase difference, sdot
difference)`` to the nearest target point on the same wall (the engine's rule,
:func:`mapimpl.engine.observers.orbit_distance`).  Here the distance is a ball and the decision is
certified (:func:`capture_decision`).  The target is given by the caller as points taken as exact
numbers: for a certified ``T_post``, the float64 4-cycle of the engine
(:func:`mapimpl.engine.t_post.float64_target`; a certified distance to those points, not to the true
periodic orbit, which lies within ~1e-15 of them).  The certified track does not compute it: it
imports nothing of the float64 kernels (the import contract of pyproject.toml).
"""

from __future__ import annotations

from dataclasses import dataclass

from flint import arb

from .balls import CertificationError, exact


@dataclass(frozen=True)
class Target:
    """The capture target: pre-impact points ``(theta, sdot, wall)`` (float64, taken as exact)."""

    theta: tuple
    sdot: tuple
    wall: tuple

    def as_dict(self) -> dict:
        return {
            "theta": [repr(float(x)) for x in self.theta],
            "sdot": [repr(float(x)) for x in self.sdot],
            "wall": [int(w) for w in self.wall],
        }


def certified_distance(theta: arb, sdot: arb, wall: int, target: Target) -> arb | None:
    """Ball enclosing the sup-norm distance of the pre-impact state ``(theta, sdot)`` on ``wall`` to
    the nearest target point on the same wall (phase difference wrapped to ``[0, pi]``), as
    :func:`mapimpl.engine.observers.orbit_distance` defines it; ``None`` (infinite) when no point is on
    ``wall``.  ``theta`` must lie in ``[0, 2 pi)``."""
    two_pi = 2 * arb.pi()
    best = None
    for th_p, v_p, w_p in zip(target.theta, target.sdot, target.wall):
        if w_p != wall:
            continue
        dth = abs(theta - arb(th_p))
        d = dth.min(two_pi - dth).max(abs(sdot - arb(v_p)))
        best = d if best is None else best.min(d)
    return best


def capture_decision(distance: arb | None, delta: float) -> bool:
    """Whether the pre-impact state at the certified ``distance`` (:func:`certified_distance`; ``None``:
    no target point on its wall) is captured: certified ``distance < delta`` (True) or ``>= delta``
    (False); raises :class:`~.balls.CertificationError` when the ball straddles ``delta``."""
    if distance is None:
        return False
    dl = exact(delta)
    if distance < dl:
        return True
    if distance >= dl:
        return False
    raise CertificationError(f"capture decision not definite: distance {distance.str(5)} straddles delta={delta:g}")


__all__ = [
    "Target",
    "certified_distance",
    "capture_decision",
]
