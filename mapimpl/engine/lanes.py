"""The engine's data as named structures (JAX pytrees of arrays): an orbit's parameters, a queue of
initial conditions, the lane state, the run constants and the per-orbit results.

The parameters keep one form from the command line to the kernel: a
:class:`~gear_rattle.core.params.Params` becomes a :class:`~gear_rattle.core.params.ParamArrays`
(the same field names, arrays with one value per orbit) in :func:`gear_rattle.mapimpl.engine.driver.run`,
and a lane carries that ``ParamArrays`` itself, with the constants that depend on it alone beside it
(:class:`LaneParams`).  The same structures serve one lane (scalars, inside ``vmap``), a block of lanes
and a queue (one value per lane or initial condition) and, when every orbit of a run has the same
parameters, the run constants (scalars, :class:`RunConsts`).

Every field's dtype is fixed (:func:`lane_dtypes`); :func:`fill` builds a structure of any shape from it.
"""

from __future__ import annotations

from typing import Any, NamedTuple

from ...core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from ...core.deprecation import renamed_names
from ...core.params import ParamArrays

_F64, _I32, _BOOL = jnp.float64, jnp.int32, jnp.bool_


class ReleasePhase(NamedTuple):
    """The canonical release from one wall (:func:`mapimpl.sticking.release_phase`): its phase, the
    phase's sin and cos, and whether the tooth never leaves that wall."""

    phase: Any
    sin: Any
    cos: Any
    never: Any


class LaneParams(NamedTuple):
    """An orbit's parameters (``params``, :class:`~gear_rattle.core.params.ParamArrays`) and the
    constants that depend on them alone: the release from the wall ``s = 0`` (``top``) and from
    ``s = -1`` (``bottom``)."""

    params: ParamArrays
    top: ReleasePhase
    bottom: ReleasePhase


class Point(NamedTuple):
    """A pre-impact state: phase ``theta`` in ``[0, 2 pi)``, velocity, wall (0 or -1) and the phase's
    sin and cos."""

    theta: Any
    sdot: Any
    wall: Any
    sin: Any
    cos: Any


class Flight(NamedTuple):
    """The lane's current flight: start phase ``theta0`` and its sin/cos, start velocity ``v0`` and
    position ``s0`` (the wall), whole turns ``cycles0`` at the start, the sticking delay before it,
    whether it starts from a release, the finder's departure certificate ``t_depart`` and the decaying
    bound term ``bound`` (:func:`mapimpl.finder.safe_step`)."""

    theta0: Any
    sin0: Any
    cos0: Any
    v0: Any
    s0: Any
    cycles0: Any
    delay: Any
    released: Any
    t_depart: Any
    bound: Any


class Search(NamedTuple):
    """The search for the flight's next impact.  What each field holds depends on the lane's mode
    (:data:`gear_rattle.mapimpl.engine.kernel.SEARCH_FIELDS`): the modes use disjoint quantities, so
    they share fields, and a search micro-step reads and writes few arrays."""

    t: Any
    p1: Any
    p2: Any
    window: Any
    v_a: Any
    a_a: Any
    b_a: Any
    top: Any
    steps: Any
    root_iters: Any


class Lane(NamedTuple):
    """One lane of the engine (or a block of lanes): its mode and the initial condition it runs
    (``ic``, -1: none), the orbit's bookkeeping (impacts ``n``, whole turns ``cycles`` of the current
    state, sticking episodes ``nstick``, the impact of the first one ``first_stick``, the status it
    ends with), its parameters, the current pre-impact state ``at``, the current flight, the search
    and the observers' states (one dict per observer)."""

    mode: Any
    ic: Any
    n: Any
    cycles: Any
    nstick: Any
    first_stick: Any
    status: Any
    par: LaneParams
    at: Point
    flight: Flight
    search: Search
    obs: tuple


class Queue(NamedTuple):
    """Initial conditions with their parameters (:func:`gear_rattle.mapimpl.engine.kernel.prepare_queue`),
    and ``n_ic``, how many of them are loaded (the queue may be padded beyond)."""

    start: Point
    par: LaneParams
    n_ic: Any


class Results(NamedTuple):
    """Per-initial-condition results of the kernel, with the names of
    :class:`gear_rattle.mapimpl.engine.driver.EngineResult`: impacts done, status, sticking episodes,
    first sticking impact, the last pre-impact state (phase, velocity, wall, whole turns) and the
    observers' outputs (one dict per observer)."""

    n: Any
    status: Any
    nstick: Any
    first_stick: Any
    theta: Any
    sdot: Any
    wall: Any
    cycles: Any
    obs: tuple


class RunConsts(NamedTuple):
    """The run constants (:func:`gear_rattle.mapimpl.engine.kernel.make_consts`): the impact cap, the
    sticking threshold, the finder's caps, whether to stop at the first sticking, a run-time ``True``
    (for ``kernel._barrier``), the observers' constants and, when all orbits of the run share one
    parameter set, its :class:`LaneParams` as scalars (``None`` otherwise)."""

    cap: Any
    stick_time: Any
    t_max: Any
    max_steps: Any
    stop_at_stick: Any
    true: Any
    obs: tuple
    uniform: LaneParams | None


_RELEASE_PHASE = ReleasePhase(_F64, _F64, _F64, _BOOL)
#: The dtype of every field of :class:`LaneParams`.
PARAMS_DTYPES = LaneParams(ParamArrays(_F64, _F64, _F64, _F64), _RELEASE_PHASE, _RELEASE_PHASE)
#: The dtype of every field of :class:`Point`.
POINT_DTYPES = Point(_F64, _F64, _I32, _F64, _F64)


def lane_dtypes() -> Lane:
    """The dtype of every engine field of :class:`Lane` (``obs``: empty; the observers say theirs)."""
    return Lane(
        mode=_I32,
        ic=_I32,
        n=_I32,
        cycles=_I32,
        nstick=_I32,
        first_stick=_I32,
        status=_I32,
        par=PARAMS_DTYPES,
        at=POINT_DTYPES,
        flight=Flight(_F64, _F64, _F64, _F64, _F64, _I32, _F64, _BOOL, _F64, _F64),
        search=Search(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _BOOL, _I32, _I32),
        obs=(),
    )


#: The dtype of every engine field of :class:`Results`.
RESULT_DTYPES = Results(_I32, _I32, _I32, _I32, _F64, _F64, _I32, _I32, ())


def fill(dtypes, shape, value=0):
    """A structure of arrays of ``shape`` filled with ``value``, one per leaf of ``dtypes`` (a
    structure of dtypes, e.g. :func:`lane_dtypes`)."""
    return jax.tree_util.tree_map(lambda dt: jnp.full(shape, value, dt), dtypes)


#: The old name of :class:`ReleasePhase`, kept with a DeprecationWarning.
__getattr__ = renamed_names(__name__, {"Release": "ReleasePhase"}, globals())

__all__ = [
    "ReleasePhase",
    "LaneParams",
    "Point",
    "Flight",
    "Search",
    "Lane",
    "Queue",
    "Results",
    "RunConsts",
    "PARAMS_DTYPES",
    "POINT_DTYPES",
    "RESULT_DTYPES",
    "lane_dtypes",
    "fill",
]
