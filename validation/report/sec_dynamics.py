"""Report section: Figs. 4-8 -- bifurcation diagrams, Lyapunov exponents, time series, and the
intermittency point r2, the interior crisis r1 and the crisis alpha1 (Section 3 and Fig. 8).

The paper's numbers come from :mod:`.paper`; every number and statement of the text below is
computed in the run (the settling of orbits at the paper's r of Fig. 5, the laminar phases at its r
of Fig. 6, the local slopes of the laminar-length curve, the overflow horizon of the paper's
Lyapunov method).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...mapimpl import Params
from ..plots import subplots
from .document import Section
from ..paper import PAPER
from .verdict import row

KEY = "dynamics"
TITLE = "Figs. 4-8: bifurcations, Lyapunov exponents, intermittency (r2) and crises (r1, alpha1)"

SETTINGS = {
    "quick": {"fig4_values": 120, "fig8_values": 120, "transient": 1000, "keep": 150, "lyap_n": 4000,
              "ts_n": 1500, "settle_ics": 8, "settle_n": 20000},
    "paper": {"fig4_values": 600, "fig8_values": 600, "transient": 5000, "keep": 400, "lyap_n": 20000,
              "ts_n": 4000, "settle_ics": 32, "settle_n": 100000},
}

#: Stated tolerance of the Lyapunov sum rule lambda1 + lambda2 = mean ln|det J| (tests/test_dynamics_lyapunov.py).
SUM_RULE_TOL = 1e-10
#: ln of the largest float64: the raw Jacobian product of the paper's method overflows once n lambda1 exceeds it.
LN_FLOAT_MAX = math.log(np.finfo(np.float64).max)
#: A settled orbit: its last SETTLE_TAIL impacts repeat with a period <= SETTLE_MAX_P to SETTLE_TOL.
SETTLE_TAIL, SETTLE_MAX_P, SETTLE_TOL = 240, 12, 1e-9
#: Laminar phases counted in the time series: at least this many impacts (as in crises.laminar_statistics).
MIN_LAMINAR = 12
#: Transient discarded before the time series of Figs. 5-7 (Fig. 5 shows the approach from the start).
TS_TRANSIENT = {"fig5": 0, "fig6": 2000, "fig7": 2000}


def _diagram_with_lyapunov(ctx, sec, fig, param, lo, hi, base, settings, marks):
    from ..dynamics.bifurcation import bifurcation_diagram
    from ...mapimpl.lyapunov import lyapunov

    n_values = settings["fig4_values" if param == "r" else "fig8_values"]
    d = bifurcation_diagram(base, param, lo, hi, n_values=n_values, transient=settings["transient"],
                            keep=settings["keep"], mode="fixed")
    lam = lyapunov(base, param, d.values, n=settings["lyap_n"], transient=settings["transient"])
    path = ctx.fig_dir / f"{fig.replace('. ', '').lower()}_bifurcation.png"
    f, ax = subplots(2, 1, figsize=(8, 6.5), sharex=True)
    vv = np.repeat(d.values, d.sdot.shape[1]) if d.sdot.ndim == 2 else d.values
    ax[0].plot(vv, np.ravel(d.sdot), ",", color="k", alpha=0.6)
    ax[0].set_ylabel(r"$\dot s_n$")
    ax[1].plot(lam.values, lam.lam_free[:, 0], lw=0.8, label=r"$\lambda_1$")
    ax[1].plot(lam.values, lam.lam_free[:, 1], lw=0.8, label=r"$\lambda_2$")
    ax[1].axhline(0, color="0.5", lw=0.5)
    ax[1].set_ylabel("Lyapunov exponents")
    ax[1].set_xlabel(param)
    ax[1].legend(fontsize=8, loc="lower left")
    for name, val in marks:
        for a in ax:
            a.axvline(val, color="C3", lw=0.6, ls="--")
        # inside the axes (x in data, y in axes units), clear of the title above
        ax[0].text(val, 0.97, f" {name}", transform=ax[0].get_xaxis_transform(), color="C3", fontsize=8,
                   ha="left", va="top", bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 1})
    ax[0].set_title(f"{fig} reproduced (computed): {param} in [{lo}, {hi}], {n_values} values, "
                    f"{settings['transient']} impacts discarded")
    f.tight_layout()
    f.savefig(path, dpi=110)
    sec.fig(path, f"{fig}(a) bifurcation diagram of sdot_n and {fig}(b) Lyapunov exponents (QR method, "
                  f"{settings['lyap_n']} impacts) against {param}; dashed lines: values located below.")
    err = np.nanmax(lam.sum_error) if np.any(np.isfinite(lam.sum_error)) else float("nan")
    return d, lam, float(err)


def _span(x: np.ndarray) -> str:
    """``"3"`` or ``"0-3"``: the range of integer counts."""
    lo, hi = int(np.min(x)), int(np.max(x))
    return f"{lo}" if lo == hi else f"{lo}-{hi}"


def _period(theta: np.ndarray, sdot: np.ndarray, max_p: int = SETTLE_MAX_P, tol: float = SETTLE_TOL) -> int | None:
    """Smallest p <= max_p with (theta, sdot) repeating after p impacts to ``tol`` (theta circular)."""
    for p in range(1, max_p + 1):
        if theta.size <= p:
            return None
        dt = np.abs(theta[p:] - theta[:-p])
        dt = np.minimum(dt, 2 * np.pi - dt)
        if max(dt.max(), np.abs(sdot[p:] - sdot[:-p]).max()) <= tol:
            return p
    return None


@dataclass
class Settling:
    """Orbits from ``n_ics`` random initial conditions at one parameter value, ``n`` impacts each:
    ``settled`` (ends periodic and inside the ``eps``-neighbourhood of the reference orbit), ``capture``
    (impact at which its final stay there began; -1 if not settled), ``phases`` (complete laminar
    phases of >= MIN_LAMINAR impacts before that), ``period`` (impacts, driving periods) of the final
    orbit, the Floquet multipliers of the orbit it settled on (the first settled one), and the
    complete stays of all orbits (>= MIN_LAMINAR impacts, begun after and ended by a burst): their
    number ``laminar_count``, the sum ``laminar_total`` and the sum of squares ``laminar_total_sq`` of
    their lengths."""

    value: float
    n_ics: int
    n: int
    eps: float
    settled: np.ndarray
    capture: np.ndarray
    phases: np.ndarray
    period: list
    multipliers: np.ndarray | None
    laminar_count: int
    laminar_total: float
    laminar_total_sq: float

    def laminar_mean(self) -> tuple[float, float]:
        """Mean length of the complete stays and its standard error (NaN below two stays)."""
        k = self.laminar_count
        if k < 2:
            return (self.laminar_total / k if k else float("nan")), float("nan")
        mean = self.laminar_total / k
        var = max(self.laminar_total_sq - k * mean * mean, 0.0) / (k - 1)
        return mean, math.sqrt(var / k)

    def common_period(self) -> tuple[int, int] | None:
        ps = [p for p, s in zip(self.period, self.settled) if s and p is not None]
        return max(set(ps), key=ps.count) if ps else None

    def describe(self, what: str) -> str:
        k = int(self.settled.sum())
        txt = f"{k} of {self.n_ics} orbits from random initial conditions settled on {what} within {self.n} impacts"
        if k:
            c = self.capture[self.settled]
            ph = self.phases[self.settled]
            txt += (f"; their final stay within {self.eps:g} of it began at impact {int(np.median(c))} (median; range "
                    f"{int(c.min())}-{int(c.max())}), after {_span(ph)} earlier stays of >= "
                    f"{MIN_LAMINAR} impacts that ended in a burst")
        if self.multipliers is not None:
            txt += "; its Floquet multipliers have moduli " + ", ".join(f"{abs(m):.6f}" for m in self.multipliers)
        return txt + " (each capture time is one float64 sample)"


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start indices and lengths of the runs of True in a 1-D boolean array."""
    m = np.concatenate([[False], mask, [False]]).astype(np.int8)
    dm = np.diff(m)
    starts = np.nonzero(dm == 1)[0]
    return starts, np.nonzero(dm == -1)[0] - starts


