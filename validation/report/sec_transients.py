"""Report section: Figs. 9-11 -- transient basins, uncertainty exponents and the exponential
transient-time law (Section 4), computed for this report with the transient engine.

The section composes the analyses of :mod:`gear_rattle.validation.transient` (compute), writes their
files (:mod:`gear_rattle.validation.io.transients`) and draws their figures
(:mod:`gear_rattle.validation.plots.transients`); it only words the results."""

from __future__ import annotations

from ...core.paper import PAPER_BOX, PAPER_PARAMS
from ..io import save_figure
from ..io.transients import write_basins, write_stick_time_sensitivity, write_survival, write_uncertainty
from ..paper import PAPER
from ..plots.transients import basins_figure, survival_figure, uncertainty_figure
from ..transient import experiments as E
from ..transient.conventions import sticking_conventions
from ...mapimpl.engine.release import certified_dict
from ...mapimpl.engine.t_post import certified_t_post, decimal_params
from ..profiles import get_profile
from .document import Section
from .verdict import row

KEY = "transients"
TITLE = (
    f"Figs. 9-11: transient basins, uncertainty exponents, transient-time statistics (alpha = {PAPER_PARAMS.alpha!r})"
)

#: Uncertainty thresholds n of Fig. 10 and the paper values they are compared with.
PHI_KEYS = {500: "phi_500", 1000: "phi_1000"}
WALL_NAMES = {"0": "upper (s = 0)", "-1": "lower (s = -1)"}


def _ordinal(k: int) -> str:
    """``2nd``, ``3rd``, ``4th``, ``11th``, ``21st``."""
    suf = "th" if 10 <= k % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(k % 10, "th")
    return f"{k}{suf}"


def _cert_text(c: dict) -> str:
    if c["status"] == "captured":
        return str(c["value"])
    if c["status"] == "undecided":
        return f"undecided (> {c['lower_bound']})"
    return f"never captured ({c['status']})"


def build(ctx) -> Section:
    sec = Section(KEY, TITLE)
    data = ctx.out_dir / "data" / "transients"
    prog = ctx.progress
    ctx.say("Fig. 9 basins")
    b = E.basins(profile=ctx.profile, progress=prog)
    write_basins(data, b)
    save_figure(basins_figure(b), data / "fig9_basins.png")
    ctx.say("Fig. 10 uncertainty exponents")
    u = E.uncertainty(profile=ctx.profile, seed=ctx.seed, progress=prog)
    write_uncertainty(data, u)
    save_figure(uncertainty_figure(u), data / "fig10_uncertainty.png")
    ctx.say("Fig. 11 transient-time statistics")
    t = E.transients(profile=ctx.profile, seed=ctx.seed, progress=prog, float64_rounding=True)
    write_survival(data, t)
    save_figure(survival_figure(t), data / "fig11_survival.png")
    for note in u.notes + t.notes:
        ctx.say(note)
    _figs_9_10(sec, data, b, u)
    if t.main_fit is None:
        raise RuntimeError("the Eq. (14) fit failed at the main delta")
    ctx.say("certified T_post of the upper wall (release_T_post)")
    release = _release(ctx, sec, t)
    sec.fig(
        data / "fig11_survival.png",
        f"Fig. 11 reproduced (computed, {t.nx}x{t.ny} mesh, cap {t.cap}, certified T_post): survival N(n) "
        "and the Eq. (14) fit.",
    )
    _fits_per_delta(sec, t)
    conv = sticking_conventions(t, seed=ctx.seed)
    _conventions(sec, conv, release["sample"])
    ctx.say("Fig. 11: sensitivity to the chatter threshold stick_time")
    sens = E.stick_time_sensitivity(t, profile=ctx.profile, seed=ctx.seed, progress=prog)
    write_stick_time_sensitivity(data, sens)
    _sensitivity(sec, sens)
    ctx.say("transient Lyapunov exponent and the float64 horizon")
    _horizon(sec, E.float64_horizon(PAPER_PARAMS, profile=ctx.profile, delta=t.delta), t)
    ctx.say("Fig. 11 with the alternative initial-condition reading (free flight from s = -1)")
    alt = E.transients(
        profile=ctx.profile,
        seed=ctx.seed,
        progress=prog,
        ic_mode="free",
        s0=-1.0,
        nx=get_profile(ctx.profile, "alt_ic")["n"],
        float64_rounding=True,
    )
    write_survival(data / "alt_ic_s0_-1", alt)
    save_figure(survival_figure(alt), data / "alt_ic_s0_-1" / "fig11_survival.png")
    _readings(sec, t, alt)
    _summary_rows(sec, t, conv, release)
    return sec


