"""The crisis law ``T(mu) = C |mu - mu_c|^-g`` fitted by maximum likelihood to censored counts, its
fit-range systematic, and the power law of the laminar lengths (methods: :mod:`.stats`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, special

from .meantime import check_counts, check_side


# ------------------------------------------------------------------------------ crisis law fit


@dataclass
class CrisisFit:
    """Maximum-likelihood fit of ``T(mu) = C x^-g`` (see the module docstring).

    ``mu_c``: critical value; ``err_lo``, ``err_hi``: 68 % profile-likelihood interval
    ``[mu_c - err_lo, mu_c + err_hi]`` (statistical, scaled by the misfit ``dispersion``); ``g``,
    ``g_err``: exponent (``g_err`` = 0 when fixed); ``log_C``; ``deviance`` (Poisson, at the optimum)
    and ``dof``; ``dispersion = max(1, deviance/dof)``; ``values``: the parameter values fitted.
    """

    side: str
    mu_c: float
    err_lo: float
    err_hi: float
    g: float
    g_err: float
    fixed_g: bool
    log_C: float
    deviance: float
    dof: int
    dispersion: float
    values: np.ndarray = field(repr=False)

    @property
    def err(self) -> float:
        """The larger half-width of the 68 % interval."""
        return max(self.err_lo, self.err_hi)

    def x(self, mu) -> np.ndarray:
        mu = np.asarray(mu, float)
        return mu - self.mu_c if self.side == "above" else self.mu_c - mu

    def T(self, mu) -> np.ndarray:
        """The fitted law (``inf`` on the pre-crisis side)."""
        x = self.x(mu)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(x > 0, np.exp(self.log_C) * np.abs(x) ** (-self.g), np.inf)

    def distance_at(self, T: float) -> float:
        """``|mu - mu_c|`` at which the law gives the mean time ``T``."""
        return float((np.exp(self.log_C) / T) ** (1.0 / self.g))

    def mu_at(self, T: float) -> float:
        """The parameter value at which the law gives the mean time ``T``."""
        d = self.distance_at(T)
        return self.mu_c + d if self.side == "above" else self.mu_c - d

    def as_dict(self) -> dict:
        return {
            "mu_c": self.mu_c,
            "err_lo": self.err_lo,
            "err_hi": self.err_hi,
            "err": self.err,
            "g": self.g,
            "g_err": self.g_err,
            "fixed_g": self.fixed_g,
            "log_C": self.log_C,
            "deviance": self.deviance,
            "dof": self.dof,
            "dispersion": self.dispersion,
            "n_points": int(np.size(self.values)),
        }


def _poisson_deviance(k: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Per-point Poisson deviance ``2 (k ln(k/m) - (k - m))`` (``inf`` where ``m = 0 < k``)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        d = 2.0 * (special.xlogy(k, k) - special.xlogy(k, m) - (k - m))
    return np.where((m <= 0) & (k > 0), np.inf, np.maximum(d, 0.0))


class _Law:
    """Counts ``k`` in exposures ``E`` at ``mu`` (per-point dispersion ``w``) against the crisis law."""

    def __init__(self, mu, k, E, side, w):
        self.mu, self.k, self.E, self.side, self.w = mu, k, E, side, w

    def x(self, mu_c):
        return self.mu - mu_c if self.side == "above" else mu_c - self.mu

    def log_C(self, mu_c, g):
        """Closed-form maximum-likelihood ``ln C`` for given ``(mu_c, g)``: ``sum k/w = sum E x^g / (C w)``."""
        x = self.x(mu_c)
        return float(np.log(np.sum(self.E * x**g / self.w)) - np.log(np.sum(self.k / self.w)))

    def expected(self, mu_c, g, log_C):
        x = self.x(mu_c)
        return self.E * np.where(x > 0, np.abs(x) ** g, 0.0) * np.exp(-log_C)

    def deviance(self, mu_c, g, log_C=None):
        if np.any(self.x(mu_c) <= 0):
            return np.inf
        lc = self.log_C(mu_c, g) if log_C is None else log_C
        return float(np.sum(_poisson_deviance(self.k, self.expected(mu_c, g, lc)) / self.w))

    def residuals(self, theta, g_fixed=None):
        log_C, mu_c = theta[0], theta[1]
        g = g_fixed if g_fixed is not None else theta[2]
        m = self.expected(mu_c, g, log_C)
        d = _poisson_deviance(self.k, m)
        d = np.where(np.isfinite(d), d, 1e12)
        return np.sign(self.k - m) * np.sqrt(d / self.w)


def fit_crisis(
    mu,
    events,
    exposure,
    side: str,
    g: float | None = None,
    dispersion=None,
    g_bounds: tuple[float, float] = (0.05, 5.0),
) -> CrisisFit:
    """Fit the crisis law ``T = C |mu - mu_c|^-g`` to ``events`` in ``exposure`` impacts at ``mu``
    (points without events are ignored: they belong to a bracket, see :func:`bracket`).

    ``side``: ``"above"`` (the data lie above ``mu_c``) or ``"below"``; ``g``: fixed exponent (e.g.
    :func:`goy_exponent`) or None (fitted within ``g_bounds``); ``dispersion``: per-point Pearson
    dispersion of the counts (>= 1) or None.  Needs >= 2 points with events for a fixed ``g``, >= 3 free.
    """
    side = check_side(side)
    mu, k, E, w = check_counts(mu, events, exposure, dispersion)
    use = k > 0
    mu, k, E, w = mu[use], k[use], E[use], w[use]
    n_par = 2 if g is not None else 3
    if mu.size < n_par:
        raise ValueError(f"fit_crisis needs at least {n_par} values with events (got {mu.size})")
    if g is not None and not (math.isfinite(g) and g > 0):
        raise ValueError(f"g={g!r} is out of range: allowed g > 0")
    law = _Law(mu, k, E, side, w)
    span = float(mu.max() - mu.min()) or abs(float(mu.mean())) * 1e-3 or 1e-3
    edge = float(mu.min() if side == "above" else mu.max())
    tiny = 1e-9 * span
    sgn = -1.0 if side == "above" else 1.0  # mu_c = edge + sgn * distance
    far = 20.0 * span

    def best_g(mu_c):
        if g is not None:
            return g
        r = optimize.minimize_scalar(
            lambda gg: law.deviance(mu_c, gg), bounds=g_bounds, method="bounded", options={"xatol": 1e-7}
        )
        return float(r.x)

    def prof(dist):  # profile deviance as a function of the distance of mu_c beyond the edge
        mc = edge + sgn * dist
        return law.deviance(mc, best_g(mc))

    # coarse log grid of distances, then a bounded refinement around the best one
    grid = np.geomspace(tiny, far, 121)
    dev = np.array([prof(d) for d in grid])
    j = int(np.argmin(dev))
    lo_d, hi_d = grid[max(j - 1, 0)], grid[min(j + 1, grid.size - 1)]
    r = optimize.minimize_scalar(prof, bounds=(lo_d, hi_d), method="bounded", options={"xatol": tiny})
    d_best = float(r.x) if r.fun <= dev[j] else float(grid[j])
    mu_c = edge + sgn * d_best
    g_best = best_g(mu_c)
    log_C = law.log_C(mu_c, g_best)
    g_err = 0.0
    if g is None:  # polish jointly and take the covariance of (log C, mu_c, g) from the Jacobian
        lb = [-np.inf, mu_c - far if side == "above" else edge + tiny, g_bounds[0]]
        ub = [np.inf, edge - tiny if side == "above" else mu_c + far, g_bounds[1]]
        x0 = np.clip([log_C, mu_c, g_best], np.array(lb) + 1e-15, np.array(ub) - 1e-15)
        ls = optimize.least_squares(
            law.residuals, x0, bounds=(lb, ub), x_scale=[1.0, span, 0.1], xtol=1e-14, ftol=1e-14, gtol=1e-14
        )
        if law.deviance(ls.x[1], ls.x[2], ls.x[0]) < law.deviance(mu_c, g_best, log_C):
            log_C, mu_c, g_best = (float(v) for v in ls.x)
            d_best = abs(mu_c - edge)
        J = ls.jac
        try:
            cov = np.linalg.pinv(J.T @ J)
        except np.linalg.LinAlgError:
            cov = np.full((3, 3), np.nan)
    D = law.deviance(mu_c, g_best, log_C)
    dof = int(mu.size - n_par)
    phi = max(1.0, D / dof) if dof > 0 else 1.0
    if g is None:
        g_err = float(np.sqrt(max(cov[2, 2], 0.0) * phi))
    # 68 % profile interval: D(mu_c) = D_min + phi on each side
    target = D + phi

    def f(dist):
        v = prof(dist)
        return (v if np.isfinite(v) else 1e300) - target

    near_err = d_best - float(optimize.brentq(f, tiny, d_best, xtol=tiny)) if f(tiny) > 0 and d_best > tiny else d_best
    far_err = (float(optimize.brentq(f, d_best, far, xtol=tiny)) - d_best) if f(far) > 0 else math.inf
    # "near" moves mu_c towards the data
    err_lo, err_hi = (far_err, near_err) if side == "above" else (near_err, far_err)
    return CrisisFit(
        side,
        float(mu_c),
        float(err_lo),
        float(err_hi),
        float(g_best),
        g_err,
        g is not None,
        float(log_C),
        float(D),
        dof,
        float(phi),
        mu,
    )


def fit_crisis_fixed(values, T, T_err, g: float) -> tuple[float, float, float]:
    """Compatibility wrapper: fit ``T = C |mu - mu_c|^-g`` (``g`` fixed) to mean times with one-sigma
    errors, read as ``(T/T_err)^2`` Poisson events in ``events * T`` impacts; the side is decided by
    the trend of ``T``.  Returns ``(mu_c, mu_c_err, deviance per degree of freedom)``."""
    v, T, e = (np.asarray(a, float).ravel() for a in (values, T, T_err))
    ok = np.isfinite(T) & np.isfinite(e) & (T > 0) & (e > 0)
    v, T, e = v[ok], T[ok], e[ok]
    if v.size < 3:
        raise ValueError("fit_crisis_fixed needs at least 3 finite mean times")
    k = (T / e) ** 2
    side = "above" if np.polyfit(v, np.log(T), 1)[0] < 0 else "below"
    fit = fit_crisis(v, k, k * T, side, g=g)
    return fit.mu_c, fit.err, fit.deviance / max(fit.dof, 1)


def range_systematic(
    mu, events, exposure, side: str, g: float | None = None, dispersion=None, drop: int = 2
) -> tuple[float, list[tuple[str, float]]]:
    """Fit-range systematic of :func:`fit_crisis`: refit without the ``1..drop`` farthest points from the
    crisis, and without the nearest one (as long as enough points with events remain).  Returns the
    largest shift of ``mu_c`` from the fit of all points and ``[(which points, mu_c), ...]``."""
    side = check_side(side)
    mu, k, E, w = check_counts(mu, events, exposure, dispersion)
    use = k > 0
    mu, k, E, w = mu[use], k[use], E[use], w[use]
    order = np.argsort(mu) if side == "above" else np.argsort(-mu)  # nearest first
    mu, k, E, w = mu[order], k[order], E[order], w[order]
    need = 2 if g is not None else 3
    nominal = fit_crisis(mu, k, E, side, g=g, dispersion=w).mu_c
    out = []
    for j in range(1, int(drop) + 1):
        if mu.size - j >= need + 1:
            out.append(
                (f"without the {j} farthest", fit_crisis(mu[:-j], k[:-j], E[:-j], side, g=g, dispersion=w[:-j]).mu_c)
            )
    if mu.size - 1 >= need + 1:
        out.append(("without the nearest", fit_crisis(mu[1:], k[1:], E[1:], side, g=g, dispersion=w[1:]).mu_c))
    syst = max((abs(m - nominal) for _, m in out), default=0.0)
    return float(syst), out


# ------------------------------------------------------------------------------ power law (r2)


def fit_power_law(x, y, yerr) -> tuple[float, float, float, float]:
    """Weighted fit ``ln y = a + s ln x`` (:func:`scipy.optimize.curve_fit`, sigma = relative errors);
    returns ``(s, s_err, a, reduced chi^2)``; the error is scaled by sqrt(chi^2_red) when that exceeds 1."""
    x, y, e = (np.asarray(a, float).ravel() for a in (x, y, yerr))
    ok = np.isfinite(x) & np.isfinite(y) & np.isfinite(e) & (x > 0) & (y > 0) & (e > 0)
    if ok.sum() < 3:
        raise ValueError("fit_power_law needs at least 3 positive finite points with errors")
    lx, ly, s = np.log(x[ok]), np.log(y[ok]), e[ok] / y[ok]
    p, cov = optimize.curve_fit(lambda t, a, b: a + b * t, lx, ly, p0=(ly.mean(), 0.0), sigma=s, absolute_sigma=True)
    chi2 = float(np.sum(((ly - p[0] - p[1] * lx) / s) ** 2) / max(ok.sum() - 2, 1))
    return float(p[1]), float(np.sqrt(cov[1, 1] * max(chi2, 1.0))), float(p[0]), chi2


__all__ = [
    "CrisisFit",
    "fit_crisis",
    "fit_crisis_fixed",
    "range_systematic",
    "fit_power_law",
]