def _settle(base: Params, param: str, value: float, ref_th, ref_sd, n_ics: int, n: int, eps: float,
            seed: int) -> Settling:
    """Run ``n_ics`` orbits (random pre-impact states at s = 0, 0 <= tau0 < 2 pi, 0.05 <= sdot0 <= 0.5) at
    ``param = value`` for ``n`` impacts on the engine and see whether and when each settles near the
    reference orbit (``ref_th, ref_sd``).  Two observers, no history: a
    :class:`~gear_rattle.mapimpl.engine.observers.Laminar` counts the stays within ``eps`` (Euclidean)
    of the reference orbit from impact 1 on and gives the length of the stay in progress at impact
    ``n``; a :class:`~gear_rattle.mapimpl.engine.observers.Sample` keeps the last SETTLE_TAIL states for
    the period test."""
    from ...mapimpl.engine.driver import run
    from ...mapimpl.engine.observers import Laminar, Sample
    from ...mapimpl.orbit import map_orbit
    from ...mapimpl.periodic import find_periodic

    if n < SETTLE_TAIL:
        raise ValueError(f"n={n!r} is out of range: allowed n >= {SETTLE_TAIL} (the tail of the period test)")
    rng = np.random.default_rng(seed)
    t0, s0 = rng.uniform(0.0, 2 * np.pi, n_ics), rng.uniform(0.05, 0.5, n_ics)
    P = base.replace(**{param: value})
    lam = Laminar(np.mod(np.asarray(ref_th, float), 2 * np.pi), np.asarray(ref_sd, float), eps=eps,
                  min_length=MIN_LAMINAR, n_start=1)
    res = run(t0, s0, np.zeros(n_ics, np.int32), P, (lam, Sample(keep=SETTLE_TAIL, n_start=n - SETTLE_TAIL + 1)),
              cap=n, progress=False)
    lo, tail = res.obs
    reached = res.n == n
    run_end = np.where(reached, lo["run"], 0)
    settled, capture, period, mult = [], [], [], None
    for j in range(n_ics):
        th, sd = tail["theta"][j], tail["sdot"][j]
        p = _period(th, sd) if bool(reached[j]) else None
        ok = bool(run_end[j] > 0) and p is not None
        settled.append(ok)
        capture.append(int(n - run_end[j] + 1) if ok else -1)
        if p is None:
            period.append(None)
            continue
        tau = map_orbit(P, float(th[-1]), float(sd[-1]), p).impact_arrays()[0]
        turns = int(round((tau[-1] - tau[0]) / (2 * np.pi)))
        period.append((p, turns))
        if ok and mult is None:
            po = find_periodic(P, float(th[-1]), float(sd[-1]), p, turns)
            mult = po.multipliers if po.converged else None
    return Settling(float(value), n_ics, n, float(eps), np.array(settled), np.array(capture),
                    np.asarray(lo["count"], int), period, mult, int(np.sum(lo["count"])),
                    float(np.sum(lo["total"])), float(np.sum(lo["total_sq"])))