def _figs_9_10(sec: Section, data, b, u) -> None:
    pp, bx = PAPER_PARAMS, PAPER_BOX
    sec.p(
        f"Setting: alpha = {pp.alpha:g}, r = {pp.r:g}, beta = {pp.beta:g}, gamma = {pp.gamma:g} (the paper's "
        f"alpha of Fig. 9). Initial conditions (tau0, sdot0) are map states just before an impact at s = 0 "
        f"(box {bx[0]:g} < tau0 < {bx[1]:g}, {bx[2]:g} < sdot0 < {bx[3]:g}). The transient "
        "duration is the number of map iterations until the orbit comes within delta of the stable "
        "4-impact period-1 orbit (found by Newton, not typed in). Orbits that chatter and stick are "
        "followed through the sticking policy, not dropped: each is released at its wall's canonical phase with "
        "sdot = 0, so all of them continue on one post-release orbit, whose duration T_post is certified in ball "
        "arithmetic in this run (below). Figs. 9-11 use the certified T_post. Method and the alternative IC reading: "
        "docs/transients.md, docs/release.md."
    )
    fr = b.short_fraction
    sec.fig(
        data / "fig9_basins.png",
        f"Fig. 9 reproduced (computed, {b.nx}x{b.ny} mesh): black = transient shorter than n; short "
        "fractions "
        + ", ".join(f"n={n}: {100 * float(fr[n]):.1f}%" for n in sorted(fr))
        + f". The paper's box of Figs. 10-11 is drawn in red. Orbits that stick at least once: "
        f"{b.engine.n_stuck_orbits}.",
    )
    sec.fig(
        data / "fig10_uncertainty.png",
        f"Fig. 10 reproduced (computed): fraction of eps-uncertain points among {u.n_points} random "
        f"points of the box (seed {u.seed}), eps from {min(u.eps):.0e} to {max(u.eps):.0e}; error bars: "
        f"binomial standard error sqrt(f (1 - f) / {u.n_points}) of each f(eps); lines: least-squares fits.",
    )
    rows = []
    for n, key in PHI_KEYS.items():
        pv = PAPER[key]
        fit = u.fits.get(n)
        if fit is None:
            rows.append([n, "fit failed", "", "", pv.text()])
            sec.numbers.append(
                row(
                    key,
                    f"uncertainty exponent phi, n = {n}",
                    None,
                    paper=key,
                    computed_text="fit failed",
                    explanation="too few uncertain points for a fit",
                    where=pv.where,
                )
            )
            continue
        err = max(fit.phi_se_ls, fit.phi_se_boot)
        rows.append([n, f"{fit.phi:.4f}", f"{fit.phi_se_ls:.4f}", f"{fit.phi_se_boot:.4f}", pv.text()])
        sec.numbers.append(
            row(
                key,
                f"uncertainty exponent phi, n = {n}",
                float(fit.phi),
                float(err),
                paper=key,
                computed_text=f"{fit.phi:.4f}",
                error_text=f"+- {err:.4f}",
                explanation=(
                    f"boundary dimension D = 2 - phi = {2 - fit.phi:.4f} +- {err:.4f}; our error bar is the "
                    f"larger of the least-squares ({fit.phi_se_ls:.4f}) and bootstrap ({fit.phi_se_boot:.4f}) "
                    f"errors over {len(u.eps)} eps values and {u.n_points} points"
                ),
                where=pv.where,
            )
        )
    sec.table(["n", "phi (this run)", "LS error", "bootstrap error", "paper"], rows)


