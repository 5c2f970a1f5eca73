"""Report section: Figs. 2-3 (time series, regular vs chaotic motion) and the map's foundations
(Eq. 3 residual, Jacobian identity) computed for this report."""

from __future__ import annotations

from ...core.paper import PAPER_FIG2, PAPER_FIG3
from .document import Section
from .verdict import row

KEY = "timeseries"
TITLE = "Figs. 2-3: regular and chaotic rattling (time series)"


def build(ctx) -> Section:
    from ..dynamics.motion import MAX_PERIOD, PERIOD_ATOL, START, TAIL, motion
    from ..io import save_figure
    from ..plots import time_series_figure

    sec = Section(KEY, TITLE)
    rows = []
    for fig, P in (("Fig. 2", PAPER_FIG2), ("Fig. 3", PAPER_FIG3)):
        alpha = P.alpha
        m = motion(P, ctx.profile)
        path = ctx.fig_dir / f"fig{fig[-1]}_timeseries.png"
        save_figure(
            time_series_figure(
                m.seq,
                span=50.0,
                title=f"{fig}: alpha={P.alpha:g}, beta={P.beta:g}, gamma={P.gamma:g}, r={P.r:g} (computed)",
            ),
            path,
        )
        sec.fig(
            path,
            f"{fig} reproduced: (a) driven gear between the driving gear's flanks, (b) relative "
            f"coordinate s with impacts, alpha = {alpha:g}, from (tau0, sdot0) = ({START[0]:g}, {START[1]:g}).",
        )
        per_txt, orbit_txt = f"none up to {MAX_PERIOD}", ""
        if m.period:
            per_txt = f"{m.period} impacts per {m.turns} driving period(s)"
        if m.orbit is not None:  # found where there is a period (dynamics.motion)
            orbit_txt = (
                f"Newton residual {m.orbit.residual:.1e}; Floquet multipliers "
                + ", ".join(f"{abs(z):.4f}" for z in m.orbit.multipliers)
                + " (moduli)"
            )
        rows.append([fig, alpha, per_txt, m.lam1, m.lam2, m.det_mean, m.sum_error, orbit_txt])
        key = f"fig{fig[-1]}_motion"
        sec.numbers.append(
            row(
                key,
                f"{fig}: motion at alpha = {alpha:g}",
                m.lam1,
                paper=key,
                category=m.kind,
                computed_text=f"{m.kind}: "
                + (f"periodic, {per_txt}" if m.period else "aperiodic")
                + f", lambda1 = {m.lam1:.3g}",
                error_text="",
                explanation=(
                    f"regular = the last {TAIL} impacts repeat with a period <= {MAX_PERIOD} (to {PERIOD_ATOL:g}) and "
                    f"lambda1 < 0; chaotic = no such period and lambda1 > 0 (lambda1 over {m.lyap_n} impacts, value "
                    f"shown)"
                ),
                where=fig,
            )
        )
    sec.table(
        [
            "figure",
            "alpha",
            "period of the impact sequence",
            "lambda1",
            "lambda2",
            "mean ln|det J|",
            "|lambda1+lambda2 - mean ln|det J||",
            "periodic orbit",
        ],
        rows,
    )
    sec.p(
        "The sum of the two Lyapunov exponents (QR method) must equal the closed-form mean of ln|det J|, "
        "det J = r^2 exp(-beta dt) sdot_n / sdot_{n+1} (docs/model.md); the last column but one checks it."
    )
    return sec


__all__ = [
    "KEY",
    "TITLE",
    "build",
]
