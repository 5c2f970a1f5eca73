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
backend): :func:`use_cpu_devices` opts in to one XLA CPU device per core before JAX starts.
"""

from __future__ import annotations

# first: in the command line, core._jax takes over Ctrl-C before anything slow is imported
from .core._jax import use_cpu_devices
from .core.params import Params
from .core.results import TRACKS

from importlib import metadata as _metadata  # noqa: E402

try:
    #: The installed distribution's version (``gear-rattle --version``).
    __version__ = _metadata.version("gear-rattle")
except _metadata.PackageNotFoundError:  # a source tree on sys.path without an install
    __version__ = "0+unknown"

__all__ = ["__version__", "Params", "orbit", "find_periodic", "lyapunov", "transient_times", "use_cpu_devices", "TRACKS"]



def orbit(params: Params, tau0: float, sdot0: float, n_impacts: int, *, track: str = "map",
          s0: float | None = None, **options):
    """Impact sequence of one orbit (:class:`gear_rattle.core.results.ImpactSequence`) on ``track``:
    impact 0 is the pre-impact state ``(tau0, sdot0)`` (or, with ``s0``, the first impact of the
    free flight from ``(tau0, s0, sdot0)``), then ``n_impacts`` further impacts."""
    from .mapimpl.tracks import orbit as _orbit

    return _orbit(track, params, tau0, sdot0, n_impacts, s0=s0, **options)


def find_periodic(params: Params, tau0: float, sdot0: float, impacts: int, turns: int = 1, **options):
    """Newton search for a periodic orbit with ``impacts`` impacts per ``turns`` driving periods
    (:func:`gear_rattle.mapimpl.periodic.find_periodic`)."""
    from .mapimpl.periodic import find_periodic as _find

    return _find(params, tau0, sdot0, impacts, turns, **options)


def lyapunov(params: Params, param: str = "r", values=None, **options):
    """Lyapunov exponents of the impact map (QR method) at ``values`` of ``param`` (default: the
    value in ``params``); see :func:`gear_rattle.mapimpl.lyapunov.lyapunov`."""
    from .mapimpl.lyapunov import lyapunov as _lyap

    return _lyap(params, param, values, **options)


def transient_times(tau0, sdot0, params: Params | None = None, **options):
    """Transient durations until capture by the stable periodic orbit, for many initial conditions
    (:func:`gear_rattle.mapimpl.engine.transients.transient_times`; default parameters: the paper's
    Figs. 9-11, alpha = 1.245, beta = gamma = 0.1, r = 0.9)."""
    from .mapimpl.engine.transients import transient_times as _tt
    from .core.paper import PAPER_PARAMS

    return _tt(tau0, sdot0, PAPER_PARAMS if params is None else params, **options)
