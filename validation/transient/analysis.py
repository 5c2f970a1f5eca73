"""Statistics of Section 4: survival curve and Eq. (14) fit (Fig. 11), uncertain fraction and
uncertainty exponent (Fig. 10), transient basins (Fig. 9).

Eq. (14): ``N(n) = N0 exp(-kappa n / <n>)``.  ``N(n)`` is the number of initial conditions still
transient after ``n`` iterations (duration > n).  We fit ``ln N(n)`` linearly in ``n`` over a fit
range ``[n_lo, n_hi]`` (default: from ``n_lo`` = the median duration, past the fast tongues of
Fig. 9(a), up to the ``n`` where ``N`` falls to ``n_min_count`` = 100, below which Poisson noise
dominates); the slope is ``-1/tau_fit``.  ``<n>`` is the mean transient duration over all
initial conditions (censored ones counted at the cap: a lower bound, exact when none is censored).
Then ``kappa = <n> / tau_fit``.  For a pure exponential with ``<n>`` its mean, ``kappa = 1``
exactly; ``kappa < 1`` means the tail decays more slowly than the mean suggests (an excess of
short transients).  Standard errors: the ordinary least-squares one (which treats the highly
correlated cumulative counts as independent and so is far too small, like the paper's
``+-0.001``) and a bootstrap over initial conditions (the honest one).

The line fits are :func:`numpy.linalg.lstsq` on the weighted design matrix (:func:`linear_fit`); the
bootstraps (Eq. 14 over initial conditions, the uncertainty exponent of Fig. 10 over random points)
are :func:`scipy.stats.bootstrap` (``method="percentile"``, ``n_resamples=n_boot``, a
``numpy.random.default_rng(seed)`` generator, one resample per batch), whose ``standard_error`` is
reported.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy import stats

from ...core.checks import MAX_AVERAGED, MAX_ORBITS, MAX_RESAMPLES, check_int


def _check_durations(durations, censored=None):
    d = np.asarray(durations)
    if d.ndim != 1 or d.size == 0:
        raise ValueError("durations must be a non-empty 1-D array")
    if not np.all(np.isfinite(d)) or np.any(d < 0):
        raise ValueError("durations are out of range: allowed finite values >= 0")
    c = np.zeros(d.shape, bool) if censored is None else np.asarray(censored, bool)
    if c.shape != d.shape:
        raise ValueError("censored must have the same shape as durations")
    return d.astype(np.int64), c


def survival(durations, n_max: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(n, N)``: number of initial conditions with duration > n, for n = 0..n_max (non-increasing)."""
    d, _ = _check_durations(durations)
    n_max = int(d.max()) if n_max is None else check_int("n_max", n_max, 0, MAX_AVERAGED)
    counts = np.bincount(np.minimum(d, n_max + 1), minlength=n_max + 2)
    # N(n) = #(d > n) = total - #(d <= n)
    N = d.size - np.cumsum(counts)[: n_max + 1]
    return np.arange(n_max + 1), N


