"""Report section: Figs. 4-8 -- bifurcation diagrams, Lyapunov exponents, time series, and the
intermittency point r2, the interior crisis r1 and the crisis alpha1 (Section 3 and Fig. 8).

The paper's numbers come from :mod:`..paper`; every number and statement of the text below is
computed in the run by the analyses of :mod:`gear_rattle.validation.dynamics` (the settling of orbits at
the paper's r of Fig. 5, the laminar phases at its r of Fig. 6, the local slopes of the laminar-length
curve, the overflow horizon of the paper's Lyapunov method); the section writes their files
(:mod:`gear_rattle.validation.io.crises`), draws their figures (:mod:`gear_rattle.validation.plots`) and
words the results.
"""

from __future__ import annotations

import numpy as np

from ..dynamics.bifurcation import LN_FLOAT_MAX, diagram_with_lyapunov, raw_product_horizon
from ..dynamics.scans import SCANS, TS_TRANSIENT
from ..profiles import get_profile
from ..dynamics.settling import MIN_LAMINAR, SETTLE_TAIL, SETTLE_TOL, laminar_in_series, local_slopes, settle
from ..io import save_figure
from ..io.crises import write_crises
from ..paper import PAPER
from ..plots import velocity_series_figure
from ..plots.base import params_text
from ..plots.dynamics import crisis_laws_figure, diagram_lyapunov_figure, laminar_law_figure
from .document import Section
from .verdict import row

KEY = "dynamics"
TITLE = "Figs. 4-8: bifurcations, Lyapunov exponents, intermittency (r2) and crises (r1, alpha1)"

#: Stated tolerance of the Lyapunov sum rule lambda1 + lambda2 = mean ln|det J| (tests/test_dynamics_lyapunov.py).
SUM_RULE_TOL = 1e-10


def _span(x: np.ndarray) -> str:
    """``"3"`` or ``"0-3"``: the range of integer counts."""
    lo, hi = int(np.min(x)), int(np.max(x))
    return f"{lo}" if lo == hi else f"{lo}-{hi}"


def _describe(s, what: str) -> str:
    """A :class:`~..dynamics.settling.Settling` in words."""
    k = int(s.settled.sum())
    txt = f"{k} of {s.n_ics} orbits from random initial conditions settled on {what} within {s.n} impacts"
    if k:
        c = s.capture[s.settled]
        ph = s.phases[s.settled]
        txt += (
            f"; their final stay within {s.eps:g} of it began at impact {int(np.median(c))} (median; range "
            f"{int(c.min())}-{int(c.max())}), after {_span(ph)} earlier stays of >= "
            f"{MIN_LAMINAR} impacts that ended in a burst"
        )
    if s.multipliers is not None:
        txt += "; its Floquet multipliers have moduli " + ", ".join(f"{abs(m):.6f}" for m in s.multipliers)
    return txt + " (each capture time is one float64 sample)"


def _bracket_text(b, digits: int) -> str:
    """``seen / clear`` of a crisis bracket (:class:`~..dynamics.crises.stats.Bracket`)."""
    tail = (
        f"none at {b.clear:.{digits}f} in {b.clear_exposure:.3g} impacts (mean time > {b.clear_bound:.3g} "
        f"at {100 * b.level:.0f}%)"
        if np.isfinite(b.clear)
        else "no value without events observed long enough"
    )
    return f"events at {b.seen:.{digits}f}; {tail}"


def _window_text(w: dict | None) -> str:
    """The Lyapunov check at the upper end of the r1 bracket (:func:`~..dynamics.crises.r1.lyapunov_at`)."""
    if w is None:
        return "no upper end, nothing to check"
    verdict = (
        "chaotic on every orbit, not a periodic window"
        if w["chaotic"]
        else "NOT chaotic on every orbit: possibly a periodic window, so this end is not used"
    )
    return (
        f"lambda1 = {w['lam1_min']:.4f} ... {w['lam1_max']:.4f} per impact at r = {w['r']:.10g} "
        f"({w['orbits']} orbits x {w['n']} impacts): {verdict}"
    )


