"""Reference tracks: Eq. (3) of de Souza et al. (2004) integrated numerically, from its right-hand side
only, with the impact law Eqs. (9)-(11), as an independent check of the closed-form map (Eqs. 7-8, 12-13).

* :mod:`reference.scipy_track` -- ``scipy.integrate.solve_ivp`` (DOP853) with terminal,
  direction-filtered events, dense output, variational equations and saltation matrix;
* :mod:`reference.diffrax_track` -- ``diffrax.diffeqsolve`` with ``diffrax.Event`` in a
  ``lax.while_loop`` restart loop (jit, vmap, ``jax.jacfwd`` through the event solve).

Both define their events with one specification, :mod:`reference.events` (monotone segments, wall
and reversal conditions, the missed-crossing guard, restarts, caps), apply the shared sticking policy
of :mod:`mapimpl.sticking`, return :class:`core.results.ImpactSequence` (tracks ``"scipy"`` /
``"diffrax"``) and are :class:`core.results.Track` objects (``scipy_track.TRACK``,
``diffrax_track.TRACK``).  The track modules are imported lazily (diffrax is heavy).
"""

from .events import T_MAX

__all__ = ["T_MAX", "events", "scipy_track", "diffrax_track"]