def linear_fit(x, y, w=None):
    """Weighted least squares ``y = a + b x``: ``(a, b, se_a, se_b)`` (standard errors from residuals).

    Minimises ``sum w (y - a - b x)^2`` with :func:`numpy.linalg.lstsq` on the design matrix
    ``sqrt(w) [1, x]``.  The standard errors are those of the covariance ``s^2 (X^T W X)^-1`` with the
    residual variance ``s^2 = sum w res^2 / (n - 2)``: ``w`` are relative weights (their scale
    cancels), not inverse variances.  Raises ``ValueError`` for fewer than 3 points, mismatched
    shapes, x or y not finite, weights negative or not finite, or fewer than two distinct x values.
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size < 3 or x.shape != y.shape:
        raise ValueError("linear_fit needs at least 3 points of matching shape")
    w = np.ones_like(x) if w is None else np.asarray(w, float)
    if w.shape != x.shape:
        raise ValueError("linear_fit weights must have the shape of x")
    x, y, w = x.ravel(), y.ravel(), w.ravel()
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValueError("linear_fit needs finite x and y")
    if not np.all(np.isfinite(w)) or np.any(w < 0) or not w.sum() > 0:
        raise ValueError("linear_fit weights are out of range: allowed finite w >= 0, not all 0")
    sw = np.sqrt(w)
    X = np.column_stack([sw, sw * x])
    if np.all(x[w > 0] == x[w > 0][0]):
        raise ValueError("linear_fit needs at least two distinct x values")
    (a, b), _rss, rank, _sv = np.linalg.lstsq(X, sw * y, rcond=None)
    if rank < 2:
        raise ValueError("linear_fit needs at least two distinct x values")
    res = y - a - b * x
    s2 = float((w * res**2).sum()) / (x.size - 2)
    # (X^T W X)^-1 from the triangular factor of the weighted design matrix: R^-1 R^-T
    Rinv = np.linalg.inv(np.linalg.qr(X, mode="r"))
    cov = s2 * (Rinv @ Rinv.T)
    return float(a), float(b), math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])


def _boot_se(res) -> np.ndarray:
    """Standard error(s) of a :func:`scipy.stats.bootstrap` result: ``res.standard_error`` when every
    resample gave a value; resamples whose fit failed (NaN) are left out otherwise, NaN below 2 left."""
    dist = np.atleast_2d(res.bootstrap_distribution)
    se = np.atleast_1d(np.asarray(res.standard_error, float)).copy()
    for k, row in enumerate(dist):
        if not np.all(np.isfinite(row)):
            good = row[np.isfinite(row)]
            se[k] = float(np.std(good, ddof=1)) if good.size > 1 else math.nan
    return se


def _bootstrap(sample, statistic, n_boot: int, seed: int):
    """:func:`scipy.stats.bootstrap` of a vectorised ``statistic`` over the observations (axis 0) of
    ``sample``: percentile method, ``n_boot`` resamples drawn one at a time from
    ``numpy.random.default_rng(seed)`` (one resample in memory at a time; the draws are those of
    ``rng.integers(0, n, n)`` per resample).  The confidence interval is not used (failed resamples
    give NaN and the interval is then undefined: its warning is silenced)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", category=stats.DegenerateDataWarning)
        return stats.bootstrap(
            (sample,),
            statistic,
            n_resamples=int(n_boot),
            batch=1,
            vectorized=True,
            axis=0,
            method="percentile",
            rng=np.random.default_rng(seed),
        )


@dataclass
class SurvivalFit:
    """Eq. (14) fit: ``N0``, ``kappa``, ``mean_n`` (``<n>``), ``tau_fit`` (decay time) and errors."""

    N0: float
    kappa: float
    kappa_se_ls: float
    kappa_se_boot: float
    mean_n: float
    mean_n_se: float
    tau_fit: float
    tau_fit_se_ls: float
    tau_fit_se_boot: float
    n_lo: int
    n_hi: int
    n_ic: int
    n_censored: int

    def as_dict(self) -> dict:
        return {k: (float(v) if isinstance(v, (float, np.floating)) else int(v)) for k, v in self.__dict__.items()}


def _fit_range(N, n_lo, n_hi, n_min_count):
    if n_hi is None:
        below = np.flatnonzero(N < n_min_count)
        n_hi = int(below[0]) - 1 if below.size else N.size - 1
    return int(n_lo), int(min(n_hi, N.size - 1))


def _fit_once(d, n_lo, n_hi, n_max):
    n, N = survival(d, n_max)
    sel = (n >= n_lo) & (n <= n_hi) & (N > 0)
    a, b, se_a, se_b = linear_fit(n[sel], np.log(N[sel]), w=N[sel])
    return a, b, se_a, se_b


