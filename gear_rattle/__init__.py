"""gear-rattle: reference implementation of the single-stage gear-rattling impact model of de Souza,
Caldas, Viana and Balthazar, Chaos, Solitons & Fractals 21 (2004) 763-772.

The installed namespace has three parts (the repository's top-level folders):

* :mod:`gear_rattle.core` -- the vocabulary every layer shares: parameters, status codes, result types,
  the paper's settings;
* :mod:`gear_rattle.mapimpl` -- the closed-form flight (Eqs. 7-8), the certified impact finder, the
  impact map (Eqs. 12-13) with its Jacobian, periodic orbits, Lyapunov exponents, the many-orbit
  engine (JAX, float64), the certified track in ball arithmetic and the registry of tracks;
* :mod:`gear_rattle.reference` -- Eq. (3) integrated numerically (scipy and diffrax tracks);
* :mod:`gear_rattle.validation` -- cross-checks, the reproduction of the paper, the CLI and the report.

The layers and who may import whom: docs/architecture.md.

This module is a small facade over the most used entry points::

    import gear_rattle as gr
    p = gr.Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.9)
    seq = gr.orbit(p, tau0=0.0, sdot0=0.5, n_impacts=1000, track="map")

Importing it switches JAX to float64 and changes nothing else (no device split, no matplotlib
backend): :func:`use_cpu_devices` opts in to one XLA CPU device per core before JAX starts.  It does
not import JAX itself (numpy only): JAX is imported where a computation first needs it, so that
``gear-rattle check`` runs with numpy alone (docs/golden.md, "Using the suite in CI").
"""

from __future__ import annotations

# first: in the command line, core._jax takes over Ctrl-C before anything slow is imported
from .core._jax import use_cpu_devices
from .core.params import Params
from .core.results import TRACKS

from importlib import metadata as _metadata

try:
    #: The installed distribution's version (``gear-rattle --version``).
    __version__ = _metadata.version("gear-rattle")
except _metadata.PackageNotFoundError:  # a source tree on sys.path without an install
    __version__ = "0+unknown"

__all__ = ["__version__", "Params", "orbit", "find_periodic", "lyapunov", "transient_times", "use_cpu_devices", "TRACKS"]



def _renamed(old: str, new: str, value, old_value):
    """The value of a keyword argument renamed from ``old`` to ``new`` (the old name still works, with a
    DeprecationWarning); ``TypeError`` when both are given."""
    if old_value is None:
        return value
    if value is not None:
        raise TypeError(f"give {new}= or its old name {old}=, not both")
    import warnings

    warnings.warn(f"{old}= is deprecated: use {new}= (same meaning)", DeprecationWarning, stacklevel=3)
    return old_value


def orbit(params: Params, tau0: float, sdot0: float, n_impacts: int, *, track: str = "map",
          s0: float | None = None, progress=False, **solver_options):
    """Impact sequence of one orbit on ``track``: impact 0, then ``n_impacts`` further impacts.

    Parameters
    ----------
    params : Params
        The model's parameters ``alpha, beta, gamma, r`` of Eq. (3) and the reset of Eq. (11).
    tau0, sdot0 : float
        Impact 0 as a pre-impact state (the paper's map variables, Eqs. 12-13): time ``tau0`` and
        velocity ``sdot0 != 0`` just before the impact (``sdot0 > 0`` hits ``s = 0``, ``sdot0 < 0``
        hits ``s = -1``); with ``s0``, the free state ``(tau0, s0, sdot0)`` whose flight's first
        impact is impact 0.
    n_impacts : int
        Impacts after impact 0, ``0 <= n_impacts <= 1e7`` (every impact is kept in memory; an orbit that
        sticks forever or never lands again ends early).
    track : {"map", "scipy", "diffrax", "certified"}
        The closed-form impact map (:mod:`gear_rattle.mapimpl.orbit`), a numerical integration of
        Eq. (3) (:mod:`gear_rattle.reference`; :data:`TRACKS`), or the certified track
        (:mod:`gear_rattle.mapimpl.certified.track`: every row proven in ball arithmetic, the values the
        float64 nearest to the exact ones and float64 bounds in ``seq.bounds``; it raises
        :class:`~gear_rattle.mapimpl.certified.track.UncertifiedOrbit`, holding the certified prefix, where
        no precision up to its limit certifies every impact).
    s0 : float, optional
        A start in free flight, ``-1 <= s0 <= 0``.
    progress : bool, optional
        True for a bar on a terminal (:mod:`gear_rattle.core.progress`).
    **solver_options
        Of the numerical tracks: ``rtol``, ``atol``, ``t_max`` and ``max_step`` (scipy) or ``dtmax``,
        ``max_steps`` (diffrax); the map track takes none; the certified track ``stick_time``, ``prec``,
        ``max_prec`` (the precision schedule's start and limit, bits), ``t_max`` and ``time_budget_s``.

    Returns
    -------
    ImpactSequence
        :class:`gear_rattle.core.results.ImpactSequence`: per event ``n, tau, theta = tau mod 2 pi,
        wall, sdot, kind`` and the orbit's ``status``.

    Raises
    ------
    ValueError, TypeError
        For an argument out of range or of the wrong type, naming it and its range
        (:mod:`gear_rattle.core.checks`), before anything is computed.

    Examples
    --------
    The same orbit on the closed-form map and on scipy's integration of Eq. (3):

    >>> import gear_rattle as gr
    >>> p = gr.Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.9)
    >>> seq = gr.orbit(p, tau0=0.0, sdot0=0.5, n_impacts=10, track="map")
    >>> seq.wall[:5].tolist()
    [0, -1, -1, 0, 0]
    >>> print(f"{seq.tau[10]:.6f}", seq.status)
    10.831944 active
    >>> ref = gr.orbit(p, tau0=0.0, sdot0=0.5, n_impacts=10, track="scipy")
    >>> bool(abs(ref.tau - seq.tau).max() < 1e-8)
    True
    """
    from .mapimpl.tracks import orbit as _orbit

    return _orbit(track, params, tau0, sdot0, n_impacts, s0=s0, progress=progress, **solver_options)


