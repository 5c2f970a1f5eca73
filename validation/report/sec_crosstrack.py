"""Report section: agreement of the three tracks (closed-form map vs scipy vs diffrax) and the
one-step Jacobian by three routes, computed for this report."""

from __future__ import annotations

from ..profiles import get_profile
from .document import Section
from .verdict import row

KEY = "crosstrack"
TITLE = "Cross-track agreement: closed form (Eqs. 7-8, 12-13) vs Eq. (3) integrated by scipy and diffrax"

#: Stated tolerances (docs/reference_track.md, "Tolerances (stated)"): one step, tau: 1e-10 + 1e-12/|sdot|
#: (the report applies its sdot-independent part, the stricter 1e-10); Jacobian: 1e-9.
TAU_TOL, JAC_TOL = 1e-10, 1e-9
#: Depth below which an impact counts as near-grazing (left out of the comparison).
GRAZE_DEPTH = 1e-6


def build(ctx) -> Section:
    from ..crosscheck import DOMAIN, jacobian_agreement, one_step_agreement

    sec = Section(KEY, TITLE)
    st = get_profile(ctx.profile, "crosscheck")  # random states compared: one_step, jacobian
    ctx.say(f"one-step agreement on {st['one_step']} random states")
    rows = one_step_agreement(st["one_step"], seed=ctx.seed, graze_depth=GRAZE_DEPTH)
    sec.p(
        "From the same random pre-impact states (domain: "
        + ", ".join(f"{k} in {v}" for k, v in DOMAIN.items())
        + f"; seed {ctx.seed}), the next impact on each numerical track is compared with the closed-form map. "
        f"Impacts within {GRAZE_DEPTH:g} of a tangency are counted but not compared: there the hit-or-miss decision "
        "itself is ill-conditioned (the tests treat them separately)."
    )
    sec.table(
        [
            "track",
            "states compared",
            "near-grazing (left out)",
            "wall/kind mismatches",
            "max |tau - tau_map|",
            "median |tau - tau_map|",
            "max |sdot - sdot_map|",
        ],
        [[r.track, r.compared, r.near_graze, r.mismatched, r.tau_max, r.tau_median, r.sdot_max] for r in rows],
    )
    ctx.say(f"Jacobian by three routes on {st['jacobian']} random states")
    jc = jacobian_agreement(st["jacobian"], seed=ctx.seed + 1)
    sec.table(
        ["route", "max relative difference from the analytic Jacobian", "states"],
        [
            ["variational flow x saltation matrix (scipy)", jc.scipy_max, jc.compared],
            ["jax.jacfwd through the diffrax event solve", jc.diffrax_max, jc.compared],
        ],
    )
    worst = max(r.tau_max for r in rows)
    mism = sum(r.mismatched for r in rows)
    sec.numbers.append(
        row(
            "track_agreement",
            "track agreement: next impact time, map vs scipy vs diffrax",
            worst,
            paper=None,
            tolerance=TAU_TOL,
            check_ok=mism == 0,
            computed_text=f"max |dtau| = {worst:.1e}, {mism} wall/kind mismatches",
            explanation=f"an internal check (independent tracks: closed form vs integration of Eq. 3); "
            f"{sum(r.compared for r in rows)} comparisons, {sum(r.near_graze for r in rows)} near-grazing "
            f"left out; a mismatch of wall or kind fails the check",
            where="Eqs. 3, 7-8, 12-13",
        )
    )
    jmax = max(jc.scipy_max, jc.diffrax_max)
    sec.numbers.append(
        row(
            "jacobian_agreement",
            "map Jacobian: analytic vs variational x saltation vs autodiff",
            jmax,
            paper=None,
            tolerance=JAC_TOL,
            computed_text=f"max rel. diff {jmax:.1e}",
            explanation=f"an internal check of the Jacobian used for the Lyapunov exponents (Section 3), "
            f"{jc.compared} states",
            where="Eqs. 12-13",
        )
    )
    return sec


__all__ = [
    "KEY",
    "TITLE",
    "TAU_TOL",
    "JAC_TOL",
    "GRAZE_DEPTH",
    "build",
]
