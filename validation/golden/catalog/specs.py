"""The catalogue of shipped cases: the 25 cases of ``validation/golden/cases`` as :class:`..formats.spec.Spec`
values, in order (:func:`specs`), each with the bug classes it exists to catch and its level
(docs/golden.md, "Cases").

Case settings that are *found* rather than chosen (the grazing initial velocities, the chaotic horizon,
the states before a release or at a sticking threshold) are computed here, by documented rules, every
time the suite is regenerated (``python -m gear_rattle.validation.golden.generate``); the certification
and the files are :mod:`.build`'s.  The states at a sticking threshold or before a release are found by
:mod:`..rules.thresholds`, as the fuzzer's scenarios find theirs.
"""

from __future__ import annotations

import math
from dataclasses import replace
from decimal import Decimal

from ....core.paper import PAPER_FIG2, PAPER_FIG3, PAPER_PARAMS
from ....core.params import Params
from ....mapimpl import certified as cert
from ..formats.spec import Spec
from ..rules.thresholds import release_lead_state, stick_ratio_sdot0
from . import contacts

FIG2 = PAPER_FIG2
FIG3 = PAPER_FIG3
#: The transient setting of Figs. 9-11 (float64 values of the printed decimals).
FIG11 = PAPER_PARAMS
#: Phase of the release case's initial state: the centre of the Fig. 11 box in tau (3.0 < tau0 < 3.5).
RELEASE_TAU0 = 3.25


#: The length of the shipped chaotic cases (0002, 0012): the horizon ``n`` at which an error of ``CHAOS_ERR0``
#: per impact, grown like ``exp(lambda1 n)``, reaches ``CHAOS_TOL / CHAOS_SAFETY`` (the rule of suite 0.5.0; a
#: length, not a tolerance: every row's tolerance is set by :mod:`..rules.conditioning`).
CHAOS_TOL, CHAOS_ERR0, CHAOS_SAFETY = 1e-8, 1e-12, 10.0
#: Target pre-impact speed of the grazing impact, and the initial-velocity offset of the near miss.
GRAZE_TARGET_SPEED, NEAR_MISS_OFFSET = 1e-3, 1e-7


# ---------------------------------------------------------------------------------------------
# settings found by rules


#: Impacts of the QR run that sets the chaotic horizon, and the decimals its lambda1 is rounded to.  A
#: converged value: on Fig. 3's parameters one float64 orbit of 1e6 impacts gives 0.3512 ... 0.3525 from
#: any start, with or without the engine's XLA options (12 orbits of 2e5 impacts: 0.3520, SD 0.0010), so
#: the 2-decimal value and the horizon are the same for every float64 pseudo-orbit.  5000 impacts (the rule
#: before) scatter by SD 0.009 from orbit to orbit: 0.336 ... 0.365 as the float64 map changed.
CHAOS_LYAP_IMPACTS, CHAOS_LYAP_DECIMALS = 1_000_000, 2


def chaos_horizon(params: Params) -> tuple[int, float]:
    """Impacts ``n`` with ``CHAOS_ERR0 * exp(lambda1 n) * CHAOS_SAFETY <= CHAOS_TOL`` (lambda1 per impact,
    QR method over CHAOS_LYAP_IMPACTS impacts after 500 from (0, 0.5), rounded to CHAOS_LYAP_DECIMALS)."""
    from ....mapimpl.lyapunov import lyapunov

    lam = float(lyapunov(params, "r", [params.r], n_impacts=CHAOS_LYAP_IMPACTS, transient=500).lam[0, 0])
    lam = round(lam, CHAOS_LYAP_DECIMALS)
    if not lam > 0:
        raise RuntimeError(f"lambda1={lam} is not positive: not a chaotic case")
    return horizon(lam), lam