def _release(ctx, sec: Section, t) -> dict:
    """The release orbit: one certified number per wall (a table), and the upper wall's values for the
    summary row (``dec``, ``f64``, the float64 ``sample``)."""
    delta, rel = float(t.delta), t.release_info()[f"{float(t.delta):g}"]
    up = rel.get("0")
    dec = (
        up["certified"] if up else certified_dict(certified_t_post(PAPER_PARAMS, 0, (delta,), confirm=t.confirm)[delta])
    )
    f64 = (
        up["certified_float64_rounding"]
        if up
        else certified_dict(certified_t_post(PAPER_PARAMS, 0, (delta,), rounding="float64", confirm=t.confirm)[delta])
    )
    counts, n_comp, n_ic = t.stick_counts, int(t.composed.sum()), t.nx * t.ny
    sec.p(
        f"Orbits that chatter and stick before coming within delta = {delta:g}: {n_comp} of {n_ic} "
        f"({100 * n_comp / n_ic:.1f}% of the mesh); by the wall of their first sticking episode "
        f"(the engine's stick_wall): upper wall s = 0: {counts['0']}, lower wall s = -1: {counts['-1']}. "
        "Each such orbit's duration is n_s + T_post, n_s the impact at which it first sticks and T_post the "
        "duration of its wall's one post-release orbit, counted from the release."
    )
    trows = []
    for w, e in sorted(rel.items(), key=lambda kv: -int(kv[0])):
        for c in (e["certified"], e["certified_float64_rounding"]):
            trows.append(
                [
                    WALL_NAMES[w],
                    "exact decimals as printed" if c["rounding"] == "decimal" else "their float64 roundings",
                    _cert_text(c),
                    c["precision"] or "",
                    "yes" if c["confirmed"] else "no",
                    f"{c['seconds']:.1f}",
                ]
            )
        trows.append(
            [
                WALL_NAMES[w],
                "float64 engine (a sample)",
                e["float64_sample"] if e["float64_sample"] >= 0 else "> cap",
                "",
                "",
                "",
            ]
        )
    if not rel:
        trows.append(
            [
                WALL_NAMES["0"],
                "exact decimals as printed",
                _cert_text(dec),
                dec["precision"] or "",
                "yes" if dec["confirmed"] else "no",
                f"{dec['seconds']:.1f}",
            ]
        )
    sec.table(
        [
            "wall",
            f"parameters (alpha, beta, gamma, r) = ({', '.join(decimal_params(t.params).values())})",
            f"T_post (delta = {delta:g})",
            "decided at (bits)",
            "confirmed at the next precision",
            "seconds (whole schedule)",
        ],
        trows,
    )
    undecided = [w for w, e in rel.items() if e["source"] != "certified"]
    if undecided:
        sec.p(
            "WARNING: the certification was undecided for wall(s) "
            + ", ".join(undecided)
            + "; the durations of the orbits that stick there use the float64 sample instead."
        )
    sec.p(
        "T_post is certified in ball arithmetic (python-flint arb; mapimpl/certified/): every flight, "
        "impact and sticking decision of the post-release orbit and every distance to the target is proven at the "
        "precision shown"
        + (
            " and the next precision gives the same impact"
            if t.confirm
            else " (the quick profile does not repeat it at a second precision)"
        )
        + ". The main <n>, kappa and decay time below use the certified value for the decimal parameters. The "
        "float64 roundings of the same parameters (a change of ~1e-17) give another value, and the float64 engine's "
        "own post-release orbit yet another: the release orbit is chaotic, so T_post is exact for the stated "
        "parameters but is not a robust feature of the model."
    )
    return {"dec": dec, "f64": f64, "sample": up["float64_sample"] if up else None}


def _fits_per_delta(sec: Section, t) -> None:
    fits, rel = {f"{d:g}": f for d, f in t.fits.items()}, t.release_info()
    sec.table(
        [
            "delta",
            "T_post (upper wall, certified)",
            "<n>",
            "+-",
            "kappa",
            "+- (bootstrap)",
            "decay time <n>/kappa",
            "+- (bootstrap)",
            "censored",
        ],
        [
            [
                d,
                _cert_text(rel[d]["0"]["certified"]) if "0" in rel[d] else "",
                f.mean_n,
                f.mean_n_se,
                f.kappa,
                f.kappa_se_boot,
                f.tau_fit,
                f.tau_fit_se_boot,
                f.n_censored,
            ]
            for d, f in fits.items()
            if f is not None
        ],
    )
    certs = [rel[d]["0"]["certified"] for d in fits if "0" in rel[d]]
    n_conf = sum(bool(c["confirmed"]) for c in certs)
    sec.p(
        "Eq. (14) written with the decay time T of N(n): N(n) = N0 exp(-n/T), so kappa = <n>/T; for a pure "
        "exponential whose mean is <n>, kappa = 1. One schedule of certified runs gives T_post at every delta (one "
        f"orbit decides them all); {n_conf} of the {len(certs)} values are confirmed at the next precision."
    )


