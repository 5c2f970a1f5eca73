"""Lyapunov exponents of the 2-D impact map (Figs. 4b and 8b) by QR re-orthonormalisation.

The paper computes ``lambda_i = lim (1/n) ln |A_i(n)|`` from the eigenvalues ``A_i(n)`` of the raw
product ``A = J_1 J_2 ... J_n`` of step Jacobians.  In float64 that product overflows: with
``lambda_1 ~ 0.3`` per impact its largest entry passes 1e308 after ~2400 impacts, and its smallest
singular value underflows even sooner (``lambda_2 ~ -1``), so the eigenvalues of the raw product are
useless for the long runs a converged exponent needs.  Here the product is carried as ``Q R``:
at each step ``J_n Q_{n-1} = Q_n R_n`` (a Givens rotation of the 2x2, on the many-orbit engine:
:class:`gear_rattle.mapimpl.engine.observers.Tangent`), and::

    lambda_i = (1/N) sum_n ln |R_n[i, i]|        (per impact, natural log).

The sum ``lambda_1 + lambda_2`` equals ``(1/N) sum ln |det J_n|`` exactly, and the closed form
``det J = r^2 exp(-beta dt) sdot_n / sdot_{n+1}`` telescopes to::

    (1/N) sum ln|det J_n| = 2 ln r - beta (tau_N - tau_0)/N + (1/N) ln |sdot_0 / sdot_N|,

an independent check of the analytic Jacobians (:func:`lyapunov` returns both).

Steps that stick to a wall forget their input (``J = 0``): formally the product vanishes and both
exponents are ``-inf``.  Such steps are counted (``n_stuck``); the reported exponents are then
``-inf`` (``formal``) while ``lam_free`` gives the exponents of the non-sticking steps only
(Q restarted at the identity after a sticking step), which is what a plot can show.  An orbit that
ended early (stuck forever, no impact, step cap) has none (NaN).  These rules are those of
:func:`gear_rattle.mapimpl.engine.exponents.exponents`, the one function that turns the observer's
output into exponents (also used by the atlas and the r1 analysis).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core import jax_config  # noqa: F401
import jax
import jax.numpy as jnp

from ..core.deprecation import UNSET, renamed_argument
from ..core.outcome import Outcome, check_lengths, check_status
from ..core.checks import MAX_AVERAGED, MAX_VALUES, check_array, check_choice, check_int, check_start
from ..core.params import DIAGRAM_PARAMS, Params, param_arrays
from ..core.state import make_state
from ..core.status import Status
from .engine.driver import run
from .engine.exponents import exponents
from .engine.observers import Tangent
from .impact_map import step


@dataclass
class LyapunovResult(Outcome):
    """Exponents per impact at each parameter value.

    ``lam``: (n, 2) exponents (``-inf`` where a step stuck); ``lam_free``: exponents over the
    non-sticking steps; ``det_mean``: closed-form mean of ln|det J| (telescoped);
    ``n_stuck``: sticking steps; ``n_steps``: steps used (``n_impacts``); ``status``: per value, the
    :class:`~gear_rattle.core.status.Status` code of its orbit -- ``ACTIVE`` where it went on through
    ``transient + n_impacts`` impacts, else how it ended (stuck forever, no impact, step cap: the exponents
    are NaN, there is no average over ``n_impacts`` impacts; ``lam_free`` is NaN too where every step
    stuck); ``ok`` only where every value has its exponents (:class:`~gear_rattle.core.outcome.Outcome`);
    ``active``: ``status == ACTIVE``.
    """

    #: Worked: every orbit went on to the end (an orbit that ended has no exponents).
    OK_CODES = frozenset({Status.ACTIVE})

    param: str
    values: np.ndarray
    lam: np.ndarray
    lam_free: np.ndarray
    det_mean: np.ndarray
    n_stuck: np.ndarray
    n_steps: int
    status: np.ndarray

    def __post_init__(self) -> None:
        """Refuse status codes that are no :class:`~gear_rattle.core.status.Status` and arrays whose shapes
        disagree (``ValueError`` naming them)."""
        check_status(self.status, list(Status))
        m = check_lengths(
            "values, status and n_stuck of a LyapunovResult",
            values=self.values,
            status=self.status,
            n_stuck=self.n_stuck,
        )
        for k in ("lam", "lam_free"):
            if np.shape(getattr(self, k)) != (m, 2):
                raise ValueError(f"{k} of a LyapunovResult: allowed shape ({m}, 2) (got {np.shape(getattr(self, k))})")

    @property
    def active(self) -> np.ndarray:
        """Per value: the orbit went on through every impact (``status == ACTIVE``)."""
        return self.status == int(Status.ACTIVE)

    @property
    def sum_error(self) -> np.ndarray:
        """``|lambda_1 + lambda_2 - mean ln|det J||`` for orbits without sticking (NaN otherwise)."""
        s = self.lam_free.sum(axis=1)
        return np.where(self.n_stuck == 0, np.abs(s - self.det_mean), np.nan)

    def arrays(self) -> dict:
        """The arrays of the result (an NPZ file's content)."""
        return dict(
            param=self.param,
            values=self.values,
            lam=self.lam,
            lam_free=self.lam_free,
            det_mean=self.det_mean,
            n_stuck=self.n_stuck,
            n_steps=self.n_steps,
            active=self.active,
        )

    def table(self) -> tuple[list, list]:
        """``(header, rows)``: one row per parameter value (a CSV file's content)."""
        header = [self.param, "lambda1", "lambda2", "lambda1_free", "lambda2_free", "mean_log_det", "n_stuck", "active"]
        return header, [
            [
                float(v),
                float(self.lam[i, 0]),
                float(self.lam[i, 1]),
                float(self.lam_free[i, 0]),
                float(self.lam_free[i, 1]),
                float(self.det_mean[i]),
                int(self.n_stuck[i]),
                bool(self.active[i]),
            ]
            for i, v in enumerate(self.values)
        ]


def check_arguments(params, param, values, n_impacts, transient, tau0, sdot0):
    """The arguments of :func:`lyapunov`, checked (:mod:`core.checks`) and returned as
    ``(param, values, n_impacts, transient, tau0, sdot0)``: ``param`` in ``("r", "alpha")``, ``values`` a
    1-D sequence of at most ``MAX_VALUES`` (2e4) allowed values of it (default: ``params``'),
    ``1 <= n_impacts <= MAX_AVERAGED`` and ``0 <= transient <= MAX_AVERAGED`` (5e7 impacts), a pre-impact
    start ``(tau0, sdot0)``."""
    from ..core.params import check_params

    base = check_params(params, "params")
    check_choice("param", param, DIAGRAM_PARAMS)
    n = check_int("n_impacts", n_impacts, 1, MAX_AVERAGED)
    transient = check_int("transient", transient, 0, MAX_AVERAGED)
    tau0, sdot0, _ = check_start(tau0, sdot0)
    values = check_array("values", [getattr(base, param)] if values is None else values, max_size=MAX_VALUES)
    try:
        param_arrays(base, param, values)
    except ValueError as e:
        raise ValueError(f"values: {e}") from None
    return param, values, n, transient, tau0, sdot0


def lyapunov(
    params: Params,
    param: str = "r",
    values=None,
    n_impacts=UNSET,
    transient: int = 1000,
    tau0: float = 0.0,
    sdot0: float = 0.5,
    progress=None,
    *,
    n=UNSET,
) -> LyapunovResult:
    """Lyapunov exponents (QR method) of the orbit from ``(tau0, sdot0)`` at each value of ``param``
    (``"r"`` or ``"alpha"``), after ``transient`` impacts, over ``n_impacts`` impacts (default 20000): one
    orbit per value on the many-orbit engine (the :class:`~gear_rattle.mapimpl.engine.observers.Tangent`
    observer).  ``values``: default the value of ``param`` in ``params`` (one orbit).  The arguments and
    their ranges: :func:`check_arguments` (``ValueError``/``TypeError`` naming the argument); ``n=`` is the
    old name of ``n_impacts`` (a DeprecationWarning).  ``progress``: :mod:`gear_rattle.core.progress`.

    >>> import gear_rattle as gr
    >>> res = gr.lyapunov(gr.Params(3.0, 0.1, 0.1, 0.9), "r", [0.9], n_impacts=500, transient=100, progress=False)
    >>> res.ok, res.message, res.lam.shape
    (True, 'active: the orbit goes on', (1, 2))
    """
    n_impacts = renamed_argument("n", "n_impacts", n_impacts, n, 20000)
    base = params
    param, values, n, transient, tau0, sdot0 = check_arguments(base, param, values, n_impacts, transient, tau0, sdot0)
    p = param_arrays(base, param, values)
    m = values.size
    res = run(
        np.full(m, float(tau0)),
        np.full(m, float(sdot0)),
        np.full(m, 0 if sdot0 > 0 else -1, np.int32),
        p,
        Tangent(n_start=transient),
        cap=transient + n,
        progress=progress,
        label="lyapunov",
    )
    t, ex = res.obs[0], exponents(res)  # the one rule for sticking steps and orbits that ended early
    rr = np.asarray(p.r) * np.ones(m)
    beta = np.asarray(p.beta) * np.ones(m)
    steps = np.maximum(res.n - transient, 1)
    elapsed = 2.0 * np.pi * (res.cycles - t["cycles0"]) + (res.theta - t["theta0"])
    det_mean = 2 * np.log(rr) - beta * elapsed / steps + np.log(np.abs(t["sdot0"] / res.sdot)) / steps
    # an orbit that went on is active; one that ended says how (its engine status)
    status = np.where(ex.ran, int(Status.ACTIVE), res.status).astype(np.int32)
    return LyapunovResult(param, values, ex.lam, ex.lam_free, det_mean, ex.n_stuck, n, status)


def raw_product_overflow(
    params: Params, n: int = 5000, tau0: float = 0.0, sdot0: float = 0.5, transient: int = 1000
) -> int | None:
    """First impact count at which the paper's raw product ``J_n ... J_1`` overflows to inf/NaN in
    float64 along the orbit (None if it does not within ``n``): the reason for the QR method."""
    from ..core.params import check_params

    n = check_int("n", n, 1, 10_000_000)
    transient = check_int("transient", transient, 0, 10_000_000)
    tau0, sdot0, _ = check_start(tau0, sdot0)
    p = check_params(params).arrays()
    st = make_state(jnp.asarray(tau0), jnp.asarray(sdot0))
    st = jax.jit(lambda s, pp: jax.lax.fori_loop(0, transient, lambda _, x: step(x, pp)[0], s))(st, p)

    @jax.jit
    def run(s, pp):
        def body(c, _):
            x, A = c
            x1, info = step(x, pp)
            A1 = info.jac @ A
            return (x1, A1), jnp.all(jnp.isfinite(A1))

        _, fin = jax.lax.scan(body, (s, jnp.eye(2)), None, length=n)
        return fin

    fin = np.asarray(run(st, p))
    bad = np.nonzero(~fin)[0]
    return int(bad[0]) + 1 if bad.size else None


__all__ = [
    "LyapunovResult",
    "check_arguments",
    "lyapunov",
    "raw_product_overflow",
]