def horizon(lam: float) -> int:
    """The float64 horizon rule of the chaotic cases: ``n = floor(ln(tol / (err0 * safety)) / lambda1)``."""
    return int(math.floor(math.log(CHAOS_TOL / (CHAOS_ERR0 * CHAOS_SAFETY)) / lam))


def _chaos_lyapunov_text() -> str:
    return (
        f"QR method (mapimpl/lyapunov.py) on the float64 map, one orbit from (tau0, sdot0) = (0, 0.5), "
        f"{CHAOS_LYAP_IMPACTS} impacts after 500, rounded to {CHAOS_LYAP_DECIMALS} decimals: converged "
        "(orbits of 1e6 impacts from other starts give 0.3512 ... 0.3525)"
    )


def _horizon_rule_text() -> str:
    return (
        f"n = floor(ln(tol / (err0 * safety)) / lambda1) with tol={CHAOS_TOL:g}, err0={CHAOS_ERR0:g} (per-impact "
        f"error of a good float64 solver), safety={CHAOS_SAFETY:g}; errors grow like exp(lambda1 n)"
    )


def finish_release_case(spec: Spec) -> Spec:
    """The found settings of the release case: its horizon from the Lyapunov exponent of the
    *transient* at alpha = 1.245 (:func:`mapimpl.float64_release.transient_lyapunov`), and, as
    oracle notes, the certified post-release duration ``T_post`` for the decimal parameters and for their
    float64 roundings (:func:`mapimpl.certified.certified_release_duration`, several minutes), the float64
    engine's own ``T_post``, ``delta`` and the capture target."""
    from ....core.paper import DELTA, PAPER_DECIMAL
    from ....mapimpl import certified as rel
    from ....mapimpl import float64_release as fl64
    from ....mapimpl.engine.t_post import float64_target

    ly = fl64.transient_lyapunov(spec.params, n_side=RELEASE_LYAP_SIDE, impacts=RELEASE_LYAP_IMPACTS)
    lam = round(ly["lambda1"], 3)
    if not lam > 0:
        raise RuntimeError(f"transient lambda1={lam} is not positive")
    n = horizon(lam)
    cert_notes = {}
    target = float64_target(spec.params)
    for rounding in rel.ROUNDINGS:
        d = rel.certified_release_duration(PAPER_DECIMAL, 0, rounding=rounding, target=target)
        if d.status != "captured" or not d.confirmed:
            raise cert.CertificationError(f"release case: T_post ({rounding}) not certified: {d.summary()}")
        cert_notes[rounding] = {
            "params": d.params
            if rounding == "decimal"
            else {k: str(Decimal(getattr(spec.params, k))) for k in cert.PARAM_NAMES},
            "T_post": d.value,
            "precision_bits": d.precision,
            "confirmed_at_bits": d.attempts[-1].prec,
            "capture_distance": d.attempts[-1].distance,
            "release_phase": d.release_phase,
        }
    f64 = fl64.float64_release_duration(spec.params, 0)
    notes = dict(spec.notes)
    notes.update(
        {
            "lyapunov_lambda1_per_impact": lam,
            "lyapunov_method": (
                f"QR exponent of the transient: {ly['orbits']} orbits from a {RELEASE_LYAP_SIDE}x"
                f"{RELEASE_LYAP_SIDE} grid of the Fig. 11 box, {ly['impacts_used']} impacts before each "
                "comes within 1e-2 of the 4-impact orbit (mapimpl/float64_release.py)"
            ),
            "horizon_rule": _horizon_rule_text(),
            "T_post_definition": (
                "the release flight's first impact is post-release impact 1 (here: impact 1); T_post is "
                "the index of the first post-release impact whose pre-impact state lies within delta "
                "of the target (sup norm of the wrapped phase difference and the sdot difference, "
                "same wall); an initial condition that first sticks at its impact n_s has transient "
                "duration n_s + T_post"
            ),
            "T_post_certified": cert_notes,
            "T_post_float64_engine": {
                "value": f64["value"],
                "meaning": "the float64 engine's own T_post: a sample of "
                "a chaotic orbit, not a value (the float64 orbit leaves the true one after "
                f"~{fl64.float64_horizon(lam, DELTA):.0f} impacts at this lambda1)",
            },
            "capture_delta": DELTA,
            "capture_target": target.as_dict()
            | {
                "source": "float64 4-impact period-1 orbit of "
                "mapimpl.engine.transients.periodic_target, taken as exact numbers"
            },
        }
    )
    return replace(spec, n_impacts=n, notes=notes, finish=None)


