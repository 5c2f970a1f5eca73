"""Bifurcation diagrams of the impact map (Figs. 4a and 8a).

Two kinds of diagram (:func:`bifurcation_diagram`):

* ``mode="fixed"``: every parameter value starts from the same initial condition; one orbit per value
  on the many-orbit engine (:mod:`gear_rattle.mapimpl.engine`, the
  :class:`~gear_rattle.mapimpl.engine.observers.Sample` observer);
* ``mode="sweep"``: a continuation sweep -- the final state at one parameter value is the initial
  state at the next (a ``lax.scan`` over the parameter values), which follows one attractor through
  hysteresis and shows the other side of a crisis.

Transients (``transient`` impacts) are discarded, then ``keep`` impacts are recorded.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from ...core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from ...mapimpl.engine.driver import run
from ...mapimpl.engine.observers import Sample
from ...core.status import Status
from ...mapimpl.impact_map import step
from ...core.state import MapState, make_state
from ...core.checks import MAX_VALUES, check_int, check_tau0
from ...core.params import DIAGRAM_PARAMS, ParamArrays, Params, check_value, param_arrays
from ...core.progress import sink

if TYPE_CHECKING:  # imported where the exponents are computed (diagram_lyapunov)
    from ...mapimpl.lyapunov import LyapunovResult

#: Hard caps that keep a run bounded.
MAX_POINTS = MAX_VALUES  # parameter values of one diagram (core.checks)
MAX_IMPACTS = 50_000_000


@partial(jax.jit, static_argnums=(2, 3))
def _sweep(st0: MapState, p: ParamArrays, transient: int, keep: int):
    def one_param(s, pp):
        s = make_state(s.theta, s.sdot, s.wall)  # reset cycles and status
        s = jax.lax.fori_loop(0, transient, lambda _, x: step(x, pp)[0], s)

        def body(x, _):
            x1, _info = step(x, pp)
            return x1, (x1.sdot, x1.theta, x1.status == Status.ACTIVE)

        s, rec = jax.lax.scan(body, s, None, length=keep)
        return s, rec

    _, rec = jax.lax.scan(one_param, st0, p)
    return rec


@dataclass
class Diagram:
    """A bifurcation diagram: ``values`` (n,), recorded ``sdot`` and ``theta`` (n, keep)."""

    param: str
    values: np.ndarray
    sdot: np.ndarray
    theta: np.ndarray
    active: np.ndarray
    mode: str
    base: Params
    transient: int
    keep: int

    def n_distinct(self, tol: float = 1e-6) -> np.ndarray:
        """Number of distinct ``sdot`` values (to ``tol``) at each parameter value."""
        out = []
        for row in self.sdot:
            s = np.sort(row[np.isfinite(row)])
            out.append(1 + int(np.sum(np.diff(s) > tol)) if s.size else 0)
        return np.array(out)

    def arrays(self) -> dict:
        """The arrays of the diagram's NPZ file."""
        return dict(
            param=self.param,
            values=self.values,
            sdot=self.sdot,
            theta=self.theta,
            active=self.active,
            mode=self.mode,
            transient=self.transient,
            keep=self.keep,
            alpha=self.base.alpha,
            beta=self.base.beta,
            gamma=self.base.gamma,
            r=self.base.r,
        )

    def table(self) -> tuple[list, list]:
        """``(header, rows)`` of the diagram's CSV: one row per recorded impact (parameter value, index,
        theta, sdot)."""
        return [self.param, "n", "theta", "sdot"], [
            [float(v), j, float(self.theta[i, j]), float(self.sdot[i, j])]
            for i, v in enumerate(self.values)
            for j in range(self.sdot.shape[1])
            if self.active[i, j]
        ]


def bifurcation_diagram(
    base: Params,
    param: str,
    lo: float,
    hi: float,
    n_values: int = 200,
    transient: int = 1000,
    keep: int = 200,
    mode: str = "fixed",
    tau0: float = 0.0,
    sdot0: float = 0.5,
    reverse: bool = False,
    progress=None,
) -> Diagram:
    """sdot_n against ``param`` in ``[lo, hi]`` (Fig. 4a: ``param="r"``, alpha = 3; Fig. 8a:
    ``param="alpha"``, r = 0.9), ``transient`` impacts discarded, ``keep`` recorded.

    ``mode="fixed"``: every value starts from ``(tau0, sdot0)`` (one orbit per value on the many-orbit
    engine, :mod:`gear_rattle.mapimpl.engine`); ``mode="sweep"``: the state is carried from value to value
    (from ``hi`` down to ``lo`` when ``reverse``; one orbit, a ``lax.scan`` of the map step).
    """
    if mode not in ("fixed", "sweep"):
        raise ValueError(f"mode={mode!r} is out of range: allowed 'fixed' or 'sweep'")
    n_values = check_int("n_values", n_values, 1, MAX_POINTS)
    transient = check_int("transient", transient, 0, MAX_IMPACTS)
    keep = check_int("keep", keep, 1, 100000)
    if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi):
        raise ValueError(f"range lo={lo!r}, hi={hi!r} is out of range: allowed finite lo <= hi")
    if param in DIAGRAM_PARAMS:  # the ends as given (the values between them are checked below)
        check_value(param, lo), check_value(param, hi)
    check_tau0(tau0)
    if not (np.isfinite(sdot0) and sdot0 != 0.0):
        raise ValueError(f"sdot0={sdot0!r} is out of range: allowed a finite sdot0 != 0")
    values = np.linspace(lo, hi, n_values)
    if reverse:
        values = values[::-1]
    p = param_arrays(base, param, values)
    if mode == "fixed":
        # one orbit per value on the many-orbit engine: impacts transient+1 .. transient+keep recorded
        res = run(
            np.full(n_values, float(tau0)),
            np.full(n_values, float(sdot0)),
            np.full(n_values, 0 if sdot0 > 0 else -1, np.int32),
            p,
            Sample(keep=keep, n_start=transient + 1),
            cap=transient + keep,
            progress=progress,
            label="bifurcation",
        )
        sd, th = res.obs[0]["sdot"], res.obs[0]["theta"]
        act = np.isfinite(th)
    else:
        st = make_state(jnp.asarray(tau0), jnp.asarray(sdot0))
        sd, th, act = (np.asarray(a) for a in _sweep(st, p, transient, keep))
        report = sink(progress)  # True, None and False draw no bar here: one scan, nothing to count
        if report is not None:
            report(n_values, n_values)
    sd = np.where(act, sd, np.nan)
    return Diagram(param, values, sd, th, act, mode, base, transient, keep)