def _method_text(loc) -> str:
    """How the reported crisis point was decided (:class:`~..dynamics.crises.stats.Located`)."""
    lo, hi = loc.interval
    if loc.method == "fit":
        return (
            "the GOY fit, which lies inside the bracket by direct observation and is narrower"
            if np.isfinite(lo)
            else "the GOY fit (no bracket: no run without events was long enough)"
        )
    if loc.why == "bracket narrower than the fit":
        return (
            f"the bracket by direct observation [{lo:.8g}, {hi:.8g}], midpoint and half-width: it is narrower "
            f"than the GOY fit's error, and the fit lies {'inside it' if loc.outside == 0 else 'within its error of it'}"
        )
    return (
        f"the bracket by direct observation [{lo:.8g}, {hi:.8g}], midpoint and half-width: the GOY fit lies "
        f"{loc.outside:.1f} of its errors outside it, so the fitted law does not hold that close to the crisis"
    )


def _period_text(s) -> str:
    cp = s.common_period()
    return f"{cp[0]} impacts per {cp[1]} driving period(s)" if cp else "no settled orbit"


def build(ctx) -> Section:
    from ...mapimpl.continuation import orbit_states
    from ..dynamics.crises import locate_alpha1, locate_r1, locate_r2, six_impact_branch

    sec = Section(KEY, TITLE)
    st = get_profile(ctx.profile, "settling")
    sizes = get_profile(ctx.profile, "diagrams")
    ctx.say("continuing the 6-impact orbit through its fold (r2)")
    branch = six_impact_branch()
    ctx.say("r2: laminar phases")
    r2 = locate_r2(ctx.profile, branch=branch)
    ctx.say("r1: band hops below the interior crisis (engine)")
    r1 = locate_r1(ctx.profile, branch=branch)
    ctx.say("alpha1: escape times from the pre-crisis chaotic set (engine)")
    a1 = locate_alpha1(ctx.profile)
    write_crises(ctx.out_dir / "data" / "dynamics", ctx.profile, r2, r1, a1)
    dl4 = _diagram(ctx, sec, "Fig. 4", sizes, [("r1", r1.value), ("r2", r2.r2)])
    dl8 = _diagram(ctx, sec, "Fig. 8", sizes, [("alpha1", a1.value)])
    l1max = max(dl4.lam1_max, dl8.lam1_max)
    sum_err = float(np.nanmax([dl4.sum_error, dl8.sum_error]))
    sec.p(
        f"Check of every Lyapunov pair of Figs. 4 and 8: max |lambda1 + lambda2 - mean ln|det J|| = "
        f"{sum_err:.2e} (closed-form determinant, docs/model.md). We use QR re-orthonormalisation: the paper's "
        f"method (eigenvalues of the raw product of Jacobians) needs the product itself, whose entries grow like "
        f"exp(n lambda1); with the largest lambda1 of these diagrams ({l1max:.3f} per impact) they pass the "
        f"largest float64 (exp({LN_FLOAT_MAX:.1f})) after about {raw_product_horizon(l1max):.0f} impacts."
    )
    A3, R9 = SCANS["Fig. 4"][3], SCANS["Fig. 8"][3]
    f, ls = r2.fold, r2.laminar
    fold_th, fold_sd = orbit_states(A3.replace(r=f.mu), f.theta, f.sdot, 6)
    # what happens at the paper's r of Fig. 5 (or, if that is above our r2, just below our r2)
    r_settle = float(PAPER["r2"].value) if float(PAPER["r2"].value) < r2.r2 else r2.r2 - 1e-6
    ctx.say(f"r = {r_settle:.8g}: settling on the 6-impact orbit ({st['settle_ics']} orbits)")
    settle6 = settle(A3, "r", r_settle, fold_th, fold_sd, st["settle_ics"], st["settle_n"], ls.eps, ctx.seed)
    # laminar phases at the paper's r of Fig. 6 (same run shape as above: no new compilation)
    r_f6 = float(PAPER["r2_fig6"].value)
    ctx.say(f"r = {r_f6:g}: laminar phases ({st['settle_ics']} orbits)")
    lam6 = settle(A3, "r", r_f6, fold_th, fold_sd, st["settle_ics"], st["settle_n"], ls.eps, ctx.seed + 1)
    # the orbit after the crisis alpha1, at the alpha of Fig. 9
    a_f9 = float(PAPER["alpha1_fig9"].value)
    ctx.say(f"alpha = {a_f9:g}: settling on the 4-impact orbit ({st['settle_ics']} orbits)")
    settle4 = settle(R9, "alpha", a_f9, a1.node.theta, a1.node.sdot, st["settle_ics"], st["settle_n"], ls.eps, ctx.seed)
    _time_series(ctx, sec, get_profile(ctx.profile, "timeseries"), r2, r1, ls.eps)
    _table(sec, branch, r2, r1, a1, a_f9)
    local = _intermittency(ctx, sec, r2)
    _r2_rows(sec, r2, settle6, lam6, r_settle, r_f6, local)
    save_figure(crisis_laws_figure(r1, a1), ctx.fig_dir / "crises_mean_times.png")
    sec.fig(
        ctx.fig_dir / "crises_mean_times.png",
        "Crisis laws (computed): left, mean time between band hops below the interior crisis r1 (alpha = 3); "
        "right, mean escape time from the chaotic set above the boundary crisis alpha1 (r = 0.9, Fig. 8); "
        "95% intervals, GOY fits with the exponent of the mediating saddle orbit. Points at or beyond the "
        "fitted crisis are not drawn on these axes.",
    )
    _crisis_rows(sec, r1, a1, settle4, a_f9)
    sec.numbers.append(
        row(
            "lyapunov_sum_rule",
            "Lyapunov sum rule: lambda1 + lambda2 = mean ln|det J|",
            sum_err,
            paper=None,
            tolerance=SUM_RULE_TOL,
            computed_text=f"max deviation {sum_err:.1e}",
            explanation=f"an internal check over the {dl4.lyapunov.values.size + dl8.lyapunov.values.size} parameter "
            "values of Figs. 4 and 8 (closed-form det J, docs/model.md)",
            where="Figs. 4, 8",
        )
    )
    return sec


