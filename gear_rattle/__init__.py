"""gear-rattle: reference implementation of the single-stage gear-rattling impact model of de Souza,
Caldas, Viana and Balthazar, Chaos, Solitons & Fractals 21 (2004) 763-772.

The installed namespace has four parts (the repository's top-level folders):

* :mod:`gear_rattle.core` -- the vocabulary every layer shares: parameters, status codes, result types,
  the paper's settings;
* :mod:`gear_rattle.mapimpl` -- the closed-form flight (Eqs. 7-8), the certified impact finder, the
  impact map (Eqs. 12-13) with its Jacobian, periodic orbits, Lyapunov exponents, the many-orbit
  engine (JAX, float64), the certified track in ball arithmetic and the registry of tracks;
* :mod:`gear_rattle.reference` -- Eq. (3) integrated numerically (scipy and diffrax tracks);
* :mod:`gear_rattle.validation` -- cross-checks, the reproduction of the paper, the CLI and the report.

The layers and who may import whom: docs/architecture.md.

This module is the public API (``__all__``; ``dir(gear_rattle)`` shows it and nothing else): the most used
entry points and the types they return, each the library's own object under the library's own name
(``gr.orbit is gear_rattle.mapimpl.tracks.orbit``)::

    import gear_rattle as gr

    p = gr.Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.9)
    seq = gr.orbit(p, tau0=0.0, sdot0=0.5, n_impacts=1000, track="map")

The vocabulary: every function takes ``params`` first; ``n_impacts`` is a count of impacts computed,
``cap`` the most impacts before an orbit is censored, ``period`` the impacts per period of a periodic
orbit (``turns`` its driving periods); ``tau`` is absolute time and ``theta = tau mod 2 pi`` the phase;
``progress=None`` (a bar when stderr is a terminal) everywhere.  Every result says whether it worked the
same way: ``ok``, ``status`` and ``message``, built on :class:`~gear_rattle.core.status.Status`
(:class:`gear_rattle.core.outcome.Outcome`).  The old spellings (``impacts=``, ``n=``, ``PeriodicOrbit.tau``,
``.impacts``, ``orbit(track, params, ...)``, ``transient_times(tau0, sdot0, params)``) still work, with a
DeprecationWarning naming the new one.

Importing it switches JAX to float64 and changes nothing else (no device split, no matplotlib
backend, no signal handler): :func:`use_cpu_devices` opts in to one XLA CPU device per core before JAX
starts.  It imports neither JAX nor numpy, nor the command line: every public name but
:func:`use_cpu_devices`, :data:`TRACKS` and :class:`Status` is loaded on first use (PEP 562), and so is
the display of progress bars (:mod:`gear_rattle.validation.progress`, when the first bar is drawn).
``import gear_rattle`` loads seven small modules and no other package; ``gear-rattle check`` runs with
numpy alone (docs/reference/golden_commands.md, "In CI").
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .core.jax_config import use_cpu_devices
from .core.progress import set_display as _set_display
from .core.registry import TRACKS
from .core.status import Status
from . import _tracks  # noqa: F401  (registers the numerical tracks' loaders: core.registry)

if TYPE_CHECKING:  # what the names loaded on first use are, for type checkers
    from .core.params import Params
    from .core.results import ImpactSequence, StepJacobian
    from .mapimpl.certified.track import CertifiedSequence
    from .mapimpl.engine.transients import TransientResult, transient_times
    from .mapimpl.lyapunov import LyapunovResult, lyapunov
    from .mapimpl.periodic import PeriodicOrbit, find_periodic
    from .mapimpl.tracks import orbit
    from .validation.transient.results import SurvivalResult

    __version__: str

#: The public names loaded on first use (they import numpy, JAX or the analyses): see :func:`_module`.
_LAZY = (
    "__version__",
    "Params",
    "ImpactSequence",
    "StepJacobian",
    "orbit",
    "find_periodic",
    "lyapunov",
    "transient_times",
    "PeriodicOrbit",
    "LyapunovResult",
    "TransientResult",
    "SurvivalResult",
    "CertifiedSequence",
)

__all__ = [
    "__version__",
    "Params",
    "TRACKS",
    "Status",
    "use_cpu_devices",
    "orbit",
    "find_periodic",
    "lyapunov",
    "transient_times",
    "ImpactSequence",
    "CertifiedSequence",
    "StepJacobian",
    "PeriodicOrbit",
    "LyapunovResult",
    "TransientResult",
    "SurvivalResult",
]


def _display(label: str, **kw):
    """The display of every progress bar (:func:`gear_rattle.validation.progress.display`), imported when
    the first bar is drawn: importing it registers it in place of this function (core.progress)."""
    from .validation.progress import display

    return display(label, **kw)


_set_display(_display)


def _version() -> str:
    """The installed distribution's version (``gear-rattle --version``): ``importlib.metadata``, read on
    first use of ``gear_rattle.__version__``."""
    from importlib import metadata

    try:
        return metadata.version("gear-rattle")
    except metadata.PackageNotFoundError:  # a source tree on sys.path without an install
        return "0+unknown"


def _module(name: str):
    """The module that defines the public ``name`` of :data:`_LAZY` (``__version__``: :func:`_version`)."""
    if name == "Params":
        from .core import params

        return params
    if name in ("ImpactSequence", "StepJacobian"):
        from .core import results as core_results

        return core_results
    if name == "orbit":
        from .mapimpl import tracks

        return tracks
    if name in ("find_periodic", "PeriodicOrbit"):
        from .mapimpl import periodic

        return periodic
    if name in ("lyapunov", "LyapunovResult"):
        from .mapimpl import lyapunov

        return lyapunov
    if name in ("transient_times", "TransientResult"):
        from .mapimpl.engine import transients

        return transients
    if name == "CertifiedSequence":
        from .mapimpl.certified import track

        return track
    from .validation.transient import results  # SurvivalResult

    return results


def __getattr__(name: str):
    """A public name of :data:`_LAZY`, imported on first use (PEP 562)."""
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = _version() if name == "__version__" else getattr(_module(name), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The public API only (``__all__``)."""
    return sorted(__all__)
