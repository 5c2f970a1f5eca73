"""Lyapunov exponents from the :class:`~gear_rattle.mapimpl.engine.observers.Tangent` observer's output:
the one function that turns tangent data into exponents (:func:`exponents`), with the one rule for
steps that stick and for orbits that ended early.

The observer sums ``log_r = sum ln |R_n[i, i]|`` over the free steps of its window and counts them
(``n_free``) and the sticking ones (``n_stuck``).  From these, per orbit:

* ``lam_free = log_r / n_free``: the exponents of the free steps (Q restarts at the identity after a
  sticking step); NaN where no step was free;
* ``lam``, the formal exponents: ``lam_free`` where no step stuck, ``-inf`` where one did (a sticking
  step forgets its input, ``J = 0``, and the product of Jacobians vanishes);
* **an orbit that ended early has no exponents**: where the orbit was not still going when the run
  ended -- its engine status is neither ``CAPPED`` (the impact cap reached) nor ``STOPPED`` (an
  observer's criterion met) but ``STUCK_FOREVER``, ``NO_IMPACT``, ``STEP_CAP`` or ``NOT_RUN`` -- both
  ``lam`` and ``lam_free`` are NaN, whatever it did before it ended: an average over fewer steps than
  asked, of a motion that did not last, is not the attractor's exponent (:attr:`Exponents.ran` says
  which orbits ran to the end).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...core.status import Status
from .driver import EngineResult
from .observers import Tangent

#: Engine statuses of an orbit still going when its run ended (:func:`ran_to_end`).
RAN_TO_END = (int(Status.STOPPED), int(Status.CAPPED))


def ran_to_end(status) -> np.ndarray:
    """Per orbit, whether it was still going when its run ended (engine status ``STOPPED`` or
    ``CAPPED``): the orbits that have exponents (the module docstring)."""
    return np.isin(np.asarray(status), RAN_TO_END)


@dataclass(frozen=True)
class Exponents:
    """Lyapunov exponents per impact (natural log) of the orbits of one engine run, by the module's rule.

    ``lam``: (m, 2) formal exponents (``-inf`` where a step stuck, NaN where the orbit ended early);
    ``lam_free``: (m, 2) exponents of the free steps (NaN where the orbit ended early or no step was
    free); ``n_free``, ``n_stuck``: steps of the window that were free and that stuck; ``ran``: the
    orbit was still going when the run ended (:func:`ran_to_end`).
    """

    lam: np.ndarray
    lam_free: np.ndarray
    n_free: np.ndarray
    n_stuck: np.ndarray
    ran: np.ndarray

    @property
    def ended(self) -> int:
        """Orbits that ended early (no exponents)."""
        return int(np.sum(~self.ran))


def exponents(res: EngineResult, obs: int = 0) -> Exponents:
    """The Lyapunov exponents of the orbits of ``res``, an engine run whose observer number ``obs`` was a
    :class:`~gear_rattle.mapimpl.engine.observers.Tangent`, by the one rule of this module (NaN for an
    orbit that ended early, ``-inf`` in ``lam`` where a step stuck).

    Examples
    --------
    Fig. 4's chaotic attractor (alpha = 3, r = 0.9) and an orbit stuck forever (alpha = 0.05, r = 0.5):

    >>> import numpy as np
    >>> from gear_rattle.mapimpl.engine.driver import run
    >>> from gear_rattle.mapimpl.engine.exponents import exponents
    >>> from gear_rattle.mapimpl.engine.observers import Tangent
    >>> p = {"alpha": np.array([3.0, 0.05]), "beta": 0.1, "gamma": 0.1, "r": np.array([0.9, 0.5])}
    >>> ex = exponents(run([0.0, 0.0], [0.5, 0.5], [0, 0], p, Tangent(n_start=100), cap=1100, progress=False))
    >>> bool(ex.lam[0, 0] > 0.3), bool(np.all(np.isnan(ex.lam[1]))), ex.ran.tolist(), ex.ended
    (True, True, [True, False], 1)
    """
    if not isinstance(res, EngineResult):
        raise TypeError(f"res is a {type(res).__name__}: allowed an EngineResult of mapimpl.engine.driver.run")
    if not 0 <= obs < len(res.obs) or set(Tangent().outputs()) - set(res.obs[obs]):
        raise ValueError(f"obs={obs!r} is out of range: allowed the index of a Tangent observer of the run")
    t = res.obs[obs]
    ran = ran_to_end(res.status)
    n_stuck, n_free = np.asarray(t["n_stuck"]).astype(int), np.asarray(t["n_free"]).astype(int)
    lam_free = np.asarray(t["log_r"]) / np.maximum(n_free, 1)[:, None]
    lam_free = np.where(ran[:, None] & (n_free[:, None] > 0), lam_free, np.nan)
    lam = np.where(n_stuck[:, None] > 0, -np.inf, lam_free)
    lam = np.where(ran[:, None], lam, np.nan)
    return Exponents(lam, lam_free, n_free, n_stuck, ran)


__all__ = [
    "RAN_TO_END",
    "ran_to_end",
    "Exponents",
    "exponents",
]