def _diagram(ctx, sec: Section, fig: str, st: dict, marks):
    """Fig. 4 or Fig. 8: the diagram and the Lyapunov exponents, computed, drawn and captioned."""
    param, lo, hi, base = SCANS[fig]
    ctx.say(f"{fig} bifurcation diagram and Lyapunov exponents")
    n_values = st["fig4_values" if param == "r" else "fig8_values"]
    dl = diagram_with_lyapunov(base, param, lo, hi, n_values, st["transient"], st["keep"], st["lyap_n"])
    path = ctx.fig_dir / f"{fig.replace('. ', '').lower()}_bifurcation.png"
    save_figure(diagram_lyapunov_figure(dl, fig, marks), path)
    sec.fig(
        path,
        f"{fig}(a) bifurcation diagram of sdot_n and {fig}(b) Lyapunov exponents (QR method, "
        f"{st['lyap_n']} impacts) against {param}; dashed lines: values located below.",
    )
    return dl


def _time_series(ctx, sec: Section, st: dict, r2, r1, eps: float) -> None:
    """Figs. 5-7 at the paper's r, with the laminar phases seen in the displayed series."""
    from ..dynamics.timeseries import FIGURE_R, time_series

    A3 = SCANS["Fig. 4"][3]
    for fig in ("fig5", "fig6", "fig7"):
        P = A3.replace(r=FIGURE_R[fig])
        trans = TS_TRANSIENT[fig]
        ts = time_series(P, n_impacts=st["ts_n"], transient=trans)
        path = ctx.fig_dir / f"{fig}_timeseries.png"
        save_figure(velocity_series_figure(ts, title=f"Fig. {fig[-1]} reproduced (computed): {params_text(P)}"), path)
        if fig in ("fig5", "fig6"):
            frac, n_ph, tail = laminar_in_series(np.asarray(ts.sdot_n), eps)
            what = (
                f"r - r2 = {P.r - r2.r2:+.3g} (our r2); of the {ts.n.size} impacts shown, {100 * frac:.1f}% "
                f"repeat after 6 impacts to {eps:g} (laminar), in {n_ph} laminar phase(s) of >= {MIN_LAMINAR} "
                "impacts; "
                + (
                    f"the series ends inside a laminar stretch that began at impact {tail}"
                    if tail is not None
                    else "the series ends in a burst"
                )
            )
        else:
            what = (
                f"r - r1 = {P.r - r1.value:+.3g} (our r1 = {r1.value:.7f} +- {r1.err:.7f}); the largest r "
                f"with band hops observed in the r1 analysis is {r1.lower_bound:.7f}"
            )
        pv = PAPER["r2" if fig == "fig5" else "r2_fig6" if fig == "fig6" else "r1"]
        sec.fig(
            path,
            f"Fig. {fig[-1]}: discrete sdot_n and stroboscopic sdot(2 pi k) at the paper's r = {P.r:g} "
            f"({pv.where}), from (tau0, sdot0) = (0, 0.5), {trans} impacts discarded; {what}.",
        )