#: Grid side and impacts of the transient Lyapunov exponent of the release case.
RELEASE_LYAP_SIDE, RELEASE_LYAP_IMPACTS = 8, 1500


def specs() -> list[Spec]:
    """The cases, in order (ids are folder names): 0001-0012 (:func:`flight_specs`, :func:`contact_specs`,
    :func:`chatter_specs`, :func:`parameter_edge_specs`, :func:`release_spec`), then 0013-0025
    (:func:`new_specs`)."""
    return flight_specs() + contact_specs() + chatter_specs() + parameter_edge_specs() + [release_spec()] + new_specs()


def flight_specs() -> list[Spec]:
    """Cases 0001-0003: the paper's regular (Fig. 2) and chaotic (Fig. 3) rattling, the chaotic case's
    horizon found by :func:`chaos_horizon`, and a start in free flight."""
    n_chaos, lam = chaos_horizon(FIG3)
    return [
        Spec(
            "0001-regular-fig2",
            "Paper Fig. 2 parameters (alpha=0.5): regular rattling, transient into the "
            "periodic motion; pre-impact start (tau0, sdot0) = (0, 0.5) on the upper wall.",
            FIG2,
            0.0,
            0.5,
            20,
            tags=("regular", "paper"),
            catches=("flight-or-impact-law",),
        ),
        Spec(
            "0002-chaotic-fig3",
            "Paper Fig. 3 parameters (alpha=3): chaotic rattling, short horizon set by the "
            "largest Lyapunov exponent so that a float64 implementation's error stays below the tolerance.",
            FIG3,
            0.0,
            0.5,
            n_chaos,
            tags=("chaotic", "paper"),
            notes={
                "lyapunov_lambda1_per_impact": lam,
                "lyapunov_method": _chaos_lyapunov_text(),
                "horizon_rule": _horizon_rule_text(),
            },
            catches=("float64-drift", "flight-or-impact-law"),
        ),
        Spec(
            "0003-free-flight-start",
            "Start in free flight (tau0, s0, sdot0) = (1, -0.3, 0.2), Fig. 2 parameters: "
            "impact 0 is the first wall reached.",
            FIG2,
            1.0,
            0.2,
            20,
            s0=-0.3,
            tags=("regular", "free-flight"),
            catches=("free-flight-start",),
        ),
    ]