def _laminar_in_series(sd: np.ndarray, eps: float) -> tuple[float, int, int | None]:
    """In a displayed series sdot_n near a 6-impact orbit: the fraction of impacts with
    |sdot_{n+6} - sdot_n| < eps, the number of laminar phases (>= MIN_LAMINAR such impacts in a row)
    and the index at which the final laminar phase began (None if the series ends in a burst)."""
    lam = np.abs(sd[6:] - sd[:-6]) < eps
    starts, lens = _runs(lam)
    n_ph = int((lens >= MIN_LAMINAR).sum())
    ends_laminar = starts.size and starts[-1] + lens[-1] == lam.size and lens[-1] >= MIN_LAMINAR
    tail = int(starts[-1]) if ends_laminar else None
    return float(lam.mean()), n_ph, tail


def _local_slopes(dr, mean, sem) -> list[tuple[float, float, float, float]]:
    """Slopes of log(mean laminar length) between successive r - r2 with their errors (from the standard
    errors of the two means): ``(dr_lo, dr_hi, slope, error)``."""
    out = []
    for i in range(len(dr) - 1):
        dx = math.log(dr[i + 1]) - math.log(dr[i])
        s = (math.log(mean[i + 1]) - math.log(mean[i])) / dx
        e = math.hypot(sem[i] / mean[i], sem[i + 1] / mean[i + 1]) / abs(dx)
        out.append((float(dr[i]), float(dr[i + 1]), s, e))
    return out


def _bracket_text(b: dict, digits: int) -> str:
    """``seen / clear`` of a crisis bracket (:meth:`~..dynamics.crises.stats.Bracket.as_dict`)."""
    clear = b["clear"]
    tail = (f"none at {clear:.{digits}f} in {b['clear_exposure']:.3g} impacts (mean time > {b['clear_bound']:.3g} "
            f"at {100 * b['level']:.0f}%)" if np.isfinite(clear) else "no value without events observed long enough")
    return f"events at {b['seen']:.{digits}f}; {tail}"


def _window_text(w: dict | None) -> str:
    """The Lyapunov check at the upper end of the r1 bracket (:func:`~..dynamics.crises.r1.lyapunov_at`)."""
    if w is None:
        return "no upper end, nothing to check"
    verdict = ("chaotic on every orbit, not a periodic window" if w["chaotic"]
               else "NOT chaotic on every orbit: possibly a periodic window, so this end is not used")
    return (f"lambda1 = {w['lam1_min']:.4f} ... {w['lam1_max']:.4f} per impact at r = {w['r']:.10g} "
            f"({w['orbits']} orbits x {w['n']} impacts): {verdict}")