def fit_survival(
    durations,
    censored=None,
    cap: int | None = None,
    n_lo: int | None = None,
    n_hi: int | None = None,
    n_min_count: int = 100,
    n_boot: int = 200,
    seed: int = 0,
) -> SurvivalFit:
    """Fit Eq. (14) to the survival curve of ``durations`` (Fig. 11; see the module docstring).

    ``censored`` marks orbits stopped at ``cap`` (their duration is >= cap); the fit range must end
    below the cap.  ``kappa_se_boot`` and ``tau_fit_se_boot`` are the ``standard_error`` of
    :func:`scipy.stats.bootstrap` over the initial conditions (``n_boot`` resamples of the durations,
    each refitted over the same range; a resample whose fit fails or does not decay is left out;
    NaN for ``n_boot < 2``).  Deterministic (``seed``).  Raises ``ValueError`` on bad input or an
    empty range.
    """
    d, c = _check_durations(durations, censored)
    cap = int(d.max()) if cap is None else check_int("cap", cap, 0, MAX_AVERAGED)
    n_boot = check_int("n_boot", n_boot, 0, MAX_RESAMPLES)
    n_min_count = check_int("n_min_count", n_min_count, 1, MAX_ORBITS)
    if n_hi is None and d.size < n_min_count:
        raise ValueError(
            f"{d.size} orbits are too few to fit: allowed at least n_min_count={n_min_count} (the fit "
            "range ends where fewer than n_min_count orbits are still transient)"
        )
    auto_hi = "" if n_hi is not None else f" (n_hi: the last n with at least n_min_count={n_min_count} orbits left)"
    n_lo = int(np.median(d)) if n_lo is None else check_int("n_lo", n_lo, 0, MAX_AVERAGED)
    _, N = survival(d, cap)
    n_lo, n_hi = _fit_range(N, n_lo, n_hi, n_min_count)
    if n_hi >= cap and c.any():
        n_hi = cap - 1
    if not (0 <= n_lo < n_hi - 2):
        raise ValueError(f"fit range n_lo={n_lo}, n_hi={n_hi} is empty: allowed 0 <= n_lo < n_hi - 2{auto_hi}")
    a, b, se_a, se_b = _fit_once(d, n_lo, n_hi, cap)
    if not b < 0:
        raise ValueError("survival curve does not decay over the fit range")
    mean_n = float(d.mean())
    mean_se = float(d.std(ddof=1) / math.sqrt(d.size)) if d.size > 1 else math.nan
    tau = -1.0 / b
    kappa = mean_n / tau
    kappa_se_ls = mean_n * se_b  # slope error only, <n> held fixed (what a plain LS fit reports)
    tau_se_ls = se_b / b**2
    kse = tse = math.nan
    if n_boot >= 2 and d.size >= 2:

        def stat(db, axis=-1):  # (..., n) resamples of the durations -> (2, ...): kappa, tau_fit
            db = np.moveaxis(db, axis, -1)
            out = np.full((2,) + db.shape[:-1], np.nan)
            for i in np.ndindex(db.shape[:-1]):
                try:
                    _, bb, _, _ = _fit_once(db[i], n_lo, n_hi, cap)
                except ValueError:
                    continue
                if bb < 0:
                    out[(0,) + i] = db[i].mean() * -bb
                    out[(1,) + i] = -1.0 / bb
            return out

        kse, tse = (float(v) for v in _boot_se(_bootstrap(d, stat, n_boot, seed)))
    return SurvivalFit(
        float(math.exp(a)),
        float(kappa),
        float(kappa_se_ls),
        kse,
        mean_n,
        mean_se,
        float(tau),
        float(tau_se_ls),
        tse,
        n_lo,
        n_hi,
        int(d.size),
        int(c.sum()),
    )


# ---------------------------------------------------------------- uncertainty exponent (Fig. 10)


@dataclass
class UncertaintyFit:
    """``f(eps) ~ C eps^phi``: exponent ``phi`` with least-squares and bootstrap standard errors."""

    n_threshold: int
    eps: np.ndarray
    f: np.ndarray
    phi: float
    phi_se_ls: float
    phi_se_boot: float
    log10_C: float
    n_points: int

    def as_dict(self) -> dict:
        return {
            "n_threshold": self.n_threshold,
            "eps": self.eps.tolist(),
            "f": self.f.tolist(),
            "phi": self.phi,
            "phi_se_ls": self.phi_se_ls,
            "phi_se_boot": self.phi_se_boot,
            "log10_C": self.log10_C,
            "n_points": self.n_points,
        }


