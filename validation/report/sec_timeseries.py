"""Report section: Figs. 2-3 (time series, regular vs chaotic motion) and the map's foundations
(Eq. 3 residual, Jacobian identity) computed for this report."""

from __future__ import annotations

import numpy as np

from ...mapimpl import Params
from ...mapimpl.orbit import map_orbit
from ...mapimpl.periodic import find_periodic
from .document import Section
from .verdict import row

KEY = "timeseries"
TITLE = "Figs. 2-3: regular and chaotic rattling (time series)"


#: Periodicity test of Figs. 2-3: the last TAIL impact velocities repeat with a period <= MAX_PERIOD.
TAIL, MAX_PERIOD, PERIOD_ATOL = 120, 12, 1e-9


def _period(sd: np.ndarray, max_p: int = MAX_PERIOD, atol: float = PERIOD_ATOL) -> int | None:
    for p in range(1, max_p + 1):
        if np.allclose(sd[p:], sd[:-p], atol=atol):
            return p
    return None


def build(ctx) -> Section:
    from ...mapimpl.lyapunov import lyapunov
    from ..io import save_figure
    from ..plots import time_series_figure

    sec = Section(KEY, TITLE)
    n = 600 if ctx.quick else 5000
    n_lyap = 20000 if ctx.quick else 200000
    rows = []
    for fig, alpha in (("Fig. 2", 0.5), ("Fig. 3", 3.0)):
        P = Params(alpha, 0.1, 0.1, 0.9)
        seq = map_orbit(P, 0.0, 0.5, n)
        tau, theta, sd, wall = seq.impact_arrays()
        path = ctx.fig_dir / f"fig{fig[-1]}_timeseries.png"
        save_figure(time_series_figure(seq, span=50.0, title=f"{fig}: alpha={P.alpha:g}, beta={P.beta:g}, "
                                                            f"gamma={P.gamma:g}, r={P.r:g} (computed)"), path)
        sec.fig(path, f"{fig} reproduced: (a) driven gear between the driving gear's flanks, (b) relative "
                      f"coordinate s with impacts, alpha = {alpha:g}, from (tau0, sdot0) = (0, 0.5).")
        tail = sd[-TAIL:]
        per = _period(tail, MAX_PERIOD)
        lam = lyapunov(P, "alpha", [alpha], n=n_lyap, transient=1000)
        l1, l2 = (float(x) for x in lam.lam[0])
        per_txt, orbit_txt = f"none up to {MAX_PERIOD}", ""
        if per:
            po = find_periodic(P, theta[-per], sd[-per], per)
            turns = round((tau[-1] - tau[-1 - per]) / (2 * np.pi))
            per_txt = f"{per} impacts per {turns} driving period(s)"
            orbit_txt = (f"Newton residual {po.residual:.1e}; Floquet multipliers "
                         + ", ".join(f"{abs(m):.4f}" for m in po.multipliers) + " (moduli)")
        rows.append([fig, alpha, per_txt, l1, l2, float(lam.det_mean[0]), abs(l1 + l2 - float(lam.det_mean[0])),
                     orbit_txt])
        if per is not None and l1 < 0:
            motion = "regular"
        elif per is None and l1 > 0:
            motion = "chaotic"
        else:
            motion = "undetermined"
        key = f"fig{fig[-1]}_motion"
        sec.numbers.append(row(
            key, f"{fig}: motion at alpha = {alpha:g}", l1, paper=key, category=motion,
            computed_text=f"{motion}: " + (f"periodic, {per_txt}" if per else "aperiodic") + f", lambda1 = {l1:.3g}",
            error_text="", explanation=(
                f"regular = the last {TAIL} impacts repeat with a period <= {MAX_PERIOD} (to {PERIOD_ATOL:g}) and "
                f"lambda1 < 0; chaotic = no such period and lambda1 > 0 (lambda1 over {n_lyap} impacts, value "
                f"shown)"), where=fig))
    sec.table(["figure", "alpha", "period of the impact sequence", "lambda1", "lambda2", "mean ln|det J|",
               "|lambda1+lambda2 - mean ln|det J||", "periodic orbit"], rows)
    sec.p("The sum of the two Lyapunov exponents (QR method) must equal the closed-form mean of ln|det J|, "
          "det J = r^2 exp(-beta dt) sdot_n / sdot_{n+1} (docs/model.md); the last column but one checks it.")
    return sec