#: ln of the largest float64: the raw Jacobian product of the paper's Lyapunov method (eigenvalues of the
#: product itself) overflows once n lambda1 exceeds it.
LN_FLOAT_MAX = math.log(np.finfo(np.float64).max)


@dataclass
class DiagramLyapunov:
    """A bifurcation diagram (Figs. 4a, 8a: ``mode="fixed"``) and the Lyapunov exponents at its parameter
    values (Figs. 4b, 8b: a :class:`~gear_rattle.mapimpl.lyapunov.LyapunovResult`)."""

    diagram: Diagram
    lyapunov: LyapunovResult

    @property
    def sum_error(self) -> float:
        """Largest ``|lambda1 + lambda2 - mean ln|det J||`` over the values (NaN if none is defined)."""
        e = self.lyapunov.sum_error
        return float(np.nanmax(e)) if np.any(np.isfinite(e)) else float("nan")

    @property
    def lam1_max(self) -> float:
        """The largest lambda1 (free steps) of the scan."""
        return float(np.nanmax(self.lyapunov.lam_free[:, 0]))

    def _columns(self) -> dict[str, np.ndarray]:
        lam = self.lyapunov
        return {
            "lambda1": lam.lam[:, 0],
            "lambda2": lam.lam[:, 1],
            "lambda1_free": lam.lam_free[:, 0],
            "lambda2_free": lam.lam_free[:, 1],
        }

    def arrays(self) -> dict:
        """The NPZ file's arrays: the diagram's (:meth:`Diagram.arrays`) and, per parameter value, the
        exponents drawn in panel b and their formal values (``lambda1``, ``lambda2``: ``-inf`` where a
        step stuck; ``lambda1_free``, ``lambda2_free``: over the free steps; NaN where the orbit ended
        early), ``n_stuck`` and the impacts averaged ``lyapunov_impacts``."""
        return {
            **self.diagram.arrays(),
            **self._columns(),
            "n_stuck": self.lyapunov.n_stuck,
            "lyapunov_impacts": self.lyapunov.n_steps,
        }

    def table(self) -> tuple[list, list]:
        """The CSV file's ``(header, rows)``: the diagram's rows (:meth:`Diagram.table`, one per recorded
        impact) with the exponents of the row's parameter value in four more columns (those of
        :meth:`arrays`)."""
        header, rows = self.diagram.table()
        cols = self._columns()
        at = {float(v): i for i, v in enumerate(self.diagram.values)}
        return header + list(cols), [row + [float(c[at[row[0]]]) for c in cols.values()] for row in rows]


def diagram_with_lyapunov(
    base: Params, param: str, lo: float, hi: float, n_values: int, transient: int, keep: int, lyap_n: int
) -> DiagramLyapunov:
    """The diagram of ``param`` in ``[lo, hi]`` (``n_values`` values, ``transient`` impacts discarded,
    ``keep`` recorded, every value from the same initial condition) and the QR Lyapunov exponents over
    ``lyap_n`` impacts at the same values."""
    from ...mapimpl.lyapunov import lyapunov

    d = bifurcation_diagram(base, param, lo, hi, n_values=n_values, transient=transient, keep=keep, mode="fixed")
    return DiagramLyapunov(d, lyapunov(base, param, d.values, n_impacts=lyap_n, transient=transient))


def raw_product_horizon(lam1: float) -> float:
    """Impacts after which the raw product of Jacobians (entries growing like ``exp(n lambda1)``) is predicted to
    pass the largest float64: ``ln(float64 max) / lambda1`` (the measured step:
    :func:`gear_rattle.mapimpl.lyapunov.raw_product_overflow`)."""
    return LN_FLOAT_MAX / lam1


__all__ = [
    "MAX_POINTS",
    "MAX_IMPACTS",
    "Diagram",
    "bifurcation_diagram",
    "LN_FLOAT_MAX",
    "DiagramLyapunov",
    "diagram_with_lyapunov",
    "raw_product_horizon",
]