def _method_text(res: dict) -> str:
    """How the reported crisis point was decided (:func:`~..dynamics.crises.stats.locate`)."""
    loc = res["located"]
    lo, hi = loc["interval"]
    if loc["method"] == "fit":
        return ("the GOY fit, which lies inside the bracket by direct observation and is narrower"
                if np.isfinite(lo) else "the GOY fit (no bracket: no run without events was long enough)")
    if loc.get("why") == "bracket narrower than the fit":
        return (f"the bracket by direct observation [{lo:.8g}, {hi:.8g}], midpoint and half-width: it is narrower "
                f"than the GOY fit's error, and the fit lies {'inside it' if loc['outside'] == 0 else 'within its error of it'}")
    return (f"the bracket by direct observation [{lo:.8g}, {hi:.8g}], midpoint and half-width: the GOY fit lies "
            f"{loc['outside']:.1f} of its errors outside it, so the fitted law does not hold that close to the crisis")


def _crisis_figures(ctx, sec, r1: dict, a1: dict) -> None:
    """Mean time between band hops (r1) and mean escape time (alpha1) with their 95% intervals and the GOY
    fits, against the distance to the fitted crisis."""
    f, ax = subplots(1, 2, figsize=(10, 4))
    for axis, res, key, rows, name in ((ax[0], r1, "r1", r1["hops"], "r"), (ax[1], a1, "alpha1", a1["lifetimes"], "alpha")):
        mu_c = res[key + "_goy"]
        side = -1.0 if key == "r1" else 1.0
        x = np.array([side * (row_[name] - mu_c) for row_ in rows])
        T = np.array([row_["T"] for row_ in rows], float)
        lo = np.array([row_["lo"] for row_ in rows], float)
        hi = np.array([row_["hi"] for row_ in rows], float)
        ok = (x > 0) & np.isfinite(T)
        axis.errorbar(x[ok], T[ok], yerr=[T[ok] - lo[ok], np.where(np.isfinite(hi[ok]), hi[ok] - T[ok], 0)], fmt="o",
                      label="measured (95%)")
        cens = (x > 0) & ~np.isfinite(T)
        if cens.any():
            axis.plot(x[cens], lo[cens], "^", label="no event: lower bound (95%)")
        if ok.any():
            xx = np.geomspace(x[ok].min(), x[ok].max(), 50)
            fit = res["fit_goy"]
            axis.plot(xx, np.exp(fit["log_C"]) * xx ** (-fit["g"]), "-", label=f"GOY fit, g = {fit['g']:.3f}")
        axis.set_xscale("log"); axis.set_yscale("log")
        lab = "r1 - r" if key == "r1" else "alpha - alpha1"
        axis.set_xlabel(lab); axis.set_ylabel("mean time (impacts)")
        axis.set_title(f"GOY fit {key} = {mu_c:.7g} +- {res[key + '_goy_err']:.1g}; reported {res[key]:.7g} "
                       f"+- {res[key + '_err']:.1g}", fontsize=8)
        axis.legend(fontsize=7)
    f.tight_layout()
    path = ctx.fig_dir / "crises_mean_times.png"
    f.savefig(path, dpi=110)
    sec.fig(path, "Crisis laws (computed): left, mean time between band hops below the interior crisis r1 (alpha = 3); "
                  "right, mean escape time from the chaotic set above the boundary crisis alpha1 (r = 0.9, Fig. 8); "
                  "95% intervals, GOY fits with the exponent of the mediating saddle orbit. Points at or beyond the "
                  "fitted crisis are not drawn on these axes.")


def _jsonable(x):
    """``x`` with numpy scalars/arrays as Python numbers/lists and objects that are not data (periodic
    orbits, branches, fits) left out."""
    if isinstance(x, dict):
        pairs = ((str(k), _jsonable(v)) for k, v in x.items())
        return {k: v for k, v in pairs if v is not _SKIP}
    if isinstance(x, (list, tuple)):
        return [v for v in map(_jsonable, x) if v is not _SKIP]
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, (np.integer, np.floating, np.bool_)):
        return x.item()
    if x is None or isinstance(x, (bool, int, float, str)):
        return x
    return _SKIP


_SKIP = object()


def _save_crises(ctx, r2: dict, r1: dict, a1: dict) -> None:
    """The crisis analyses' results -- every scan row, bracket, fit and their cost (impacts, wall and CPU
    seconds per engine run) -- as ``data/dynamics/crises.json`` beside the report."""
    import json

    d = ctx.out_dir / "data" / "dynamics"
    d.mkdir(parents=True, exist_ok=True)
    out = {"profile": ctx.profile, "r2": _jsonable(r2),
           "r1": _jsonable(r1), "alpha1": _jsonable(a1)}
    (d / "crises.json").write_text(json.dumps(out, indent=1, allow_nan=True))


