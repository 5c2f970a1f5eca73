"""The paper's settings that the library uses: parameters of its figures, its box and the capture rule.

de Souza, Caldas, Viana and Balthazar, Chaos, Solitons & Fractals 21 (2004) 763-772.  Every module
takes these from here (a guard test, ``tests/test_layers.py``, finds a second definition).  The
numbers the paper *reports* (``<n> = 2272``, ``kappa = 0.893``, ``r2``, ...), with their quotes, are
in :mod:`gear_rattle.validation.paper`.
"""

from __future__ import annotations

from .params import Params

#: The parameters of Figs. 9-11 as printed (exact decimals: the certified track encloses these).
PAPER_DECIMAL = {"alpha": "1.245", "beta": "0.1", "gamma": "0.1", "r": "0.9"}
#: The setting of Figs. 9-11 (the float64 values of :data:`PAPER_DECIMAL`): just past the crisis alpha_1.
PAPER_PARAMS = Params(**{k: float(v) for k, v in PAPER_DECIMAL.items()})
#: The parameters of Fig. 2 as printed (regular motion: alpha = 0.5, beta = gamma = 0.1, r = 0.9).
PAPER_FIG2_DECIMAL = {"alpha": "0.5", "beta": "0.1", "gamma": "0.1", "r": "0.9"}
#: The parameters of Fig. 2: the float64 values of :data:`PAPER_FIG2_DECIMAL`.
PAPER_FIG2 = Params(**{k: float(v) for k, v in PAPER_FIG2_DECIMAL.items()})
#: The parameters of Figs. 3-7 as printed (exact decimals: the certified r2 encloses the fold of these).
PAPER_FIG3_DECIMAL = {"alpha": "3.0", "beta": "0.1", "gamma": "0.1", "r": "0.9"}
#: The parameters of Figs. 3-7 (alpha = 3, beta = gamma = 0.1, r = 0.9): the float64 values of
#: :data:`PAPER_FIG3_DECIMAL`.
PAPER_FIG3 = Params(**{k: float(v) for k, v in PAPER_FIG3_DECIMAL.items()})
#: The paper's box (Figs. 10 and 11): 3.0 < tau0 < 3.5, 0 < sdot0 < 0.5.
PAPER_BOX = (3.0, 3.5, 0.0, 0.5)
#: Capture distance: an orbit is captured by the stable periodic orbit at the first pre-impact state
#: within ``DELTA`` of it (sup norm of the wrapped phase and the sdot differences, same wall;
#: :func:`gear_rattle.mapimpl.engine.observers.orbit_distance`).
DELTA = 1e-3
#: The capture distances recorded alongside :data:`DELTA` (Fig. 11's sensitivity to the rule).
DELTAS = (1e-2, 1e-3, 1e-4, 1e-6)


def recorded_deltas(delta: float) -> tuple[float, ...]:
    """The capture distances a Fig. 11 run records: :data:`DELTAS` with the run's own ``delta`` in the
    place of :data:`DELTA` (``recorded_deltas(DELTA) == DELTAS``)."""
    return tuple(delta if d == DELTA else d for d in DELTAS)


#: Largest capture distance accepted anywhere (``0 < delta <= MAX_DELTA``): a distance the size of the
#: phase space would capture every orbit at once.
MAX_DELTA = 10.0

__all__ = [
    "PAPER_DECIMAL",
    "PAPER_PARAMS",
    "PAPER_FIG2_DECIMAL",
    "PAPER_FIG2",
    "PAPER_FIG3_DECIMAL",
    "PAPER_FIG3",
    "PAPER_BOX",
    "DELTA",
    "DELTAS",
    "MAX_DELTA",
    "recorded_deltas",
]