def contact_specs() -> list[Spec]:
    """Cases 0004-0006 (Fig. 2 parameters): a grazing impact and a near miss, their initial velocities found
    by bisection (:mod:`.contacts`), and a flight returning to the wall it left."""
    graze_v = contacts.grazing_speed_sdot0(FIG2, 2.0, 0.40, 0.41, GRAZE_TARGET_SPEED)
    miss_v = contacts.near_miss_offset_sdot0(FIG2, 2.0, 0.40, 0.41, NEAR_MISS_OFFSET)
    return [
        Spec(
            "0004-grazing-impact",
            f"Near-tangential impact: from the upper wall at tau0=2 the flight reaches the "
            f"lower wall with pre-impact speed ~{GRAZE_TARGET_SPEED:g} (impact 1). Impact times near a graze are "
            "ill-conditioned (dtau ~ gap error / speed), hence the looser tolerances from impact 1 on.",
            FIG2,
            2.0,
            graze_v,
            10,
            tags=("grazing",),
            notes={
                "sdot0_rule": f"bisection on sdot0 in [0.40, 0.41] for a first impact on the lower wall "
                f"with |sdot| >= {GRAZE_TARGET_SPEED:g}, rounded to 12 significant digits"
            },
            level=3,
            catches=("skipped-graze",),
        ),
        Spec(
            "0005-near-miss-return",
            "Near miss: the flight from the upper wall approaches the lower wall "
            "tangentially without touching it and returns to the wall it left (impact 1 on s=0). Tests that no "
            "spurious contact is reported.",
            FIG2,
            2.0,
            miss_v,
            10,
            tags=("grazing", "return-to-start-wall"),
            notes={
                "sdot0_rule": f"{NEAR_MISS_OFFSET:g} below the bisected threshold sdot0 at which the first "
                "impact switches to the lower wall, rounded to 12 significant digits"
            },
            level=3,
            catches=("contact-tolerance", "return-to-start-wall"),
        ),
        Spec(
            "0006-return-to-start-wall",
            "A full flight returning to the wall it left (impact 1 on s=0 after "
            "leaving s=0 with speed 0.36), then regular rattling (Fig. 2 parameters).",
            FIG2,
            2.0,
            0.4,
            20,
            tags=("return-to-start-wall",),
            catches=("return-to-start-wall",),
        ),
    ]


def chatter_specs() -> list[Spec]:
    """Cases 0007-0008: chatter on the upper wall ending in sticking and release, and stuck forever."""
    return [
        Spec(
            "0007-chatter-sticking",
            "Chatter to sticking: alpha=2, beta=0.1, gamma=1, r=0.5. Bounces on the upper "
            "wall accumulate; the tooth sticks (policy: accumulation time <= STICK_TIME) and is released where the "
            "contact force changes sign (closed form); then flies on.",
            Params(2.0, 0.1, 1.0, 0.5),
            0.0,
            0.5,
            40,
            tags=("chatter", "sticking"),
            level=2,
            catches=("release-departure",),
        ),
        Spec(
            "0008-stuck-forever",
            "Chatter ending stuck forever: alpha=0.5, gamma=0.9 > R = alpha sqrt(1+beta^2), "
            "r=0.5; the contact force never changes sign, the orbit ends with status stuck_forever.",
            Params(0.5, 0.1, 0.9, 0.5),
            0.0,
            0.5,
            40,
            tags=("chatter", "sticking", "stuck-forever"),
            level=2,
            catches=("stuck-forever",),
        ),
    ]


def parameter_edge_specs() -> list[Spec]:
    """Cases 0009-0011: very small damping beta (where the printed Eq. (7) cancels) and negative constant
    torque gamma."""
    return [
        Spec(
            "0009-small-beta",
            "Very small damping beta=1e-8 (alpha=1, gamma=0.1, r=0.9): the printed Eq. (7) "
            "cancels like gamma/beta^2; implementations must evaluate the flight without that loss.",
            Params(1.0, 1e-8, 0.1, 0.9),
            0.0,
            0.5,
            20,
            tags=("small-beta",),
            catches=("cancellation",),
        ),
        Spec(
            "0010-negative-gamma",
            "Negative constant torque gamma=-0.2 (alpha=1, beta=0.1, r=0.8), start on the lower wall (sdot0 < 0).",
            Params(1.0, 0.1, -0.2, 0.8),
            0.0,
            -0.5,
            20,
            tags=("negative-gamma",),
            catches=("lower-wall-conventions",),
        ),
        Spec(
            "0011-small-beta-negative-gamma",
            "beta=1e-6 with gamma=-0.05 (alpha=0.8, r=0.95), free-flight start "
            "at rest in the middle of the backlash. The orbit is irregular (errors grow ~10x per 3 impacts), hence "
            "the short horizon.",
            Params(0.8, 1e-6, -0.05, 0.95),
            0.5,
            0.0,
            10,
            s0=-0.5,
            tags=("small-beta", "negative-gamma", "free-flight"),
            catches=("cancellation", "free-flight-start", "float64-drift"),
        ),
    ]