def _table(sec: Section, branch, r2, r1, a1, a_f9: float) -> None:
    f, node = r2.fold, a1.node
    theory = float(PAPER["intermittency_slope"].value)
    sec.table(
        ["quantity", "value"],
        [
            [f"r2: fold (multiplier +1) of the {branch.impacts}-impact period-1 orbit", f"{r2.r2:.12f}"],
            ["fold: Newton residual on the extended system", f"{f.residual:.1e}"],
            ["fold orbit (theta, sdot)", f"({f.theta:.10f}, {f.sdot:.10f})"],
            [
                f"type-I intermittency: slope of mean laminar length vs r - r2 (theory {theory:g})",
                f"{r2.slope:.3f} +- {r2.slope_err:.3f}",
            ],
            ["r1: interior crisis (reported: " + _method_text(r1.located) + ")", f"{r1.value:.7f} +- {r1.err:.7f}"],
            ["r1: GOY fit of the mean time between band hops", f"{r1.goy:.7f} +- {r1.goy_err:.7f}"],
            [
                "r1: fit with the exponent free (exponent)",
                f"{r1.free:.7f} +- {r1.free_err:.7f} (g = {r1.g_free:.2f} +- {r1.g_free_err:.2f})",
            ],
            ["r1: GOY exponent of the mediating saddle 6-impact orbit", f"{r1.goy_exponent:.4f}"],
            ["r1: bracket by direct observation (hops seen at / none at)", _bracket_text(r1.bracket, 7)],
            [
                "r1: largest Lyapunov exponent of band orbits at the bracket's upper end (a window there would not "
                "bound r1)",
                _window_text(r1.clear_lyapunov),
            ],
            ["alpha1: crisis (reported: " + _method_text(a1.located) + ")", f"{a1.value:.6f} +- {a1.err:.6f}"],
            [
                "alpha1: GOY fit of the mean escape time from the chaotic set",
                f"{a1.goy:.6f} +- {a1.goy_err:.6f}",
            ],
            [
                "alpha1: fit with the exponent free (exponent)",
                f"{a1.free:.6f} +- {a1.free_err:.6f} (g = {a1.g_free:.2f} +- {a1.g_free_err:.2f})",
            ],
            ["alpha1: GOY exponent of the saddle 4-impact orbit", f"{a1.goy_exponent:.4f}"],
            ["alpha1: bracket by direct observation (escapes seen at / none at)", _bracket_text(a1.bracket, 6)],
            [
                f"stable {node.period}-impact orbit at alpha = {a_f9:g}: Floquet multipliers",
                ", ".join(f"{complex(m):.5f}" for m in node.multipliers),
            ],
        ],
    )


def _intermittency(ctx, sec: Section, r2) -> list:
    """Type-I intermittency: the laminar-length curve, its fit and its local slopes."""
    theory = float(PAPER["intermittency_slope"].value)
    ls = r2.laminar
    local = local_slopes(np.asarray(r2.dr, float), ls.mean, ls.sem)
    path = ctx.fig_dir / "intermittency_laminar.png"
    save_figure(laminar_law_figure(r2, theory), path)
    sec.fig(
        path,
        f"Type-I intermittency above r2: mean laminar length (runs of >= {MIN_LAMINAR} impacts within "
        f"{ls.eps:g} of the fold orbit, {ls.orbits} orbits of {ls.cap} impacts per r) against r - r2 (computed).",
    )
    sec.table(
        ["r - r2 from", "to", "local slope", "+-", f"z against {theory:g}"],
        [[a, b, s, e, (s - theory) / e if e > 0 else float("nan")] for a, b, s, e in local],
    )
    return local