def _conventions(sec: Section, conv, sample_up) -> None:
    """How the orbits that stick are counted: this run's durations refitted with other conventions."""
    pn, pk = PAPER["mean_n"], PAPER["kappa"]
    sec.table(
        [
            "orbits that stick (" + f"{100 * conv.sticking_fraction:.1f}% of the mesh) are",
            "orbits",
            "<n>",
            "+-",
            "kappa",
            "+- (bootstrap)",
            "decay time",
        ],
        [
            [r.name, r.orbits, r.fit.mean_n, r.fit.mean_n_se, r.fit.kappa, r.fit.kappa_se_boot, r.fit.tau_fit]
            for r in conv.rows
        ],
    )
    ours, sample, spans, relsp = conv.ours.fit, conv.sample, conv.spans, conv.rel_spans
    effect = ""
    if sample is not None:
        s = sample.fit
        effect = (
            f" Replacing the certified T_post by the float64 engine's sample ({sample_up}) moves <n> by "
            f"{s.mean_n - ours.mean_n:+.0f} ({(s.mean_n - ours.mean_n) / ours.mean_n_se:+.1f} of its "
            f"standard error) and kappa by {s.kappa - ours.kappa:+.3f}: one chaotic float64 orbit "
            f"decides that much of the result."
        )
    sec.p(
        f"Across these conventions the decay time spans {spans['decay time'][0]:.0f}-{spans['decay time'][1]:.0f} "
        f"({100 * relsp['decay time']:.1f}%), <n> spans {spans['<n>'][0]:.0f}-{spans['<n>'][1]:.0f} "
        f"({100 * relsp['<n>']:.1f}%) and kappa {spans['kappa'][0]:.3f}-{spans['kappa'][1]:.3f} "
        f"({100 * relsp['kappa']:.1f}%)."
        + effect
        + f" The paper's <n> = {pn.printed} and kappa = {pk.printed} "
        + (
            "both lie between ours (certified) and 'counted as decayed at once' in this run (the paper does not say "
            "how chattering orbits were treated)."
            if conv.paper_between
            else "do not both lie between ours (certified) and 'counted as decayed at once' in this run."
        )
    )


def _sensitivity(sec: Section, sens) -> None:
    """Sensitivity to the sticking decision (the chatter threshold STICK_TIME)."""
    srows = []
    for r_ in sens.rows:
        f_ = r_.fit
        srows.append(
            [
                f"{r_.stick_time:g}" + (" (this run)" if r_.base else ""),
                f"{100 * r_.sticking_fraction:.2f}%",
                f"{r_.stick_counts['0']} / {r_.stick_counts['-1']}",
                r_.T_post_upper if r_.T_post_upper_status == "captured" else r_.T_post_upper_status,
                f_.mean_n if f_ else "fit failed",
                f_.mean_n_se if f_ else "",
                f_.kappa if f_ else "",
                f_.kappa_se_boot if f_ else "",
            ]
        )
    sub = (
        "the run's mesh"
        if sens.stride == 1
        else f"a coarser sub-mesh ({sens.nx}x{sens.ny}: every {_ordinal(sens.stride)} row and column of the "
        f"run's mesh, to bound the cost)"
    )
    sec.table(
        [
            "stick_time (chatter threshold)",
            "sticking fraction",
            "stick upper / lower",
            "certified T_post (upper)",
            "<n>",
            "+-",
            "kappa",
            "+- (bootstrap)",
        ],
        srows,
    )
    fr = [r_.sticking_fraction for r_ in sens.rows]
    ns_ = [r_.fit.mean_n for r_ in sens.rows if r_.fit]
    ks_ = [r_.fit.kappa for r_ in sens.rows if r_.fit]
    base_fit = next(r_.fit for r_ in sens.rows if r_.base)
    sec.p(
        f"Sensitivity to the sticking decision, on {sub}: chatter whose predicted accumulation time is below "
        "stick_time is replaced by sticking (mapimpl.sticking.STICK_TIME); each value uses its own certified T_post. "
        f"Over stick_time = {', '.join(format(r_.stick_time, 'g') for r_ in sens.rows)} the sticking fraction spans "
        f"{100 * min(fr):.2f}-{100 * max(fr):.2f}%, <n> {min(ns_):.0f}-{max(ns_):.0f} and kappa "
        f"{min(ks_):.4f}-{max(ks_):.4f}"
        + (
            f" (standard errors on this mesh: {base_fit.mean_n_se:.0f} and {base_fit.kappa_se_boot:.3f})."
            if base_fit
            else "."
        )
    )


