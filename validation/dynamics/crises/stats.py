"""Statistics of the crisis analyses: mean times of memoryless processes with censoring, the
Grebogi-Ott-Yorke (GOY) exponent, crisis-law fits by maximum likelihood, and brackets by direct
observation.

**Mean time from censored observations.**  An orbit on a chaotic saddle escapes at a constant rate
``1/T`` per impact (exponential lifetimes); band hops near an interior crisis come as a (nearly)
Poisson stream of rate ``1/T``.  Observed for a total *exposure* ``E`` (impacts, every orbit counted
until it escaped or until the run ended: censoring) with ``k`` events, the likelihood is
``T^-k exp(-E/T)``, so the maximum-likelihood estimate is ``T = E / k`` and ``k`` is a Poisson count
of mean ``E/T``.  Its exact (Garwood) confidence interval is
``2E / chi2.ppf(1 - a/2, 2k + 2) <= T <= 2E / chi2.ppf(a/2, 2k)`` (:class:`MeanTime`).  With no
event, ``T > E / (-ln(1 - level))`` one-sided (``E / 3.0`` at 95 %, :func:`lifetime_lower_bound`).
Counts that scatter more than Poisson between orbits (hops come in clusters) are handled by the
Pearson dispersion ``phi >= 1`` of the per-orbit counts: the interval is that of ``k / phi`` events
in ``E / phi`` impacts (quasi-Poisson).

**Crisis law.**  ``T(mu) = C x^-g`` with ``x = mu - mu_c`` (``side="above"``: the crisis is below the
data, e.g. the boundary crisis alpha1, escapes for alpha > alpha1) or ``x = mu_c - mu``
(``side="below"``: e.g. the interior crisis r1, hops for r < r1).  :func:`fit_crisis` maximises the
Poisson likelihood of the counts ``k_i`` given the exposures ``E_i`` (``k_i ~ Poisson(E_i / T(mu_i))``,
the exact likelihood of censored exponential lifetimes), with ``g`` free or fixed (e.g. to the GOY
value).  ``C`` has a closed form for given ``(mu_c, g)``; the profile deviance ``D(mu_c)`` is
minimised with :func:`scipy.optimize.minimize_scalar`, the 68 % interval of ``mu_c`` is where
``D <= D_min + phi`` (``phi``: the deviance per degree of freedom when it exceeds 1, i.e. errors
inflated by the misfit), found with :func:`scipy.optimize.brentq`; the free fit is polished and its
covariance (for ``g``) taken from :func:`scipy.optimize.least_squares` on the deviance residuals.
:func:`range_systematic` refits on sub-ranges (dropping the farthest or the nearest points): the
spread is the fit-range systematic.

**GOY exponent** (Grebogi, Ott, Romeiras, Yorke, Phys. Rev. A 36 (1987) 5365) of a crisis of a 2-D map
mediated by a saddle orbit with multipliers ``m_u``, ``m_s``: ``g = 1/2 + ln|m_u| / |ln|m_s||``
(:func:`goy_exponent`).

**Bracket.**  Events seen at ``mu = a`` prove that ``a`` is on the post-crisis side; no event in
``E`` impacts at ``b`` proves only that ``T(b) > E / 3`` (95 %): with the law, ``mu_c`` lies within
``(C / (E/3))^(1/g)`` of ``b`` or beyond it (:func:`bracket`, :meth:`CrisisFit.distance_at`).
:func:`locate` states the fit or the bracket, whichever is narrower, unless the fit contradicts the
bracket (then the bracket).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, special, stats

#: Confidence level of the intervals of mean times and of the bracket.
LEVEL = 0.95
SIDES = ("above", "below")


def _check_level(level: float) -> float:
    if not (isinstance(level, (int, float)) and 0.0 < level < 1.0):
        raise ValueError(f"level={level!r} is out of range: allowed 0 < level < 1")
    return float(level)


def _check_side(side: str) -> str:
    if side not in SIDES:
        raise ValueError(f"side={side!r} is out of range: allowed one of {SIDES}")
    return side


# ------------------------------------------------------------------------------ mean times

@dataclass(frozen=True)
class MeanTime:
    """Mean time ``T = exposure / events`` (impacts) of a memoryless process and its exact interval.

    ``events``: events seen (escapes, hops); ``exposure``: impacts observed; ``dispersion``: Pearson
    dispersion of the per-orbit counts (>= 1; 1 = Poisson); ``orbits``: orbits contributing;
    ``level``: confidence level of :attr:`lo`, :attr:`hi`.
    """

    events: int
    exposure: float
    dispersion: float = 1.0
    orbits: int = 0
    level: float = LEVEL

    def __post_init__(self):
        if int(self.events) != self.events or self.events < 0:
            raise ValueError(f"events={self.events!r} is out of range: allowed an integer >= 0")
        if not (math.isfinite(self.exposure) and self.exposure > 0):
            raise ValueError(f"exposure={self.exposure!r} is out of range: allowed a finite exposure > 0")
        if not (math.isfinite(self.dispersion) and self.dispersion >= 1.0):
            raise ValueError(f"dispersion={self.dispersion!r} is out of range: allowed >= 1")
        _check_level(self.level)

    @property
    def T(self) -> float:
        """Maximum-likelihood mean time (``inf`` without events)."""
        return self.exposure / self.events if self.events else math.inf

    @property
    def lo(self) -> float:
        """Lower end of the two-sided interval (exact Poisson, on ``k/phi`` events in ``E/phi``)."""
        k, E = self.events / self.dispersion, self.exposure / self.dispersion
        return 2.0 * E / float(stats.chi2.ppf(0.5 + self.level / 2, 2 * k + 2))

    @property
    def hi(self) -> float:
        """Upper end of the two-sided interval (``inf`` without events)."""
        if self.events == 0:
            return math.inf
        k, E = self.events / self.dispersion, self.exposure / self.dispersion
        return 2.0 * E / float(stats.chi2.ppf(0.5 - self.level / 2, 2 * k))

    @property
    def rel_err(self) -> float:
        """One-sigma relative error ``sqrt(phi / k)`` (``inf`` without events)."""
        return math.sqrt(self.dispersion / self.events) if self.events else math.inf

    @property
    def bound(self) -> float:
        """One-sided lower bound on ``T`` at :attr:`level` (the statement a run without events makes)."""
        return lifetime_lower_bound(self.exposure, self.level, self.events, self.dispersion)

    def as_dict(self) -> dict:
        return {"T": self.T, "lo": self.lo, "hi": self.hi, "events": int(self.events),
                "exposure": float(self.exposure), "dispersion": float(self.dispersion), "orbits": int(self.orbits),
                "level": self.level}


def lifetime_lower_bound(exposure: float, level: float = LEVEL, events: int = 0, dispersion: float = 1.0) -> float:
    """One-sided lower bound on the mean time at ``level`` after ``events`` events in ``exposure``
    impacts: ``2E / chi2.ppf(level, 2k + 2)``; with no event ``E / (-ln(1 - level))`` (= E / 3.0 at 95 %)."""
    _check_level(level)
    k, E = events / dispersion, exposure / dispersion
    return 2.0 * E / float(stats.chi2.ppf(level, 2 * k + 2))


def pearson_dispersion(events, exposure) -> float:
    """Pearson dispersion ``sum (k_i - E_i/T)^2 / (E_i/T) / (n - 1)`` of per-orbit counts, floored at 1
    (1 when there are fewer than two orbits or no events)."""
    k = np.asarray(events, float).ravel()
    E = np.asarray(exposure, float).ravel()
    if k.shape != E.shape:
        raise ValueError("events and exposure must have the same length")
    ok = E > 0
    k, E = k[ok], E[ok]
    if k.size < 2 or k.sum() == 0:
        return 1.0
    m = E * k.sum() / E.sum()
    return max(1.0, float(np.sum((k - m) ** 2 / m) / (k.size - 1)))


def mean_time(events, exposure, *, overdispersed: bool = False, level: float = LEVEL) -> MeanTime:
    """:class:`MeanTime` of per-orbit counts ``events`` in per-orbit ``exposure`` (arrays); with
    ``overdispersed`` the interval is widened by the Pearson dispersion of the counts (for repeated
    events per orbit, e.g. band hops)."""
    k = np.asarray(events).ravel()
    E = np.asarray(exposure, float).ravel()
    if k.shape != E.shape or k.size == 0:
        raise ValueError("events and exposure must be non-empty arrays of the same length")
    if np.any(k < 0) or np.any(E < 0):
        raise ValueError("events and exposure are out of range: allowed values >= 0")
    phi = pearson_dispersion(k, E) if overdispersed else 1.0
    return MeanTime(int(k.sum()), float(E.sum()), phi, int(np.sum(E > 0)), level)


def censored_lifetimes(escape, n_run, n0: int = 0, level: float = LEVEL) -> tuple[MeanTime, int]:
    """Mean lifetime from per-orbit escape indices with censoring and left truncation.

    ``escape[i]``: the impact at which orbit ``i`` escaped (< 0: not within its run); ``n_run[i]``: the
    impacts the orbit was followed (its censoring time when it did not escape); ``n0``: counting
    starts at impact ``n0`` (orbits that escaped by then are dropped: exponential lifetimes are
    memoryless, so the survivors' remaining lifetimes have the same mean).  Returns the
    :class:`MeanTime` and the number of orbits dropped.
    """
    esc = np.asarray(escape).ravel()
    n = np.asarray(n_run).ravel()
    if esc.shape != n.shape or esc.size == 0:
        raise ValueError("escape and n_run must be non-empty arrays of the same length")
    if int(n0) != n0 or n0 < 0:
        raise ValueError(f"n0={n0!r} is out of range: allowed an integer >= 0")
    escaped = esc >= 0
    end = np.where(escaped, esc, n)
    alive = end > n0
    k = int(np.sum(escaped & alive))
    E = float(np.sum(np.where(alive, end - n0, 0)))
    if E <= 0:
        raise ValueError(f"no orbit was followed beyond n0={n0}")
    return MeanTime(k, E, 1.0, int(alive.sum()), level), int(np.sum(~alive))


# ------------------------------------------------------------------------------ GOY exponent

def goy_exponent(multipliers) -> float:
    """Grebogi-Ott-Yorke critical exponent ``1/2 + ln|m_u| / |ln|m_s||`` of a crisis mediated by a saddle
    orbit with multipliers ``m_u`` (unstable) and ``m_s`` (stable) of a 2-D map."""
    m = np.sort(np.abs(np.asarray(multipliers, complex)))
    if m.size != 2 or not (0.0 < m[0] < 1.0 < m[1]):
        raise ValueError(f"multipliers {multipliers!r} are out of range: allowed a saddle (0 < |m_s| < 1 < |m_u|)")
    return float(0.5 + np.log(m[1]) / abs(np.log(m[0])))


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
        return {"mu_c": self.mu_c, "err_lo": self.err_lo, "err_hi": self.err_hi, "err": self.err, "g": self.g,
                "g_err": self.g_err, "fixed_g": self.fixed_g, "log_C": self.log_C, "deviance": self.deviance,
                "dof": self.dof, "dispersion": self.dispersion, "n_points": int(np.size(self.values))}


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
        return float(np.log(np.sum(self.E * x ** g / self.w)) - np.log(np.sum(self.k / self.w)))

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


def _check_counts(mu, k, E, dispersion=None):
    mu = np.asarray(mu, float).ravel()
    k = np.asarray(k, float).ravel()
    E = np.asarray(E, float).ravel()
    if not (mu.shape == k.shape == E.shape):
        raise ValueError("mu, events and exposure must have the same length")
    if not (np.all(np.isfinite(mu)) and np.all(np.isfinite(E)) and np.all(E > 0) and np.all(k >= 0)):
        raise ValueError("mu, events or exposure out of range: allowed finite mu, exposure > 0, events >= 0")
    w = np.ones_like(mu) if dispersion is None else np.broadcast_to(np.asarray(dispersion, float), mu.shape).copy()
    if not np.all(np.isfinite(w) & (w >= 1.0)):
        raise ValueError("dispersion is out of range: allowed values >= 1")
    return mu, k, E, w


def fit_crisis(mu, events, exposure, side: str, g: float | None = None, dispersion=None,
               g_bounds: tuple[float, float] = (0.05, 5.0)) -> CrisisFit:
    """Fit the crisis law ``T = C |mu - mu_c|^-g`` to ``events`` in ``exposure`` impacts at ``mu``
    (points without events are ignored: they belong to a bracket, see :func:`bracket`).

    ``side``: ``"above"`` (the data lie above ``mu_c``) or ``"below"``; ``g``: fixed exponent (e.g.
    :func:`goy_exponent`) or None (fitted within ``g_bounds``); ``dispersion``: per-point Pearson
    dispersion of the counts (>= 1) or None.  Needs >= 2 points with events for a fixed ``g``, >= 3 free.
    """
    side = _check_side(side)
    mu, k, E, w = _check_counts(mu, events, exposure, dispersion)
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
        r = optimize.minimize_scalar(lambda gg: law.deviance(mu_c, gg), bounds=g_bounds, method="bounded",
                                     options={"xatol": 1e-7})
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
        ls = optimize.least_squares(law.residuals, x0, bounds=(lb, ub), x_scale=[1.0, span, 0.1],
                                    xtol=1e-14, ftol=1e-14, gtol=1e-14)
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
    return CrisisFit(side, float(mu_c), float(err_lo), float(err_hi), float(g_best), g_err, g is not None,
                     float(log_C), float(D), dof, float(phi), mu)


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


def range_systematic(mu, events, exposure, side: str, g: float | None = None, dispersion=None,
                     drop: int = 2) -> tuple[float, list[tuple[str, float]]]:
    """Fit-range systematic of :func:`fit_crisis`: refit without the ``1..drop`` farthest points from the
    crisis, and without the nearest one (as long as enough points with events remain).  Returns the
    largest shift of ``mu_c`` from the fit of all points and ``[(which points, mu_c), ...]``."""
    side = _check_side(side)
    mu, k, E, w = _check_counts(mu, events, exposure, dispersion)
    use = k > 0
    mu, k, E, w = mu[use], k[use], E[use], w[use]
    order = np.argsort(mu) if side == "above" else np.argsort(-mu)  # nearest first
    mu, k, E, w = mu[order], k[order], E[order], w[order]
    need = 2 if g is not None else 3
    nominal = fit_crisis(mu, k, E, side, g=g, dispersion=w).mu_c
    out = []
    for j in range(1, int(drop) + 1):
        if mu.size - j >= need + 1:
            out.append((f"without the {j} farthest", fit_crisis(mu[:-j], k[:-j], E[:-j], side, g=g, dispersion=w[:-j]).mu_c))
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


# ------------------------------------------------------------------------------ bracket

@dataclass
class Bracket:
    """A crisis bracketed by direct observation.

    ``seen``: the parameter value nearest to the crisis at which events were observed (the crisis lies
    on the other side of it: for ``side="above"`` ``mu_c < seen``); ``clear``: the nearest value beyond
    it with no event (NaN if none), observed for ``clear_exposure`` impacts, which excludes mean times
    below ``clear_bound`` (one-sided, ``level``) -- not a proof that the set is an attractor there;
    ``interval``: ``(lo, hi)`` between the two.
    """

    side: str
    seen: float
    clear: float
    clear_exposure: float
    clear_bound: float
    level: float

    @property
    def interval(self) -> tuple[float, float]:
        return (min(self.seen, self.clear), max(self.seen, self.clear))

    @property
    def width(self) -> float:
        return abs(self.seen - self.clear)

    def as_dict(self) -> dict:
        return {"side": self.side, "seen": self.seen, "clear": self.clear, "clear_exposure": self.clear_exposure,
                "clear_bound": self.clear_bound, "level": self.level, "interval": self.interval, "width": self.width}


def bracket(mu, events, exposure, side: str, level: float = LEVEL, min_exposure: float = 0.0) -> Bracket:
    """The tightest bracket of the crisis from counts at several parameter values: ``seen`` is the value
    with events nearest to the crisis side (``min`` for ``side="above"``, ``max`` for ``"below"``),
    ``clear`` the nearest value beyond it without events in at least ``min_exposure`` impacts (runs of
    one value are summed)."""
    side = _check_side(side)
    _check_level(level)
    mu, k, E, _ = _check_counts(mu, events, exposure)
    vals = np.unique(mu)
    kk = np.array([k[mu == v].sum() for v in vals])
    EE = np.array([E[mu == v].sum() for v in vals])
    if not np.any(kk > 0):
        raise ValueError("bracket needs at least one value with events")
    strong = (kk == 0) & (EE >= min_exposure)
    if side == "above":
        seen = float(vals[kk > 0].min())
        cand = (vals < seen) & strong
        j = int(np.argmax(np.where(cand, vals, -np.inf))) if cand.any() else -1
    else:
        seen = float(vals[kk > 0].max())
        cand = (vals > seen) & strong
        j = int(np.argmin(np.where(cand, vals, np.inf))) if cand.any() else -1
    if j < 0:
        return Bracket(side, seen, math.nan, 0.0, 0.0, level)
    return Bracket(side, seen, float(vals[j]), float(EE[j]), lifetime_lower_bound(EE[j], level), level)


def next_probes(mu, events, exposure, side: str, mu_fit: float, step: float, target: float, strong: float,
                event_probe: float | None = None) -> list[float]:
    """The next bracket runs (a bisection started from a fit), each to be observed for ``strong`` impacts.

    Pre-crisis side: with no value there lacking events after ``strong`` impacts, probe ``step`` beyond
    ``mu_fit`` (or beyond ``seen`` when that is further); with one, and the bracket wider than
    ``2 target``, probe the midpoint of the bracket.  Event side: ``event_probe`` (e.g. where the law
    predicts a long mean time) unless a value within ``target / 10`` of it was observed for ``strong``
    impacts.  Returns the sorted new values (empty: done)."""
    side = _check_side(side)
    mu, k, E, _ = _check_counts(mu, events, exposure)
    if not (math.isfinite(step) and step > 0 and math.isfinite(target) and target > 0):
        raise ValueError("step and target are out of range: allowed finite values > 0")
    b = bracket(mu, k, E, side, min_exposure=strong)
    s = -1.0 if side == "above" else 1.0  # from the crisis towards the pre-crisis side
    out = []
    if not np.isfinite(b.clear):
        start = max(s * mu_fit, s * b.seen) * s
        out.append(start + s * step)
    elif b.width > 2 * target:
        out.append(0.5 * (b.seen + b.clear))
    if event_probe is not None:
        near = np.abs(mu - event_probe) <= target / 10
        if not np.any(near & (E >= strong)):
            out.append(float(event_probe))
    return sorted(set(float(v) for v in out))


# ------------------------------------------------------------------------------ the reported value

@dataclass(frozen=True)
class Located:
    """The crisis point a report states: ``value`` +- ``err`` and how it was decided.

    ``method``: ``"fit"`` (the GOY fit, +- its statistical and fit-range error) or ``"bracket"`` (the
    midpoint and half-width of the bracket by direct observation); ``why``: the reason (see
    :func:`locate`); ``outside``: how far the fit lies outside the bracket, in units of its error (0
    inside); ``interval``: the bracket ``(lo, hi)`` (NaN without one)."""

    value: float
    err: float
    method: str
    outside: float
    interval: tuple[float, float]
    why: str = ""

    def as_dict(self) -> dict:
        return {"value": self.value, "err": self.err, "method": self.method, "why": self.why,
                "outside": self.outside, "interval": self.interval}


#: The reasons :func:`locate` gives.
WHY_NO_BRACKET = "no bracket"
WHY_FIT_NARROWER = "fit inside the bracket and narrower"
WHY_BRACKET_NARROWER = "bracket narrower than the fit"
WHY_FIT_OUTSIDE = "fit outside the bracket"


def locate(fit_mu: float, fit_err: float, brk: Bracket, margin: float = 0.0) -> Located:
    """Decide the reported crisis point from a fit (``fit_mu`` +- ``fit_err``, statistical and fit-range
    systematic combined) and a :class:`Bracket` (``margin``: the distance beyond ``clear`` that the
    fitted law still allows, :meth:`CrisisFit.distance_at` of ``clear_bound``).

    The bracket is what the data show without a model; the fit adds the crisis law.  So: without a
    bracket, the fit; with the fit more than its error outside the bracket, the bracket (the law does
    not hold that close to the crisis); with the fit inside (within its error), the narrower of the two
    -- the fit's error or the bracket's half-width."""
    if not np.isfinite(brk.clear):
        return Located(float(fit_mu), float(fit_err), "fit", 0.0, (math.nan, math.nan), WHY_NO_BRACKET)
    if brk.side == "above":  # events seen above the crisis: mu_c < seen, and mu_c > clear - margin
        lo, hi = brk.clear - margin, brk.seen
    else:  # events seen below: mu_c > seen, and mu_c < clear + margin
        lo, hi = brk.seen, brk.clear + margin
    gap = max(lo - fit_mu, fit_mu - hi, 0.0)
    outside = gap / fit_err if fit_err > 0 else (math.inf if gap > 0 else 0.0)
    interval = (float(lo), float(hi))
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    if outside > 1.0:
        return Located(mid, half, "bracket", float(outside), interval, WHY_FIT_OUTSIDE)
    if half < fit_err:
        return Located(mid, half, "bracket", float(outside), interval, WHY_BRACKET_NARROWER)
    return Located(float(fit_mu), float(fit_err), "fit", float(outside), interval, WHY_FIT_NARROWER)