def _r2_rows(sec: Section, r2, settle6, lam6, r_settle: float, r_f6: float, local: list) -> None:
    from ..dynamics.crises.r2 import certified_r2

    r2v, theory, dr = float(r2.r2), float(PAPER["intermittency_slope"].value), np.asarray(r2.dr, float)
    # r2 proven (Krawczyk on the extended system, the paper's printed parameters): the bounds of Figs. 5
    # and 6 are decided by the enclosure, not by an error bar
    cr2 = certified_r2(r2.fold)
    proof = (
        f"proven: r2 lies in [{cr2.decimal[0]}, {cr2.decimal[1]}] (width {cr2.width:.1e}; Krawczyk operator on "
        "the orbit equations and det(M - I) = 0 with r unknown, for the printed alpha = 3.0, beta = gamma = 0.1 "
        f"as exact decimals; docs/golden.md). Float64 Newton on the same system: r2 = {r2v:.15g} "
        f"({r2v - cr2.mid:+.1e} from the proven value)"
    )
    r2_text = f"+- {max(cr2.hi - cr2.mid, cr2.mid - cr2.lo):.1g} (proven: the float64 enclosure)"
    cp6 = settle6.common_period()
    sec.numbers.append(
        row(
            "r2",
            "r2 (saddle-node of the 6-impact orbit, alpha = 3)",
            cr2.mid,
            None,
            paper="r2",
            computed_text=f"{cr2.mid:.12f}",
            error_text=r2_text,
            enclosure=(cr2.lo, cr2.hi),
            explanation=f"{proof}. At r = {r_settle:.8g} "
            f"(r2 - r = {r2v - r_settle:.3g}) {_describe(settle6, 'a periodic orbit')}"
            + (f"; that orbit has {cp6[0]} impacts per {cp6[1]} driving period(s)" if cp6 else ""),
            where=PAPER["r2"].where,
        )
    )
    m6, e6 = lam6.laminar_mean()
    ex6 = (
        f"at r = {r_f6:g} (r - r2 = {r_f6 - r2v:+.3g}), {lam6.n_ics} orbits of {lam6.n} impacts from random initial "
        f"conditions: {int(lam6.settled.sum())} settled on a periodic orbit; {lam6.laminar_count} complete laminar "
        f"phases (>= {MIN_LAMINAR} impacts within {lam6.eps:g} of the fold orbit, ended by a burst)"
    )
    if lam6.laminar_count > 1:
        ex6 += f" of mean length {m6:.0f} +- {e6:.0f} impacts"
    sec.numbers.append(
        row(
            "r2_fig6",
            "r2 against the r of Fig. 6",
            cr2.mid,
            None,
            paper="r2_fig6",
            computed_text=f"{cr2.mid:.12f}",
            error_text=r2_text,
            enclosure=(cr2.lo, cr2.hi),
            explanation=f"{ex6}; r2 {proof}",
            where=PAPER["r2_fig6"].where,
        )
    )
    sec.numbers.append(
        row(
            "r2_impacts_per_period",
            "impacts per driving period of the stable orbit born at r2",
            settle6.impacts_per_period(),
            paper="r2_impacts_per_period",
            computed_text=_period_text(settle6),
            explanation=f"the orbit the runs at r = {r_settle:.8g} settled on ({int(settle6.settled.sum())} of "
            f"{settle6.n_ics}); period found from the last {SETTLE_TAIL} impacts to {SETTLE_TOL:g}",
            where=PAPER["r2_impacts_per_period"].where,
        )
    )
    small = local[0] if local else None
    sec.numbers.append(
        row(
            "intermittency_slope",
            "type-I intermittency exponent (mean laminar length ~ (r - r2)^k)",
            float(r2.slope),
            float(r2.slope_err),
            paper="intermittency_slope",
            computed_text=f"{r2.slope:.3f}",
            explanation=(
                f"weighted fit over r - r2 in [{dr.min():.2g}, {dr.max():.2g}] ({dr.size} values); local slopes "
                "between successive r - r2: "
                + "; ".join(f"{s:.3f} +- {e:.3f} ({a:.2g}-{b:.2g})" for a, b, s, e in local)
                + (
                    f"; the local slope at the smallest r - r2 is {(small[2] - theory) / small[3]:+.1f} sigma "
                    f"from {theory:g}"
                    if small and small[3] > 0
                    else ""
                )
            ),
            where="Figs. 5-6",
        )
    )