def _horizon(sec: Section, hz, t) -> None:
    """A float64 transient is a sample, not a value."""
    long_frac = hz.fraction_beyond(t.durations()[0])
    sec.p(
        f"A float64 orbit is a sample, not a value, past ~{hz.horizon_delta:.0f} impacts: the transient's "
        f"largest Lyapunov exponent is lambda1 = {hz.lambda1:.3f} per impact (QR method over "
        f"{hz.impacts_used} transient impacts of {hz.orbits} orbits from a {hz.n_side}x{hz.n_side} grid "
        f"of the box, computed in this run), so a rounding error of u = 2^-53 grows to delta = {hz.delta:g} after "
        f"ln(delta/u)/lambda1 = {hz.horizon_delta:.0f} impacts and to order one after ln(1/u)/lambda1 = "
        f"{hz.horizon_1:.0f}. Every float64 transient longer than that ({100 * long_frac:.1f}% of this run's "
        "durations) is a sample of the transient-length distribution, not the value for its initial condition: "
        "the histogram, <n>, kappa and the decay time are statistics of such samples and are meaningful as "
        "statistics; the duration of one initial condition is not. The post-release orbit shared by all "
        "sticking orbits is the one transient computed as a value (certified above)."
    )


def _readings(sec: Section, t, alt) -> None:
    """The other reading of (tau0, sdot0): a free-flight state just after leaving s = -1 (docs/transients.md)."""
    pn, pk, pt = PAPER["mean_n"], PAPER["kappa"], PAPER["decay_time"]
    main, alt_main = t.main_fit, alt.main_fit
    n_t, n_alt = int(t.composed.sum()), int(alt.composed.sum())
    irows = [["pre-impact state at s = 0 (ours)", main.mean_n, main.kappa, main.tau_fit, n_t]]
    if alt_main is not None:
        irows.append(
            [
                f"free flight leaving s = -1 ({alt.nx}x{alt.ny} mesh)",
                alt_main.mean_n,
                alt_main.kappa,
                alt_main.tau_fit,
                n_alt,
            ]
        )
    irows.append(["paper", pn.value, pk.value, pt.value, ""])
    sec.table(["initial conditions (tau0, sdot0) read as", "<n>", "kappa", "decay time", "orbits that stick"], irows)
    if alt_main is not None:
        closer = abs(main.mean_n - pn.value) < abs(alt_main.mean_n - pn.value)
        dtau = 100.0 * (alt_main.tau_fit - main.tau_fit) / main.tau_fit
        sec.p(
            f"With the free-flight reading {n_alt} orbits stick (pre-impact reading: "
            f"{n_t}), the decay time changes by {dtau:+.1f}% and <n> by "
            f"{alt_main.mean_n - main.mean_n:+.0f}: in this run the "
            + ("pre-impact" if closer else "free-flight")
            + " reading gives the <n> closer to the paper's."
        )