def release_spec() -> Spec:
    """Case 0012: the release orbit of the paper's Figs. 9-11 setting, from a state that sticks at once
    (:func:`mapimpl.float64_release.stick_at_once_state`); its horizon and notes are found by
    :func:`finish_release_case` when the case is built."""
    from ....mapimpl.float64_release import stick_at_once_state

    rel_tau0, rel_sdot0 = stick_at_once_state(FIG11, 0, tau0=RELEASE_TAU0)
    return Spec(
        "0012-release-orbit-fig11",
        "Paper Figs. 9-11 setting (alpha=1.245, beta=gamma=0.1, r=0.9): a pre-impact "
        "state in the Fig. 11 box that sticks at once to the upper wall; the tooth is released at the exact zero "
        "of the contact force (the canonical release phase, a function of the parameters alone) and flies on the "
        "post-release orbit that every sticking initial condition of the mesh shares. Short horizon set by the "
        "Lyapunov exponent of the transient; the notes carry its certified post-release duration T_post.",
        FIG11,
        rel_tau0,
        rel_sdot0,
        0,
        tags=("chaotic", "paper", "sticking", "release"),
        notes={
            "sdot0_rule": f"tau0={RELEASE_TAU0:g} (centre of the Fig. 11 box in tau); sdot0 = half the largest "
            "pre-impact speed that sticks at once there, STICK_TIME (1 - r) f(tau0) / (4 r), "
            "to 3 significant digits (mapimpl/float64_release.py: "
            "stick_at_once_state)"
        },
        finish=finish_release_case,
        level=2,
        catches=("release-departure", "float64-drift"),
    )


# ---------------------------------------------------------------------------------------------
# cases 0013-0025 (issue 21): the bug classes cases 0001-0012 let through


#: Chatter parameters of case 0007 (upper wall) and their mirror gamma -> -gamma (lower wall).
CHATTER_UP, CHATTER_DOWN = Params(2.0, 0.1, 1.0, 0.5), Params(2.0, 0.1, -1.0, 0.5)
#: t_acc / STICK_TIME of the two threshold cases: within 0.5 % below and above the threshold.
STICK_RATIO_BELOW, STICK_RATIO_ABOVE = 0.995, 1.005
#: Release-delay case: the impact lies RELEASE_LEAD before the zero of the contact force, with
#: t_acc = RELEASE_DELAY_TACC (t_acc <= STICK_TIME, but longer than the release delay).
RELEASE_LEAD, RELEASE_DELAY_TACC = 2e-7, 9e-7
#: Graze cases (Fig. 3 parameters): (id suffix, tau0, sdot0 bracket, wall grazed).
GRAZES = (
    ("lower-wall-a", 2.5, (0.2, 0.4), -1),
    ("lower-wall-b", 3.5, (2.0, 2.2), -1),
    ("upper-wall-a", 0.0, (-1.4, -1.6), 0),
    ("upper-wall-b", 0.5, (-2.1, -2.3), 0),
)
#: Near-miss distances of cases 0024 and 0025.
NEAR_MISS_1E9, NEAR_MISS_1E11 = 1e-9, 1e-11