def build(ctx) -> Section:
    from ..dynamics.continuation import orbit_states
    from ..dynamics.crises import locate_alpha1, locate_r1, locate_r2, six_impact_branch
    from ..dynamics.crises.r2 import certified_r2
    from ..dynamics.timeseries import FIGURE_R, time_series
    from ..io import save_figure
    from ..plots import velocity_series_figure

    sec = Section(KEY, TITLE)
    st = SETTINGS[ctx.profile]
    A3 = Params(3.0, 0.1, 0.1, 0.9)
    R9 = Params(1.2, 0.1, 0.1, 0.9)

    ctx.say("continuing the 6-impact orbit through its fold (r2)")
    branch = six_impact_branch()
    ctx.say("r2: laminar phases")
    r2 = locate_r2(ctx.profile, branch=branch)
    ctx.say("r1: band hops below the interior crisis (engine)")
    r1 = locate_r1(ctx.profile, branch=branch)
    ctx.say("alpha1: escape times from the pre-crisis chaotic set (engine)")
    a1 = locate_alpha1(ctx.profile)

    _save_crises(ctx, r2, r1, a1)

    ctx.say("Fig. 4 bifurcation diagram and Lyapunov exponents")
    _, lam4, err4 = _diagram_with_lyapunov(ctx, sec, "Fig. 4", "r", 0.70, 0.95, A3, st,
                                           [("r1", r1["r1"]), ("r2", r2["r2"])])
    ctx.say("Fig. 8 bifurcation diagram and Lyapunov exponents")
    _, lam8, err8 = _diagram_with_lyapunov(ctx, sec, "Fig. 8", "alpha", 1.10, 1.40, R9, st,
                                           [("alpha1", a1["alpha1"])])
    l1max = float(np.nanmax(np.concatenate([lam4.lam_free[:, 0], lam8.lam_free[:, 0]])))
    sum_err = float(np.nanmax([err4, err8]))
    sec.p(f"Check of every Lyapunov pair of Figs. 4 and 8: max |lambda1 + lambda2 - mean ln|det J|| = "
          f"{sum_err:.2e} (closed-form determinant, docs/model.md). We use QR re-orthonormalisation: the paper's "
          f"method (eigenvalues of the raw product of Jacobians) needs the product itself, whose entries grow like "
          f"exp(n lambda1); with the largest lambda1 of these diagrams ({l1max:.3f} per impact) they pass the "
          f"largest float64 (exp({LN_FLOAT_MAX:.1f})) after about {LN_FLOAT_MAX / l1max:.0f} impacts.")

    f = r2["fold"]
    r2v = float(r2["r2"])
    theory = float(PAPER["intermittency_slope"].value)
    ls = r2["laminar"]
    fold_th, fold_sd = orbit_states(A3.replace(r=f.mu), f.tau, f.sdot, 6)

    # what happens at the paper's r of Fig. 5 (or, if that is above our r2, just below our r2)
    p_r2 = PAPER["r2"]
    r_settle = float(p_r2.value) if float(p_r2.value) < r2v else r2v - 1e-6
    ctx.say(f"r = {r_settle:.8g}: settling on the 6-impact orbit ({st['settle_ics']} orbits)")
    settle6 = _settle(A3, "r", r_settle, fold_th, fold_sd, st["settle_ics"], st["settle_n"], ls.eps, ctx.seed)
    # laminar phases at the paper's r of Fig. 6 (same run shape as above: no new compilation)
    r_f6 = float(PAPER["r2_fig6"].value)
    ctx.say(f"r = {r_f6:g}: laminar phases ({st['settle_ics']} orbits)")
    lam6 = _settle(A3, "r", r_f6, fold_th, fold_sd, st["settle_ics"], st["settle_n"], ls.eps, ctx.seed + 1)
    # the orbit after the crisis alpha1, at the alpha of Fig. 9
    a_f9 = float(PAPER["alpha1_fig9"].value)
    ctx.say(f"alpha = {a_f9:g}: settling on the 4-impact orbit ({st['settle_ics']} orbits)")
    node = a1["node"]
    settle4 = _settle(R9, "alpha", a_f9, node.tau, node.sdot, st["settle_ics"], st["settle_n"], ls.eps, ctx.seed)

    for fig in ("fig5", "fig6", "fig7"):
        P = A3.replace(r=FIGURE_R[fig])
        trans = TS_TRANSIENT[fig]
        ts = time_series(P, n_impacts=st["ts_n"], transient=trans)
        path = ctx.fig_dir / f"{fig}_timeseries.png"
        save_figure(velocity_series_figure(ts, title=f"Fig. {fig[-1]} reproduced (computed): alpha = 3, r = {P.r:g}"),
                    path, dpi=150)
        if fig in ("fig5", "fig6"):
            frac, n_ph, tail = _laminar_in_series(np.asarray(ts.sdot_n), ls.eps)
            what = (f"r - r2 = {P.r - r2v:+.3g} (our r2); of the {ts.n.size} impacts shown, {100 * frac:.1f}% "
                    f"repeat after 6 impacts to {ls.eps:g} (laminar), in {n_ph} laminar phase(s) of >= {MIN_LAMINAR} "
                    "impacts; " + (f"the series ends inside a laminar stretch that began at impact {tail}"
                                   if tail is not None else "the series ends in a burst"))
        else:
            what = (f"r - r1 = {P.r - r1['r1']:+.3g} (our r1 = {r1['r1']:.7f} +- {r1['r1_err']:.7f}); the largest r "
                    f"with band hops observed in the r1 analysis is {r1['lower_bound']:.7f}")
        pv = PAPER["r2" if fig == "fig5" else "r2_fig6" if fig == "fig6" else "r1"]
        sec.fig(path, f"Fig. {fig[-1]}: discrete sdot_n and stroboscopic sdot(2 pi k) at the paper's r = {P.r:g} "
                      f"({pv.where}), from (tau0, sdot0) = (0, 0.5), {trans} impacts discarded; {what}.")

    sec.table(["quantity", "value"], [
        [f"r2: fold (multiplier +1) of the {branch.impacts}-impact period-1 orbit", f"{r2v:.12f}"],
        ["fold: Newton residual on the extended system", f"{f.residual:.1e}"],
        ["fold orbit (tau, sdot)", f"({f.tau:.10f}, {f.sdot:.10f})"],
        [f"type-I intermittency: slope of mean laminar length vs r - r2 (theory {theory:g})",
         f"{r2['slope']:.3f} +- {r2['slope_err']:.3f}"],
        ["r1: interior crisis (reported: " + _method_text(r1) + ")", f"{r1['r1']:.7f} +- {r1['r1_err']:.7f}"],
        ["r1: GOY fit of the mean time between band hops", f"{r1['r1_goy']:.7f} +- {r1['r1_goy_err']:.7f}"],
        ["r1: fit with the exponent free (exponent)", f"{r1['r1_free']:.7f} +- {r1['r1_free_err']:.7f} "
                                                       f"(g = {r1['g_free']:.2f} +- {r1['g_free_err']:.2f})"],
        ["r1: GOY exponent of the mediating saddle 6-impact orbit", f"{r1['goy_exponent']:.4f}"],
        ["r1: bracket by direct observation (hops seen at / none at)", _bracket_text(r1["bracket"], 7)],
        ["r1: largest Lyapunov exponent of band orbits at the bracket's upper end (a window there would not "
         "bound r1)", _window_text(r1.get("clear_lyapunov"))],
        ["alpha1: crisis (reported: " + _method_text(a1) + ")", f"{a1['alpha1']:.6f} +- {a1['alpha1_err']:.6f}"],
        ["alpha1: GOY fit of the mean escape time from the chaotic set",
         f"{a1['alpha1_goy']:.6f} +- {a1['alpha1_goy_err']:.6f}"],
        ["alpha1: fit with the exponent free (exponent)", f"{a1['alpha1_free']:.6f} +- {a1['alpha1_free_err']:.6f} "
                                                           f"(g = {a1['g_free']:.2f} +- {a1['g_free_err']:.2f})"],
        ["alpha1: GOY exponent of the saddle 4-impact orbit", f"{a1['goy_exponent']:.4f}"],
        ["alpha1: bracket by direct observation (escapes seen at / none at)", _bracket_text(a1["bracket"], 6)],
        [f"stable {node.impacts}-impact orbit at alpha = {a_f9:g}: Floquet multipliers",
         ", ".join(f"{complex(m):.5f}" for m in node.multipliers)],
    ])

    # type-I intermittency: the laminar-length curve, its fit and its local slopes
    dr = np.asarray(r2["dr"], float)
    local = _local_slopes(dr, ls.mean, ls.sem)
    path = ctx.fig_dir / "intermittency_laminar.png"
    fg, ax = subplots(figsize=(5.5, 4))
    ax.errorbar(dr, ls.mean, yerr=ls.sem, fmt="o")
    xx = np.array([dr.min(), dr.max()])
    k = np.exp(np.mean(np.log(ls.mean) - r2["slope"] * np.log(dr)))
    ax.plot(xx, k * xx ** r2["slope"], "-", label=f"fit: slope {r2['slope']:.3f} +- {r2['slope_err']:.3f}")
    ax.plot(xx, ls.mean[0] * (xx / dr[0]) ** theory, ":", label=f"slope {theory:g} (theory) through the first point")
    ax.set_xscale("log"); ax.set_yscale("log")
    ax.set_xlabel("r - r2"); ax.set_ylabel("mean laminar length (impacts)")
    ax.legend(fontsize=8); fg.tight_layout(); fg.savefig(path, dpi=110)
    sec.fig(path, f"Type-I intermittency above r2: mean laminar length (runs of >= {MIN_LAMINAR} impacts within "
                  f"{ls.eps:g} of the fold orbit, {ls.orbits} orbits of {ls.cap} impacts per r) against r - r2 (computed).")
    sec.table(["r - r2 from", "to", "local slope", "+-", f"z against {theory:g}"],
              [[a, b, s, e, (s - theory) / e if e > 0 else float("nan")] for a, b, s, e in local])

    # ---- summary rows
    # r2 proven (Krawczyk on the extended system, the paper's printed parameters): the bounds of Figs. 5
    # and 6 are decided by the enclosure, not by an error bar
    cr2 = certified_r2(f)
    proof = (f"proven: r2 lies in [{cr2.decimal[0]}, {cr2.decimal[1]}] (width {cr2.width:.1e}; Krawczyk operator on "
             "the orbit equations and det(M - I) = 0 with r unknown, for the printed alpha = 3.0, beta = gamma = 0.1 "
             f"as exact decimals; docs/golden.md). Float64 Newton on the same system: r2 = {r2v:.15g} "
             f"({r2v - cr2.mid:+.1e} from the proven value)")
    r2_text = f"+- {max(cr2.hi - cr2.mid, cr2.mid - cr2.lo):.1g} (proven: the float64 enclosure)"
    sec.numbers.append(row(
        "r2", "r2 (saddle-node of the 6-impact orbit, alpha = 3)", cr2.mid, None, paper="r2",
        computed_text=f"{cr2.mid:.12f}", error_text=r2_text, enclosure=(cr2.lo, cr2.hi),
        explanation=f"{proof}. At r = {r_settle:.8g} "
                    f"(r2 - r = {r2v - r_settle:.3g}) {settle6.describe('a periodic orbit')}"
                    + (f"; that orbit has {settle6.common_period()[0]} impacts per {settle6.common_period()[1]} "
                       "driving period(s)" if settle6.common_period() else ""),
        where=p_r2.where))
    m6, e6 = lam6.laminar_mean()
    ex6 = (f"at r = {r_f6:g} (r - r2 = {r_f6 - r2v:+.3g}), {lam6.n_ics} orbits of {lam6.n} impacts from random initial "
           f"conditions: {int(lam6.settled.sum())} settled on a periodic orbit; {lam6.laminar_count} complete laminar "
           f"phases (>= {MIN_LAMINAR} impacts within {lam6.eps:g} of the fold orbit, ended by a burst)")
    if lam6.laminar_count > 1:
        ex6 += f" of mean length {m6:.0f} +- {e6:.0f} impacts"
    sec.numbers.append(row("r2_fig6", "r2 against the r of Fig. 6", cr2.mid, None, paper="r2_fig6",
                           computed_text=f"{cr2.mid:.12f}", error_text=r2_text, enclosure=(cr2.lo, cr2.hi),
                           explanation=f"{ex6}; r2 {proof}", where=PAPER["r2_fig6"].where))
    cp6 = settle6.common_period()
    sec.numbers.append(row(
        "r2_impacts_per_period", "impacts per driving period of the stable orbit born at r2",
        (cp6[0] // cp6[1] if cp6[0] % cp6[1] == 0 else cp6[0] / cp6[1]) if cp6 else None, paper="r2_impacts_per_period",
        computed_text=(f"{cp6[0]} impacts per {cp6[1]} driving period(s)" if cp6 else "no settled orbit"),
        explanation=f"the orbit the runs at r = {r_settle:.8g} settled on ({int(settle6.settled.sum())} of "
                    f"{settle6.n_ics}); period found from the last {SETTLE_TAIL} impacts to {SETTLE_TOL:g}",
        where=PAPER["r2_impacts_per_period"].where))

    small = local[0] if local else None
    sec.numbers.append(row(
        "intermittency_slope", "type-I intermittency exponent (mean laminar length ~ (r - r2)^k)",
        float(r2["slope"]), float(r2["slope_err"]), paper="intermittency_slope",
        computed_text=f"{r2['slope']:.3f}",
        explanation=(f"weighted fit over r - r2 in [{dr.min():.2g}, {dr.max():.2g}] ({dr.size} values); local slopes "
                     "between successive r - r2: " + "; ".join(f"{s:.3f} +- {e:.3f} ({a:.2g}-{b:.2g})"
                                                             for a, b, s, e in local)
                     + (f"; the local slope at the smallest r - r2 is {(small[2] - theory) / small[3]:+.1f} sigma "
                        f"from {theory:g}" if small and small[3] > 0 else "")),
        where="Figs. 5-6"))

    _crisis_figures(ctx, sec, r1, a1)
    hop_rs = ", ".join(f"{x['r']:.7g}" for x in r1["hops"])
    sec.numbers.append(row(
        "r1", "r1 (interior crisis, six bands merge, alpha = 3)", float(r1["r1"]), float(r1["r1_err"]), paper="r1",
        computed_text=f"{r1['r1']:.7f}",
        explanation=f"reported: {_method_text(r1)}. GOY law T ~ (r1 - r)^(-g) fitted by maximum likelihood to the band-hop counts at r = {hop_rs} "
                    f"(g = {r1['goy_exponent']:.4f} of the saddle 6-impact orbit): {r1['r1_goy']:.7f} +- "
                    f"{r1['r1_goy_err']:.1e}, error: statistical "
                    f"{r1['r1_stat']:.1e} and fit-range systematic {r1['r1_syst']:.1e}; exponent free: "
                    f"{r1['r1_free']:.7f} +- {r1['r1_free_err']:.1e}; bracket by direct observation "
                    f"{_bracket_text(r1['bracket'], 7)}; {_window_text(r1.get('clear_lyapunov'))}; the paper's r = {r1['paper_fig7']['r']:g} of Fig. 7 lies "
                    f"{r1['paper_fig7']['below_r1_by']:.2e} below our r1",
        where=PAPER["r1"].where))
    ex_a1 = (f"reported: {_method_text(a1)}. GOY law T ~ (alpha - alpha1)^(-g) fitted by maximum likelihood to the escape times from the chaotic set "
             f"({a1['ics']['n']} orbits per alpha in the scans, {a1['ics'].get('probe_n', a1['ics']['n'])} in the bracket "
             f"runs, settled on the attractor at alpha = {a1['ics']['alpha_ref']:g}) at "
             f"{len(a1['lifetimes'])} values of alpha, mean lifetimes up to {a1['T_max_measured']:.3g} impacts "
             f"(g = {a1['goy_exponent']:.4f} of the saddle 4-impact orbit): {a1['alpha1_goy']:.6f} +- "
             f"{a1['alpha1_goy_err']:.1e}, error: statistical "
             f"{a1['alpha1_stat']:.1e} and fit-range systematic {a1['alpha1_syst']:.1e}; exponent free: "
             f"{a1['alpha1_free']:.6f} +- {a1['alpha1_free_err']:.1e}; bracket by direct observation "
             f"{_bracket_text(a1['bracket'], 6)}. At the paper's alpha1 = {a1['paper']['alpha']:g} the measured mean "
             f"lifetime is {a1['paper']['T']:.3g} impacts (95%: {a1['paper']['lo']:.3g}-{a1['paper']['hi']:.3g}): a "
             f"diagram of fewer impacts per parameter value than that sees no escape there. A diagram of "
             f"{a1['diagram']['impacts']} impacts (this report's Fig. 8) would show the crisis at alpha = "
             f"{a1['diagram']['alpha_apparent']:.5f} (GOY law)")
    sec.numbers.append(row("alpha1", "alpha1 (crisis of Fig. 8, r = 0.9)", float(a1["alpha1"]),
                           float(a1["alpha1_err"]), paper="alpha1", computed_text=f"{a1['alpha1']:.6f}",
                           explanation=ex_a1, where=PAPER["alpha1"].where))
    sec.numbers.append(row("alpha1_fig9", "alpha1 against the alpha of Figs. 9-11", float(a1["alpha1"]),
                           float(a1["alpha1_err"]), paper="alpha1_fig9", computed_text=f"{a1['alpha1']:.6f}",
                           explanation=ex_a1, where=PAPER["alpha1_fig9"].where))
    cp4 = settle4.common_period()
    sec.numbers.append(row(
        "alpha1_impacts_per_period", "impacts per driving period of the stable orbit after alpha1",
        (cp4[0] // cp4[1] if cp4[0] % cp4[1] == 0 else cp4[0] / cp4[1]) if cp4 else None,
        paper="alpha1_impacts_per_period",
        computed_text=(f"{cp4[0]} impacts per {cp4[1]} driving period(s)" if cp4 else "no settled orbit"),
        explanation=f"at alpha = {a_f9:g}: {settle4.describe('the stable orbit')}",
        where=PAPER["alpha1_impacts_per_period"].where))
    sec.numbers.append(row(
        "lyapunov_sum_rule", "Lyapunov sum rule: lambda1 + lambda2 = mean ln|det J|", sum_err, paper=None,
        tolerance=SUM_RULE_TOL, computed_text=f"max deviation {sum_err:.1e}",
        explanation=f"an internal check over the {lam4.values.size + lam8.values.size} parameter values of "
                    "Figs. 4 and 8 (closed-form det J, docs/model.md)", where="Figs. 4, 8"))
    return sec