def _crisis_rows(sec: Section, r1, a1, settle4, a_f9: float) -> None:
    hop_rs = ", ".join(f"{x['r']:.7g}" for x in r1.hops)
    sec.numbers.append(
        row(
            "r1",
            "r1 (interior crisis, six bands merge, alpha = 3)",
            float(r1.value),
            float(r1.err),
            paper="r1",
            computed_text=f"{r1.value:.7f}",
            explanation=f"reported: {_method_text(r1.located)}. GOY law T ~ (r1 - r)^(-g) fitted by maximum likelihood to "
            f"the band-hop counts at r = {hop_rs} (g = {r1.goy_exponent:.4f} of the saddle 6-impact orbit): "
            f"{r1.goy:.7f} +- {r1.goy_err:.1e}, error: statistical {r1.stat:.1e} and fit-range "
            f"systematic {r1.syst:.1e}; exponent free: {r1.free:.7f} +- {r1.free_err:.1e}; bracket by "
            f"direct observation {_bracket_text(r1.bracket, 7)}; {_window_text(r1.clear_lyapunov)}; the "
            f"paper's r = {r1.paper_fig7['r']:g} of Fig. 7 lies {r1.paper_fig7['below_r1_by']:.2e} below our r1",
            where=PAPER["r1"].where,
        )
    )
    ics, pa = a1.ics, a1.paper
    ex_a1 = (
        f"reported: {_method_text(a1.located)}. GOY law T ~ (alpha - alpha1)^(-g) fitted by maximum likelihood to "
        f"the escape times from the chaotic set ({ics['n']} orbits per alpha in the scans, "
        f"{ics.get('probe_n', ics['n'])} in the bracket runs, settled on the attractor at alpha = "
        f"{ics['alpha_ref']:g}) at {len(a1.lifetimes)} values of alpha, mean lifetimes up to "
        f"{a1.T_max_measured:.3g} impacts (g = {a1.goy_exponent:.4f} of the saddle 4-impact orbit): "
        f"{a1.goy:.6f} +- {a1.goy_err:.1e}, error: statistical {a1.stat:.1e} and fit-range "
        f"systematic {a1.syst:.1e}; exponent free: {a1.free:.6f} +- {a1.free_err:.1e}; "
        f"bracket by direct observation {_bracket_text(a1.bracket, 6)}. At the paper's alpha1 = {pa['alpha']:g} "
        f"the measured mean lifetime is {pa['T']:.3g} impacts (95%: {pa['lo']:.3g}-{pa['hi']:.3g}): a diagram of "
        f"fewer impacts per parameter value than that sees no escape there. A diagram of "
        f"{a1.diagram['impacts']} impacts (this report's Fig. 8) would show the crisis at alpha = "
        f"{a1.diagram['alpha_apparent']:.5f} (GOY law)"
    )
    sec.numbers.append(
        row(
            "alpha1",
            "alpha1 (crisis of Fig. 8, r = 0.9)",
            float(a1.value),
            float(a1.err),
            paper="alpha1",
            computed_text=f"{a1.value:.6f}",
            explanation=ex_a1,
            where=PAPER["alpha1"].where,
        )
    )
    sec.numbers.append(
        row(
            "alpha1_fig9",
            "alpha1 against the alpha of Figs. 9-11",
            float(a1.value),
            float(a1.err),
            paper="alpha1_fig9",
            computed_text=f"{a1.value:.6f}",
            explanation=ex_a1,
            where=PAPER["alpha1_fig9"].where,
        )
    )
    sec.numbers.append(
        row(
            "alpha1_impacts_per_period",
            "impacts per driving period of the stable orbit after alpha1",
            settle4.impacts_per_period(),
            paper="alpha1_impacts_per_period",
            computed_text=_period_text(settle4),
            explanation=f"at alpha = {a_f9:g}: {_describe(settle4, 'the stable orbit')}",
            where=PAPER["alpha1_impacts_per_period"].where,
        )
    )


__all__ = [
    "KEY",
    "TITLE",
    "SUM_RULE_TOL",
    "build",
]