def graze_specs() -> list[Spec]:
    """Cases 0020-0023: four grazes (Fig. 3 parameters) with excursions of GRAZE_EXCURSION beyond the
    wall, at four phases, chosen so that every fixed-step sign-change finder with a step in
    contacts.STEP_RANGE misses at least one of them (checked here on float64 estimates, and by the
    test suite on the certified excursions)."""
    out, exc = [], []
    for k, (name, tau0, (lo, hi), wall) in enumerate(GRAZES):
        sd = contacts.graze_sdot0(FIG3, tau0, lo, hi, wall)
        w, a, b = contacts.float_excursion(FIG3, tau0, sd)
        exc.append((a, b))
        where = "lower wall s=-1 from the upper wall" if wall == -1 else "upper wall s=0 from the lower wall"
        out.append(
            Spec(
                f"{20 + k:04d}-graze-{name}",
                f"Graze: Fig. 3 parameters (alpha=3), the first flight reaches the {where} "
                f"with a normal speed ~{abs(contacts.first_contact(FIG3, tau0, sd)[2]):.1e}; the un-reset flight would "
                f"stay beyond the wall for only ~{contacts.GRAZE_EXCURSION:g} time units. One of four grazes at different "
                "phases that together defeat every fixed-step sign-change finder with a step from 1e-3 to 1.",
                FIG3,
                tau0,
                sd,
                4,
                tags=("grazing",),
                level=3,
                catches=("skipped-graze",),
                extras=("excursion",),
                notes={
                    "sdot0_rule": f"threshold sdot0 at which the first impact switches to wall {wall} (bisection in "
                    f"[{lo}, {hi}]), moved beyond it until the excursion beyond the wall is "
                    f"{contacts.GRAZE_EXCURSION:g} (bisection), 15 significant digits",
                    "purpose": "catches a finder that samples the flight at fixed steps and looks for a sign change "
                    "of the gap: the sample must fall inside the excursion; for every step h in [1e-3, 1] "
                    "at least one of cases 0020-0023 has no sample k h inside its excursion "
                    "(validation/golden/contacts.py, tests/test_golden_mutants.py)",
                },
            )
        )
    if contacts.steps_catching_all(exc):
        raise RuntimeError("the grazes do not defeat every fixed-step finder in the step range")
    return out


def new_specs() -> list[Spec]:
    """Cases 0013-0025, each for a bug class that cases 0001-0012 let through (issue 21):
    :func:`chatter_ending_specs`, :func:`sticking_policy_specs`, :func:`graze_specs`, :func:`near_miss_specs`."""
    return chatter_ending_specs() + sticking_policy_specs() + graze_specs() + near_miss_specs()


