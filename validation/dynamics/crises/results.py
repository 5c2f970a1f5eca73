"""The results of the crisis analyses, typed: :class:`R2Result` (:func:`.r2.locate_r2`) and the one type of
a crisis located from mean times between events, :class:`CrisisResult`, with the evidence each crisis adds:
:class:`R1Result` (:func:`.r1.locate_r1`) and :class:`Alpha1Result` (:func:`.alpha1.locate_alpha1`).

Each result's ``as_dict()`` gives the data of the result for a file -- every scan row, bracket, fit
and the cost of the engine runs -- and leaves out the objects that are not data (periodic orbits,
branches, the laminar statistics), as ``data/dynamics/crises.json`` of the report holds them.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ....core.deprecation import renamed_attribute
from ....mapimpl.periodic import PeriodicOrbit
from ....mapimpl.continuation import BifurcationPoint, Branch
from .stats import Bracket, CrisisFit, Located


@dataclass
class _Result:
    """``as_dict()`` of a result dataclass: its fields but those in ``_OBJECTS`` (not data), nested
    results by their own ``as_dict()``."""

    _OBJECTS: ClassVar[tuple[str, ...]] = ()

    def as_dict(self) -> dict:
        out = {}
        for f in dataclasses.fields(self):
            if f.name in self._OBJECTS:
                continue
            v = getattr(self, f.name)
            out[f.name] = v.as_dict() if hasattr(v, "as_dict") else v
        return out


@dataclass
class LaminarStats:
    """Laminar phases near the ghost of the fold orbit, per ``r``: ``mean`` length (impacts), its
    standard error ``sem``, the number of complete phases ``count`` and the impacts observed
    ``exposure``; ``eps``, ``min_length``: the criterion; ``orbits``, ``cap``: orbits per r, impacts each."""

    r: np.ndarray
    mean: np.ndarray
    sem: np.ndarray
    count: np.ndarray
    exposure: np.ndarray
    eps: float
    min_length: int
    orbits: int
    cap: int


@dataclass
class R2Result(_Result):
    """r2 (fold of the 6-impact orbit, alpha = 3) and the type-I intermittency exponent.

    ``r2``: the fold (Newton on the extended system); ``fold``: the
    :class:`~..continuation.BifurcationPoint` (orbit, multipliers, residual); ``branch``: the 6-impact
    branch (:func:`gear_rattle.mapimpl.branches.six_impact_branch`, shared with r1); ``laminar``: :class:`LaminarStats`
    at ``r2 + dr``; ``slope``, ``slope_err``: fitted exponent of ``<l> ~ (r - r2)^slope`` (theory -1/2)
    and its total error ``sqrt(stat^2 + syst^2)``; ``slope_stat`` (weighted fit, scaled by
    sqrt(chi^2_red) when > 1), ``slope_syst`` (fit-range systematic), ``chi2_red``; ``subranges``:
    ``[(points used, slope)]``; ``paper_fig5``: the paper's r of Fig. 5 and its distance to r2; ``cost``
    (:class:`.orbits.Cost`), ``profile``."""

    _OBJECTS = ("fold", "branch", "laminar")

    r2: float
    fold: BifurcationPoint
    branch: Branch
    laminar: LaminarStats
    dr: np.ndarray
    slope: float
    slope_err: float
    slope_stat: float
    slope_syst: float
    chi2_red: float
    subranges: list
    paper_fig5: dict
    cost: dict
    profile: str


#: The located values every crisis result holds under one name, written to a file with the crisis's name
#: in front (``value`` -> ``r1``, ``goy_err`` -> ``r1_goy_err``; :meth:`CrisisResult.as_dict`).
PREFIXED = {"value": "", "err": "_err", "goy": "_goy", "goy_err": "_goy_err", "stat": "_stat", "syst": "_syst"}
PREFIXED |= {"free": "_free", "free_err": "_free_err"}


@dataclass
class CrisisResult(_Result):
    """A crisis located from the mean time between events of a chaotic set (the interior crisis r1 from
    band hops, :class:`R1Result`; the boundary crisis alpha1 from escapes, :class:`Alpha1Result`): the
    fields both hold, under one name each.

    ``value``, ``err``: the reported value (:func:`~.stats.locate`): the GOY fit when it lies in the
    bracket by direct observation and is narrower, else the bracket's midpoint and half-width; ``method``
    (``"fit"``/``"bracket"``), ``located`` (:class:`~.stats.Located`); ``goy``, ``goy_err``: the GOY fit
    of the mean time between events (exponent fixed to that of the saddle orbit at the crisis) and its
    total error ``sqrt(stat^2 + syst^2)``; ``stat`` (68 % profile-likelihood half-width, the larger side),
    ``syst`` (fit-range systematic); ``free``, ``free_err``, ``g_free``, ``g_free_err``: the fit with the
    exponent free; ``fit_goy``, ``fit_free`` (:class:`~.stats.CrisisFit`); ``subranges_goy``,
    ``subranges_free``: ``[(points used, crisis value), ...]`` behind the systematic; ``goy_exponent``:
    ``1/2 + ln|m_u|/|ln|m_s||`` of ``saddle`` (the saddle orbit at the crisis, a
    :class:`~gear_rattle.mapimpl.periodic.PeriodicOrbit`); ``bracket`` (:class:`~.stats.Bracket`: events
    ``seen`` at one end, none at ``clear`` in ``clear_exposure`` impacts, which excludes mean times below
    ``clear_bound``); ``bracket_margin``: the distance below ``clear`` at which the GOY law gives
    ``clear_bound``; ``consistent``: the fit lies in the bracket within its error; ``ics``: how the initial
    conditions on the chaotic set were made; ``cost`` (:class:`.orbits.Cost`); ``profile``.

    In a file (:meth:`as_dict`) the located values carry the crisis's name (:data:`NAME`): ``r1``,
    ``r1_err``, ``r1_goy``, ... (:data:`PREFIXED`), in the order :data:`KEYS`."""

    #: The crisis (``"r1"``, ``"alpha1"``): the name of its located values in a file.
    NAME: ClassVar[str] = ""
    #: The keys of :meth:`CrisisResult.as_dict`, in the file's order.
    KEYS: ClassVar[tuple[str, ...]] = ()

    value: float
    err: float
    method: str
    located: Located
    goy: float
    goy_err: float
    stat: float
    syst: float
    free: float
    free_err: float
    g_free: float
    g_free_err: float
    fit_goy: CrisisFit
    fit_free: CrisisFit
    subranges_goy: list
    subranges_free: list
    goy_exponent: float
    saddle: PeriodicOrbit
    bracket: Bracket
    bracket_margin: float
    consistent: bool
    ics: dict
    cost: dict
    profile: str

    def as_dict(self) -> dict:
        """The data of the result (its fields but the objects that are not data), the located values named
        after the crisis, in the order :data:`KEYS`."""
        named = {(self.NAME + PREFIXED[k] if k in PREFIXED else k): v for k, v in super().as_dict().items()}
        return {k: named[k] for k in self.KEYS}


def located_fields(where: Located, goy: CrisisFit, free: CrisisFit, syst_goy: float, syst_free: float) -> dict:
    """The located values of a :class:`CrisisResult` (``value`` to ``fit_free``): the reported location
    ``where``, the GOY fit ``goy`` and the free fit ``free``, each fit's total error with its fit-range
    systematic (``syst_goy``, ``syst_free``) added in quadrature."""
    return dict(
        value=where.value,
        err=where.err,
        method=where.method,
        located=where,
        goy=goy.mu_c,
        goy_err=math.hypot(goy.err, syst_goy),
        stat=goy.err,
        syst=syst_goy,
        free=free.mu_c,
        free_err=math.hypot(free.err, syst_free),
        g_free=free.g,
        g_free_err=free.g_err,
        fit_goy=goy,
        fit_free=free,
    )


def _old_names(cls: type[CrisisResult]) -> type[CrisisResult]:
    """``cls`` with the old names of its located values (``r1_goy`` for ``goy``, ...) as deprecated
    read-only properties."""
    for new, suffix in PREFIXED.items():
        old = renamed_attribute(cls.NAME + suffix, new)
        setattr(cls, cls.NAME + suffix, property(old.fget, doc=f"Deprecated: the old name of ``{new}``."))
    return cls


@_old_names
@dataclass
class R1Result(CrisisResult):
    """The interior crisis r1 (alpha = 3) from band hops (:class:`CrisisResult`; the saddle is the
    6-impact orbit at r1).  Besides: ``lower_bound`` = ``bracket.seen`` (r1 > lower_bound: hops seen at the
    largest r with hops), ``upper_bound`` = ``bracket.clear`` (no hop in ``clear_exposure`` impacts, >=
    probe_orbits x probe_cap); ``clear_lyapunov`` (:func:`.r1.lyapunov_at` at ``clear``, None without one:
    the bracket bounds r1 from above only when ``clear_lyapunov["chaotic"]``); ``near``: the mean time
    between hops at the bracket's ``seen`` value (``T``, ``lo``, ``hi`` at 95 %, ``hops``, ``exposure``,
    ``dispersion``, ``orbits``); ``hops``: per r ``{r, T, lo, hi, events, exposure, dispersion, orbits}``;
    ``paper_fig7``: the paper's r of Fig. 7 and its distance below r1; ``ics``: ``r_ref``, ``settle``,
    ``drawn``, ``rejected``, ``n``."""

    NAME = "r1"
    _OBJECTS = ("saddle",)
    KEYS = (
        "r1", "r1_err", "method", "located", "r1_goy", "r1_goy_err", "r1_stat", "r1_syst", "r1_free",
        "r1_free_err", "g_free", "g_free_err", "fit_goy", "fit_free", "subranges_goy", "subranges_free",
        "goy_exponent", "bracket", "bracket_margin", "lower_bound", "upper_bound", "consistent",
        "clear_lyapunov", "near", "hops", "paper_fig7", "ics", "cost", "profile",
    )  # fmt: skip

    lower_bound: float
    upper_bound: float
    clear_lyapunov: dict | None
    near: dict
    hops: list
    paper_fig7: dict


@_old_names
@dataclass
class Alpha1Result(CrisisResult):
    """The boundary crisis alpha1 (Fig. 8, r = 0.9) from escape times of the pre-crisis chaotic set
    (:class:`CrisisResult`; the saddle is the 4-impact orbit at alpha1, events are escapes ``seen`` at the
    smallest alpha with escapes).  Besides: ``alpha_sn``: the fold of the 4-impact orbit; ``node``: the
    stable 4-impact orbit at the alpha of Fig. 9; ``branch``; ``lifetimes``: per alpha ``{alpha, T, lo,
    hi (95 %), events, exposure, orbits, dropped, approach_lag_max, other_end}``; ``T_max_measured``: the
    largest finite mean lifetime measured; ``paper``: the paper's alpha1 with the measured mean lifetime
    there (``T``, ``lo``, ``hi``) and ``diagram_impacts_equal``: the diagram length at which a bifurcation
    diagram started on the chaotic set would put the crisis there; ``diagram``: ``{impacts,
    alpha_apparent}`` for this project's Fig. 8 setting; ``ics``: ``alpha_ref``, ``settle``, ``drawn``,
    ``captured``, ``n``, ``probe_n``."""

    NAME = "alpha1"
    _OBJECTS = ("saddle", "node", "branch")
    KEYS = (
        "alpha1", "alpha1_err", "method", "located", "alpha1_goy", "alpha1_goy_err", "alpha1_stat",
        "alpha1_syst", "alpha1_free", "alpha1_free_err", "g_free", "g_free_err", "fit_goy", "fit_free",
        "subranges_goy", "subranges_free", "goy_exponent", "alpha_sn", "bracket", "bracket_margin",
        "consistent", "lifetimes", "T_max_measured", "paper", "diagram", "ics", "cost", "profile",
    )  # fmt: skip

    alpha_sn: float
    node: PeriodicOrbit
    branch: Branch
    lifetimes: list
    T_max_measured: float
    paper: dict
    diagram: dict


__all__ = [
    "LaminarStats",
    "R2Result",
    "PREFIXED",
    "CrisisResult",
    "located_fields",
    "R1Result",
    "Alpha1Result",
]
