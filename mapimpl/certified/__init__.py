"""The certified track: the model of Eq. (3) in ball arithmetic (python-flint ``arb``).

Every impact time and velocity is *enclosed* by a ball and every decision (which wall, stick or
bounce, captured or not) is proven, or the computation raises :class:`CertificationError`; it never
guesses and never loops forever.  The golden suite's cases (``validation/golden``) and the certified
post-release duration ``T_post`` of Figs. 9-11 (docs/release.md) are computed with it.

Modules, bottom up:

=================  =============================================================================
:mod:`.balls`      working precision, exact balls of floats, :class:`CertificationError`
:mod:`.model`      the parameters as balls (:class:`Model`) and the closed-form flight (Eqs. 7-8)
:mod:`.contact`    the first wall contact of a flight, certified (:func:`certified_flight`)
:mod:`.sticking`   the sticking policy in balls: stick or bounce, the release time
:mod:`.orbit`      one certified map step (Eqs. 11-13) and certified impact sequences
:mod:`.track`      the certified track on demand: any orbit, a precision schedule, float64 bounds
:mod:`.noimpact`   orbits that end with a flight proven never to land (``no_impact``, ``gamma = 0``)
:mod:`.capture`    the capture target of Figs. 9-11 and the certified capture decision
:mod:`.release`    one certified run of the canonical release orbit at one precision
:mod:`.duration`   the certified ``T_post``: a schedule of precisions, confirmed
:mod:`.jets`       forward-mode differentiation over balls (the Jacobian enclosed over a box)
:mod:`.krawczyk`   the Krawczyk operator: a box proven to hold exactly one zero
:mod:`.shooting`   periodic orbits as zeros of the multiple-shooting system; monodromy matrix
:mod:`.periodic`   certified periodic orbits, Floquet multipliers, folds and period doublings
=================  =============================================================================

A new certified computation is a new module here, built on :mod:`.model`, :mod:`.contact` and
:mod:`.orbit` (or :mod:`.krawczyk` for a zero of an analytic system).
"""

from .balls import (
    MAX_PREC,
    PREC,
    CertificationError,
    decimal_interval,
    exact,
    float_bounds,
    mod_two_pi,
    nearest_float,
    precision,
    span,
    upper_float,
)
from .capture import Target, capture_decision, certified_distance
from .contact import MAX_EVALS, T_MAX, FlightCertificate, NoContactError, certified_flight, mean_value_impact
from .duration import (
    PRECISIONS,
    ROUNDINGS,
    ReleaseDuration,
    certified_release_duration,
    certified_release_durations,
    model_params,
)

# (the function krawczyk stays in its module: re-exported, it would hide the module .krawczyk itself)
from .krawczyk import KrawczykResult, refine, verify_box
from .model import PARAM_NAMES, Flight, Model, parameter_ball
from .noimpact import certify_never_lands, certify_no_impact_orbit
from .orbit import CertifiedOrbit, CertifiedStep, Departure, Event, certified_departure, certified_step, certify_orbit
from .periodic import (
    CertifiedBifurcation,
    CertifiedPeriodicOrbit,
    certify_bifurcation,
    certify_periodic_orbit,
    floquet,
    prove_flights,
)
from .release import MAX_IMPACTS, RADIUS_LIMIT, Attempt, certify_post_release, certify_post_release_deltas
from .track import CertifiedRun, CertifiedSequence, UncertifiedOrbit, certified_orbit
from .sticking import certify_release, certify_zero, release_delay, release_phase, release_time, stick_decision

__all__ = [
    "MAX_PREC",
    "PREC",
    "CertificationError",
    "decimal_interval",
    "exact",
    "float_bounds",
    "mod_two_pi",
    "nearest_float",
    "precision",
    "span",
    "upper_float",
    "Target",
    "capture_decision",
    "certified_distance",
    "MAX_EVALS",
    "T_MAX",
    "FlightCertificate",
    "NoContactError",
    "certified_flight",
    "mean_value_impact",
    "PRECISIONS",
    "ROUNDINGS",
    "ReleaseDuration",
    "certified_release_duration",
    "certified_release_durations",
    "model_params",
    "PARAM_NAMES",
    "Flight",
    "Model",
    "parameter_ball",
    "certify_never_lands",
    "certify_no_impact_orbit",
    "CertifiedOrbit",
    "CertifiedStep",
    "Departure",
    "Event",
    "certified_departure",
    "CertifiedRun",
    "CertifiedSequence",
    "UncertifiedOrbit",
    "certified_orbit",
    "certified_step",
    "certify_orbit",
    "MAX_IMPACTS",
    "RADIUS_LIMIT",
    "Attempt",
    "certify_post_release",
    "certify_post_release_deltas",
    "certify_release",
    "certify_zero",
    "release_delay",
    "release_phase",
    "release_time",
    "stick_decision",
    "KrawczykResult",
    "refine",
    "verify_box",
    "CertifiedBifurcation",
    "CertifiedPeriodicOrbit",
    "certify_bifurcation",
    "certify_periodic_orbit",
    "floquet",
    "prove_flights",
]