def chatter_ending_specs() -> list[Spec]:
    """Cases 0013-0016: how a chatter ends: sticking on the lower wall, stuck forever there, a release flight
    that never lands (ending ``no_impact``), and elastic impacts (r = 1) where nothing accumulates."""
    return [
        Spec(
            "0013-lower-wall-sticking",
            "Chatter to sticking on the lower wall s=-1: case 0007 mirrored (alpha=2, "
            "beta=0.1, gamma=-1, r=0.5), start on the lower wall. The tooth sticks to s=-1 after impact 24, is "
            "released where the contact force -f stops pressing (f rises through zero: phase phi + pi - "
            "asin(gamma/R)), flies on, and chatters again; the case ends with impact 47, whose own sticking "
            "(rows after the last counted impact) is not written.",
            CHATTER_DOWN,
            3.0,
            -0.5,
            47,
            tags=("chatter", "sticking", "lower-wall"),
            level=2,
            catches=("lower-wall-sticking", "trailing-rows", "release-departure"),
            notes={
                "purpose": "catches no sticking on s=-1, the wrong pressing sign on s=-1 (f > 0 instead of "
                "-f > 0), the wall-0 release branch used on s=-1, and stick/release rows written for "
                "the impact after the last counted one (impact 47 sticks)"
            },
        ),
        Spec(
            "0014-lower-wall-stuck-forever",
            "Chatter ending stuck forever on the lower wall: case 0008 mirrored "
            "(alpha=0.5, beta=0.1, gamma=-0.9, r=0.5): gamma <= -R, the force -f presses into s=-1 for ever.",
            Params(0.5, 0.1, -0.9, 0.5),
            0.0,
            -0.5,
            40,
            tags=("chatter", "sticking", "stuck-forever", "lower-wall"),
            level=2,
            catches=("stuck-forever", "lower-wall-sticking"),
            notes={
                "purpose": "catches the never-release test gamma >= R applied on s=-1 (the pressing side there "
                "is gamma <= -R), and missing sticking on s=-1"
            },
        ),
        Spec(
            "0015-no-impact-after-release",
            "An orbit that ends with no_impact: alpha=0.1, beta=0.3, gamma=0, "
            "r=0.6. The tooth chatters on the upper wall, sticks after impact 29 and is released; the release flight "
            "oscillates inside the backlash for ever (gamma=0: no drift; certified for all t > 0). The file ends "
            "with the stick and release rows: no row for the flight that never lands.",
            Params(0.1, 0.3, 0.0, 0.6),
            4.5,
            0.05,
            40,
            tags=("chatter", "sticking", "no-impact"),
            level=3,
            catches=("no-impact-ending",),
            ending="no_impact",
            notes={
                "purpose": "catches an invented row after the last event (an impact at the search horizon "
                "T_MAX, a NaN placeholder) and the stick/release rows of the last step dropped "
                "because its flight never lands"
            },
        ),
        Spec(
            "0016-elastic-r1",
            "Elastic impacts r=1 (Fig. 2 parameters otherwise): nothing accumulates, nothing "
            "sticks, although most impacts happen while the forcing presses into the wall.",
            Params(0.5, 0.1, 0.1, 1.0),
            0.0,
            0.5,
            20,
            tags=("regular", "elastic"),
            catches=("elastic-r1",),
            notes={
                "purpose": "catches t_acc = 2 u / ((1 - r) f_in) evaluated with a 'safe' division that "
                "returns 0 where (1 - r) f_in = 0 (every pressing impact would stick), or any "
                "sticking at r = 1"
            },
        ),
    ]


def sticking_policy_specs() -> list[Spec]:
    """Cases 0017-0019: the sticking policy's conditions at impact 0 (the release delay, and t_acc just below
    and above STICK_TIME), the initial states found by :func:`release_lead_state` and
    :func:`stick_ratio_sdot0`."""
    lead_tau0, lead_v = release_lead_state(CHATTER_UP, 0, RELEASE_LEAD, RELEASE_DELAY_TACC)
    below_v = stick_ratio_sdot0(CHATTER_UP, 4.0, 0, STICK_RATIO_BELOW)
    above_v = stick_ratio_sdot0(CHATTER_DOWN, 1.0, -1, STICK_RATIO_ABOVE)
    return [
        Spec(
            "0017-release-before-accumulation",
            "A chatter impact that must not stick: case 0007's parameters, an "
            f"impact {RELEASE_LEAD:g} before the contact force stops pressing, with t_acc = "
            f"{RELEASE_DELAY_TACC:g} <= STICK_TIME but longer than the release delay: the tooth bounces, the "
            "force turns before it can come back, and it flies to the lower wall.",
            CHATTER_UP,
            lead_tau0,
            lead_v,
            12,
            tags=("chatter", "release-delay"),
            level=2,
            catches=("release-delay",),
            extras=("policy",),
            notes={
                "sdot0_rule": f"tau0 = the float64 nearest to (certified release phase - {RELEASE_LEAD:g}); "
                f"sdot0 = t_acc (1 - r) f(tau0) / (2 r) with t_acc = {RELEASE_DELAY_TACC:g}, "
                "3 significant digits",
                "purpose": "catches a policy that ignores the condition 'release delay > t_acc' (it would "
                "stick at impact 0 and release before the stick row)",
            },
        ),
        Spec(
            "0018-stick-threshold-below",
            f"Sticking with t_acc = {STICK_RATIO_BELOW:g} STICK_TIME (upper wall, "
            "case 0007's parameters): the tooth sticks at impact 0, is released at the zero of the contact force "
            "and flies on.",
            CHATTER_UP,
            4.0,
            below_v,
            10,
            tags=("sticking", "threshold"),
            level=2,
            catches=("sticking-threshold",),
            extras=("policy",),
            notes={
                "sdot0_rule": f"sdot0 = {STICK_RATIO_BELOW:g} STICK_TIME (1 - r) f(tau0) / (2 r), 6 significant digits",
                "purpose": "catches a sticking threshold scaled by 0.99 or less (or t_acc overestimated by "
                "0.5 % or more)",
            },
        ),
        Spec(
            "0019-stick-threshold-above-lower-wall",
            f"No sticking with t_acc = {STICK_RATIO_ABOVE:g} STICK_TIME "
            "on the lower wall (case 0013's parameters): impact 0 bounces, the tooth comes back after ~5e-7 and "
            "sticks at impact 1, is released at the lower wall's release phase and flies on.",
            CHATTER_DOWN,
            1.0,
            above_v,
            10,
            tags=("sticking", "threshold", "lower-wall"),
            level=2,
            catches=("sticking-threshold", "lower-wall-sticking"),
            extras=("policy",),
            notes={
                "sdot0_rule": f"sdot0 = -{STICK_RATIO_ABOVE:g} STICK_TIME (1 - r) (-f(tau0)) / (2 r), 6 "
                "significant digits",
                "purpose": "catches a sticking threshold scaled by 1.01 .. 1.5 (or t_acc underestimated by "
                "0.5 % or more), and sticking missing on s=-1",
            },
        ),
    ]


