"""Statistics of the crisis analyses: mean times of memoryless processes with censoring and the
Grebogi-Ott-Yorke (GOY) exponent (:mod:`.meantime`), crisis-law fits by maximum likelihood
(:mod:`.crisislaw`), and brackets by direct observation (:mod:`.brackets`); this module gathers them.

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

from .brackets import (
    WHY_BRACKET_NARROWER,
    WHY_FIT_NARROWER,
    WHY_FIT_OUTSIDE,
    WHY_NO_BRACKET,
    Bracket,
    Located,
    bracket,
    locate,
    next_probes,
)
from .crisislaw import CrisisFit, fit_crisis, fit_crisis_fixed, fit_power_law, range_systematic
from .meantime import (
    LEVEL,
    SIDES,
    MeanTime,
    censored_lifetimes,
    goy_exponent,
    lifetime_lower_bound,
    mean_time,
    pearson_dispersion,
)

__all__ = [
    "LEVEL",
    "SIDES",
    "MeanTime",
    "lifetime_lower_bound",
    "pearson_dispersion",
    "mean_time",
    "censored_lifetimes",
    "goy_exponent",
    "CrisisFit",
    "fit_crisis",
    "fit_crisis_fixed",
    "range_systematic",
    "fit_power_law",
    "Bracket",
    "bracket",
    "next_probes",
    "Located",
    "locate",
    "WHY_NO_BRACKET",
    "WHY_FIT_NARROWER",
    "WHY_BRACKET_NARROWER",
    "WHY_FIT_OUTSIDE",
]