def find_periodic(params: Params, tau0: float, sdot0: float, period: int | None = None, turns: int = 1, *,
                  tol: float = 1e-12, max_iter: int = 60, impacts: int | None = None):
    """Newton search for a periodic orbit with ``period`` impacts per ``turns`` driving periods.

    The facade of :func:`gear_rattle.mapimpl.periodic.find_periodic`.

    Parameters
    ----------
    params : Params
        The model's parameters.
    tau0, sdot0 : float
        A guess of one pre-impact state of the orbit.
    period : int
        Impacts per period, ``1 <= period <= 100000``.
    turns : int, optional
        Driving periods (``2 pi``) per period, ``1 <= turns <= 100000``.
    tol, max_iter : optional
        Newton's tolerance on the residual, ``1e-15 <= tol <= 1e-6``, and most iterations,
        ``1 <= max_iter <= 10000``.
    impacts : int, optional
        The old name of ``period`` (a DeprecationWarning).

    Returns
    -------
    PeriodicOrbit
        :class:`gear_rattle.mapimpl.periodic.PeriodicOrbit`: the states, walls and Floquet multipliers.

    Examples
    --------
    Fig. 2 (alpha = 0.5): the regular motion is a stable orbit of three impacts per period:

    >>> import gear_rattle as gr
    >>> orb = gr.find_periodic(gr.Params(0.5, 0.1, 0.1, 0.9), 2.034, -0.7343, period=3)
    >>> orb.converged, orb.walls.tolist(), orb.stable
    (True, [-1, 0, 0], True)
    """
    from .mapimpl.periodic import check_newton, find_periodic as _find

    period = _renamed("impacts", "period", period, impacts)
    check_newton(period, turns, tol, max_iter, names=("period", "turns"))  # named as here
    return _find(params, tau0, sdot0, period, turns, tol=tol, max_iter=max_iter)


def lyapunov(params: Params, param: str = "r", values=None, *, n_impacts: int | None = None, transient: int = 1000,
             tau0: float = 0.0, sdot0: float = 0.5, progress=None, n: int | None = None):
    """Lyapunov exponents of the impact map (QR method) at ``values`` of ``param`` (default: the
    value in ``params``), averaged over ``n_impacts`` impacts (default 20000, at most 5e7) after ``transient``
    (at most 5e7); see :func:`gear_rattle.mapimpl.lyapunov.lyapunov` (``n=`` is the old name of
    ``n_impacts``) and :func:`~gear_rattle.mapimpl.lyapunov.check_arguments` (the ranges)."""
    from .mapimpl.lyapunov import check_arguments, lyapunov as _lyap

    n_impacts = _renamed("n", "n_impacts", n_impacts, n)
    n_impacts = 20000 if n_impacts is None else n_impacts
    check_arguments(params, param, values, n_impacts, transient, tau0, sdot0, names=("params", "n_impacts"))
    return _lyap(params, param, values, n=n_impacts, transient=transient, tau0=tau0, sdot0=sdot0, progress=progress)


def transient_times(tau0, sdot0, params: Params | None = None, *, ic_mode: str = "pre-impact", s0=None,
                    delta: float | None = None, deltas=None, cap: int = 20000, sticking: str = "compose",
                    lanes: int | None = None, progress=None, stick_time: float | None = None, devices=None,
                    release: str | None = None):
    """Transient durations until capture by the stable periodic orbit, for many initial conditions.

    The facade of :func:`gear_rattle.mapimpl.engine.transients.transient_times` (the meaning of every
    argument); ``delta``, ``deltas``, ``stick_time``: None for that function's defaults.

    Parameters
    ----------
    tau0, sdot0 : array_like
        The initial conditions (pre-impact states, or free states with ``ic_mode``/``s0``).
    params : Params, optional
        Default: the paper's Figs. 9-11, alpha = 1.245, beta = gamma = 0.1, r = 0.9
        (:data:`gear_rattle.core.paper.PAPER_PARAMS`).
    ic_mode, s0, delta, deltas, cap, sticking, lanes, progress, stick_time, devices : optional
        As in :func:`gear_rattle.mapimpl.engine.transients.transient_times`.
    release : optional
        Deprecated spelling of ``sticking``.

    Returns
    -------
    TransientResult
        :class:`gear_rattle.mapimpl.engine.transients.TransientResult`.

    Examples
    --------
    >>> import numpy as np, gear_rattle as gr
    >>> res = gr.transient_times(np.linspace(0.0, 6.0, 8), np.ones(8), cap=2000, progress=False)
    >>> res.hit.shape[0]
    8
    """
    from .mapimpl.engine.transients import transient_times as _tt
    from .core.paper import PAPER_PARAMS

    kw = {k: v for k, v in dict(delta=delta, deltas=deltas, stick_time=stick_time).items() if v is not None}
    return _tt(tau0, sdot0, PAPER_PARAMS if params is None else params, ic_mode=ic_mode, s0=s0, cap=cap,
               sticking=sticking, release=release, lanes=lanes, progress=progress, devices=devices, **kw)