def near_miss_specs() -> list[Spec]:
    """Cases 0024-0025: near misses at ~NEAR_MISS_1E9 (lower wall) and ~NEAR_MISS_1E11 (upper wall), their
    initial velocities found by bisection (:func:`contacts.near_miss_sdot0`)."""
    miss9 = contacts.near_miss_sdot0(FIG2, 3.0, 0.93, 0.95, -1, NEAR_MISS_1E9)
    miss11 = contacts.near_miss_sdot0(FIG3, 6.0, -0.9, -1.0, 0, NEAR_MISS_1E11)
    return [
        Spec(
            "0024-near-miss-1e-9",
            "Near miss at ~1e-9: Fig. 2 parameters, the flight from the upper wall at "
            "tau0=3 turns back ~1e-9 above the lower wall and returns to the wall it left (impact 1 on s=0).",
            FIG2,
            3.0,
            miss9,
            10,
            tags=("grazing", "return-to-start-wall", "near-miss"),
            level=3,
            catches=("contact-tolerance", "return-to-start-wall"),
            notes={
                "sdot0_rule": f"the threshold sdot0 at which the first impact switches to the lower wall "
                f"(bisection in [0.93, 0.95]), moved to the missing side so that the closest "
                f"approach is ~{NEAR_MISS_1E9:g}, 15 significant digits",
                "purpose": "catches a contact accepted when the gap falls below a tolerance of 1e-9 or more "
                "(e.g. 1e-8)",
            },
        ),
        Spec(
            "0025-near-miss-1e-11-upper-wall",
            "Near miss at ~1e-11 on the upper wall: Fig. 3 parameters, the "
            "flight from the lower wall at tau0=6 turns back ~1e-11 below s=0 and returns to the lower wall.",
            FIG3,
            6.0,
            miss11,
            4,
            tags=("grazing", "return-to-start-wall", "near-miss"),
            level=3,
            catches=("contact-tolerance", "return-to-start-wall"),
            notes={
                "sdot0_rule": f"the threshold sdot0 at which the first impact switches to the upper wall "
                f"(bisection in [-1.0, -0.9]), moved to the missing side so that the closest "
                f"approach is ~{NEAR_MISS_1E11:g}, 15 significant digits",
                "purpose": "catches a contact accepted when the gap falls below a tolerance of 1e-11 or "
                "more (e.g. 1e-10)",
            },
        ),
    ]