def _summary_rows(sec: Section, t, conv, release: dict) -> None:
    pn, pk, pt = PAPER["mean_n"], PAPER["kappa"], PAPER["decay_time"]
    main, spans, sample = t.main_fit, conv.spans, conv.sample
    sample_up = release["sample"]
    expl = (
        f"orbits that stick ({100 * conv.sticking_fraction:.1f}% of the mesh) use the certified T_post = "
        f"{_cert_text(release['dec'])} of the upper wall"
        + (f"; with the float64 engine's sample ({sample_up}) <n> would be {sample.fit.mean_n:.0f}" if sample else "")
        + f"; <n> over the conventions for orbits that stick: {spans['<n>'][0]:.0f}-{spans['<n>'][1]:.0f}; "
        f"the paper's <n> and kappa {'both lie' if conv.paper_between else 'do not both lie'} between ours and "
        "'counted as decayed at once'"
    )
    sec.numbers.append(
        row(
            "mean_n",
            "mean transient duration <n>",
            float(main.mean_n),
            float(main.mean_n_se),
            paper="mean_n",
            computed_text=f"{main.mean_n:.0f}",
            error_text=f"+- {main.mean_n_se:.0f}",
            explanation=expl,
            where=pn.where,
        )
    )
    ratio = main.kappa_se_boot / main.kappa_se_ls if main.kappa_se_ls > 0 else float("nan")
    sec.numbers.append(
        row(
            "kappa",
            "kappa of N(n) = N0 exp(-kappa n/<n>)",
            float(main.kappa),
            float(main.kappa_se_boot),
            paper="kappa",
            computed_text=f"{main.kappa:.3f}",
            error_text=f"+- {main.kappa_se_boot:.3f} (bootstrap)",
            explanation=f"kappa = <n>/decay time, with the certified T_post; our least-squares error of kappa is "
            f"{main.kappa_se_ls:.2g}, the bootstrap error {main.kappa_se_boot:.2g} (ratio {ratio:.1f}); "
            f"fit over n = {main.n_lo}-{main.n_hi}, {main.n_ic} orbits, {main.n_censored} censored "
            f"at the cap"
            + (f"; with the float64 sample of T_post kappa would be {sample.fit.kappa:.3f}" if sample else ""),
            where=pk.where,
        )
    )
    sec.numbers.append(
        row(
            "decay_time",
            "decay time of N(n), <n>/kappa",
            float(main.tau_fit),
            float(main.tau_fit_se_boot),
            paper="decay_time",
            computed_text=f"{main.tau_fit:.0f}",
            error_text=f"+- {main.tau_fit_se_boot:.0f}",
            explanation=f"the paper's value is {pn.printed}/{pk.printed} = {pt.value:.1f} +- {pt.error:.1f} (its error "
            f"propagates the rounding of {pn.printed} and the stated error of kappa); decay time across the "
            f"conventions for orbits that stick: {spans['decay time'][0]:.0f}-{spans['decay time'][1]:.0f}",
            where=pt.where,
        )
    )
    sec.numbers.append(release_row(release["dec"], release["f64"], sample_up, float(t.delta)))


def release_row(dec: dict, f64: dict, sample, delta: float):
    """The summary row ``release_T_post``: the certified post-release duration of the upper wall's
    canonical release orbit for the decimal parameters (error 0: certified), with the value for their
    float64 roundings and the float64 engine's sample in the text.  Not in the paper: not compared."""
    ok = dec["status"] == "captured"
    val = float(dec["value"]) if ok else None
    f64_text = str(f64["value"]) if f64["status"] == "captured" else f64["status"]
    conf = "confirmed at the next precision" if dec["confirmed"] else "not repeated at a second precision"
    expl = (
        f"certified in ball arithmetic (python-flint arb, mapimpl/certified/): the post-release orbit "
        f"of the upper wall s = 0 (released at the canonical phase {dec['release_phase'][:20]}... with sdot = 0) "
        f"first comes within delta = {delta:g} of the 4-impact orbit at post-release impact "
        + (f"{dec['value']}" if ok else f"? ({dec['status']}, > {dec['lower_bound']} certified)")
        + f" for the exact decimal parameters (alpha, beta, gamma, r) = ({', '.join(dec['params'].values())}); "
        f"decided at {dec['precision']} bits, {conf}. For their float64 roundings T_post = {f64_text} (certified); "
        f"the float64 engine's own post-release orbit gives {sample if sample is not None else 'no value'} "
        "(a sample: float64 loses the orbit after ~60 impacts)"
    )
    return row(
        "release_T_post",
        "post-release duration T_post of the canonical release orbit (upper wall)",
        val,
        0.0 if ok else None,
        paper=None,
        computed_text=str(dec["value"]) if ok else dec["status"],
        error_text="0 (certified)" if ok else "",
        explanation=expl,
        where="Figs. 9-11 (Section 4)",
    )


__all__ = [
    "KEY",
    "TITLE",
    "PHI_KEYS",
    "WALL_NAMES",
    "build",
    "release_row",
]