def uncertain_fraction(dA, dB, dC, n_threshold: int) -> np.ndarray:
    """``f(eps)`` for every eps: ``dA`` shape (P,), ``dB``/``dC`` shape (P, E) (durations at
    ``tau0 +- eps``).  Returns shape (E,)."""
    return uncertain_mask(dA, dB, dC, n_threshold).mean(axis=0)


def uncertain_mask(dA, dB, dC, n_threshold: int) -> np.ndarray:
    """Boolean ``(P, E)``: point ``i`` is eps-uncertain at ``eps[j]`` (one of ``tau0 +- eps`` lies in the
    other basin: duration < ``n_threshold`` on one side, >= on the other)."""
    dA, dB, dC = np.asarray(dA), np.asarray(dB), np.asarray(dC)
    if dB.shape != dC.shape or dB.ndim != 2 or dB.shape[0] != dA.shape[0]:
        raise ValueError("dB and dC must have shape (len(dA), n_eps)")
    if int(n_threshold) < 1:
        raise ValueError(f"n_threshold={n_threshold!r} is out of range: allowed >= 1")
    a = (dA < n_threshold)[:, None]
    return ((dB < n_threshold) != a) | ((dC < n_threshold) != a)


def fit_uncertainty(eps, unc: np.ndarray, n_threshold: int, n_boot: int = 200, seed: int = 0) -> UncertaintyFit:
    """Fit ``log10 f = log10 C + phi log10 eps`` (Fig. 10: ordinary least squares over the eps with
    f > 0) and bootstrap the exponent by resampling the random points with
    :func:`scipy.stats.bootstrap` (``n_boot`` resamples of the rows of ``unc``, a resample with fewer
    than 3 nonzero fractions left out; ``phi_se_boot`` is its ``standard_error``, NaN for
    ``n_boot < 2``; deterministic, ``seed``).  ``unc``: boolean (P, E) uncertain mask."""
    eps = np.asarray(eps, float)
    unc = np.asarray(unc, bool)
    if eps.ndim != 1 or unc.ndim != 2 or unc.shape[1] != eps.size:
        raise ValueError("unc must have shape (n_points, len(eps))")
    if np.any(~np.isfinite(eps)) or np.any(eps <= 0):
        raise ValueError("eps is out of range: allowed eps > 0")
    n_boot = check_int("n_boot", n_boot, 0, MAX_RESAMPLES)
    f = unc.mean(axis=0)
    ok = f > 0
    if ok.sum() < 3:
        raise ValueError("fewer than 3 eps values with a nonzero uncertain fraction: cannot fit an exponent")
    a, b, se_a, se_b = linear_fit(np.log10(eps[ok]), np.log10(f[ok]))
    P = unc.shape[0]
    le = np.log10(eps)

    def stat(ub, axis=-1):  # (E, ..., P) resamples of the points -> (...): the exponent
        fb = np.moveaxis(ub, axis, -1).mean(axis=-1)
        out = np.full(fb.shape[1:], np.nan)
        for i in np.ndindex(fb.shape[1:]):
            col = fb[(slice(None),) + i]
            okb = col > 0
            if okb.sum() >= 3:
                out[i] = linear_fit(le[okb], np.log10(col[okb]))[1]
        return out

    se_boot = float(_boot_se(_bootstrap(unc, stat, n_boot, seed))[0]) if n_boot >= 2 and P >= 2 else math.nan
    return UncertaintyFit(int(n_threshold), eps, f, float(b), float(se_b), se_boot, float(a), int(P))


__all__ = [
    "survival",
    "linear_fit",
    "SurvivalFit",
    "fit_survival",
    "UncertaintyFit",
    "uncertain_fraction",
    "uncertain_mask",
    "fit_uncertainty",
]
