"""The three experiments of Section 4, importable (the report generator calls them) and used by the
CLI commands ``gear-rattle basins | uncertainty | transients``.

Each function computes, writes ``<outdir>/<name>.npz`` (+ ``.csv`` / ``.json`` summary) and a PNG,
and returns a dict of results.  ``profile="quick"`` is small (well under a minute on 2 cores);
``profile="paper"`` is the paper's scale.
"""

from __future__ import annotations

import functools
import json
import math
from pathlib import Path

import numpy as np

from matplotlib.patches import Rectangle

from ...core.params import Params
from ..figures import subplots
from . import analysis as A
from ...mapimpl.engine.transients import grid, transient_times
from ...core.paper import DELTA, DELTAS, PAPER_BOX, PAPER_PARAMS
from ...mapimpl.sticking import STICK_TIME
from ..paper import PAPER

PROFILES = ("quick", "paper")
BASIN_NS = (90, 500, 1000, 2000)
#: Fig. 9 window: the whole phase circle, 0 < sdot0 < 0.5 (contains the paper's box).
BASIN_WINDOW = (0.0, 2.0 * math.pi, 0.0, 0.5)


def _outdir(outdir) -> Path:
    p = Path(outdir)
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise ValueError(f"outdir={str(outdir)!r} cannot be created: {e.strerror}") from None
    return p


def _profile(profile, quick, paper):
    if profile not in PROFILES:
        raise ValueError(f"profile={profile!r} is out of range: allowed one of {', '.join(PROFILES)}")
    return quick if profile == "quick" else paper


# ------------------------------------------------------------- the release orbit (issue 10 item 3)
#
# Every orbit that sticks to a wall is released at that wall's canonical phase with sdot = 0
# (mapimpl.sticking.release_phase), so all of them continue on ONE post-release orbit, and an
# initial condition that first sticks at its impact n_s has duration n_s + T_post.  The float64
# engine's T_post is a sample (the orbit is chaotic and float64 loses it after ~60 impacts); the
# value used here is certified in ball arithmetic (mapimpl/certified/, docs/release.md).

#: Where the durations of the orbits that stick come from: ``certified`` (T_post in ball arithmetic
#: for the decimal parameters as printed) or ``float64`` (the engine's own post-release orbit, a sample).
RELEASE_SOURCES = ("certified", "float64")


def decimal_params(params: Params) -> dict:
    """The parameters as printed: the shortest decimal of each float64 (``repr``), e.g. ``"1.245"``;
    the certified ``T_post`` is computed for these exact decimals."""
    return {k: repr(float(getattr(params, k))) for k in ("alpha", "beta", "gamma", "r")}


@functools.lru_cache(maxsize=128)
def _certified(pdec: tuple, wall: int, deltas: tuple, rounding: str, stick_time: float, confirm: bool) -> dict:
    from ...mapimpl.certified import certified_release_durations

    rs = certified_release_durations(dict(pdec), wall, deltas, rounding=rounding, confirm=confirm,
                                     stick_time=stick_time)
    out = {}
    for d, r in rs.items():
        dd = r.to_dict()
        out[d] = {k: dd[k] for k in ("params", "rounding", "wall", "delta", "status", "value", "precision",
                                     "confirmed", "lower_bound", "release_phase", "seconds")}
    return out


def certified_t_post(params: Params, wall: int, delta: float = DELTA, *, deltas=None, rounding: str = "decimal",
                     stick_time: float = STICK_TIME, confirm: bool = True) -> dict:
    """The certified post-release duration of ``wall``'s canonical release orbit at capture distance
    ``delta`` (:func:`mapimpl.certified.certified_release_durations` for :func:`decimal_params`),
    as a dict (``value``, ``status``, ``precision``, ``confirmed``, ``lower_bound``, ``seconds``, ...).

    ``deltas``: all the capture distances the caller will ask for (containing ``delta``): one schedule
    of certified runs decides them all (one orbit serves every distance; ``seconds`` is that schedule's
    time).  Cached per process: the report asks for the same orbit in several experiments."""
    ds = tuple(sorted({float(d) for d in (deltas if deltas is not None else ())} | {float(delta)}, reverse=True))
    out = _certified(tuple(sorted(decimal_params(params).items())), int(wall), ds, rounding, float(stick_time),
                     bool(confirm))
    return dict(out[float(delta)])


def _t_post_value(c: dict):
    """``(T_post for TransientResult.duration, usable)``: the certified value, ``None`` for a certified
    'never captured' outcome, or ``(None, False)`` when the certification was undecided."""
    if c["status"] == "captured":
        return int(c["value"]), True
    if c["status"] in ("periodic", "stuck_forever", "no_capture"):
        return None, True
    return None, False


def release_durations(res, delta: float, *, source: str = "certified", confirm: bool = True,
                      stick_time: float = STICK_TIME):
    """``(durations, censored, info)`` of a :class:`TransientResult` at ``delta``, the orbits that stick
    composed with the ``source`` post-release duration of their wall (``first_stick + T_post``).

    ``info``: per wall stuck to (``"0"``, ``"-1"``): ``certified`` (the certification dict),
    ``float64_sample`` (the engine's T_post, -1 beyond the cap), ``used`` (the T_post used; ``None``:
    never captured), ``source`` (``certified``, or ``float64 sample`` when the certification was
    undecided: then the text must say so)."""
    if source not in RELEASE_SOURCES:
        raise ValueError(f"source={source!r} is out of range: allowed one of {', '.join(RELEASE_SOURCES)}")
    j = res.column(delta)
    info = {}
    t_post = {}
    for rel in res.release:
        w = int(rel["wall"])
        sample = int(np.asarray(rel["T_post"])[j])
        entry = {"float64_sample": sample}
        if source == "certified":
            c = certified_t_post(res.params, w, float(res.deltas[j]), deltas=tuple(float(x) for x in res.deltas),
                                 stick_time=stick_time, confirm=confirm)
            v, ok = _t_post_value(c)
            entry["certified"] = c
            entry["used"], entry["source"] = (v, "certified") if ok else (sample if sample >= 0 else None,
                                                                          "float64 sample (certification undecided)")
        else:
            entry["used"], entry["source"] = (sample if sample >= 0 else None), "float64 sample"
        t_post[w] = entry["used"]
        info[str(w)] = entry
    if source == "float64":
        dur, cens = res.duration(delta)
    else:
        dur, cens = res.duration(delta, t_post=t_post) if t_post else res.duration(delta)
    return dur, cens, info


def composed_mask(res, delta: float | None = None) -> np.ndarray:
    """Orbits whose duration comes from the release: they stuck before coming within ``delta``."""
    j = res.column(delta)
    raw = res.meta.get("hit_before_stick")
    m = res.first_stick >= 0
    return m & (raw[:, j] < 0) if raw is not None else m


def stick_counts(res, delta: float | None = None) -> dict:
    """Orbits that stick (before capture) per wall of their first sticking episode (``stick_wall``)."""
    m = composed_mask(res, delta)
    return {str(w): int(np.sum(m & (res.stick_wall == w))) for w in (0, -1)}


# ------------------------------------------------------------------------------------- Fig. 9

def basins(outdir="out/transients", profile="quick", nx=None, ny=None, window=BASIN_WINDOW, ns=BASIN_NS,
           delta=DELTA, params: Params = PAPER_PARAMS, ic_mode="pre-impact", s0=None, progress=None, lanes=None):
    """Fig. 9: durations on an ``nx`` x ``ny`` mesh computed once (cap = max(ns)), thresholded at each
    n: black = duration < n ("short" transients)."""
    # the paper does not state Fig. 9's resolution; 300 x 300 of the whole phase circle bounds the
    # paper profile's cost (the 400 x 400 of Fig. 11 is the paper's own, and is kept there)
    dnx, dny = _profile(profile, (120, 60), (300, 300))
    nx = dnx if nx is None else int(nx)
    ny = (dny if nx == dnx else nx) if ny is None else int(ny)
    ns = tuple(sorted(int(n) for n in ns))
    if not ns or ns[0] < 1:
        raise ValueError(f"ns={ns!r} is out of range: allowed integers >= 1")
    T, S = grid(window, nx, ny)
    res = transient_times(T.ravel(), S.ravel(), params, ic_mode=ic_mode, s0=s0, delta=delta, deltas=(delta,),
                          cap=ns[-1], progress=progress, label="basins", lanes=lanes)
    dur, cens, rinfo = release_durations(res, delta, confirm=profile == "paper")
    D = dur.reshape(T.shape)
    out = _outdir(outdir)
    fractions = {int(n): float(np.mean(D < n)) for n in ns}
    np.savez_compressed(out / "basins.npz", tau0=T, sdot0=S, duration=D, censored=cens.reshape(T.shape),
                        nstick=res.nstick.reshape(T.shape), ns=np.array(ns), delta=delta, window=np.array(window))
    fig, axs = subplots(2, 2, figsize=(9, 7), sharex=True, sharey=True)
    for ax, n, lab in zip(axs.ravel(), ns, "abcd"):
        ax.imshow(D < n, origin="lower", extent=window, aspect="auto", cmap="Greys", vmin=0, vmax=1,
                  interpolation="nearest")
        ax.add_patch(Rectangle((PAPER_BOX[0], PAPER_BOX[2]), PAPER_BOX[1] - PAPER_BOX[0],
                                   PAPER_BOX[3] - PAPER_BOX[2], fill=False, ec="C3", lw=1))
        ax.set_title(f"({lab}) n = {n}: black = duration < n ({100 * fractions[n]:.1f}%)", fontsize=9)
    for ax in axs[1]:
        ax.set_xlabel(r"$\tau_0$")
    for ax in axs[:, 0]:
        ax.set_ylabel(r"$\dot s_0$")
    fig.suptitle(f"Fig. 9: transient basins, alpha={params.alpha:g}, {nx}x{ny}, delta={delta:g}, IC {ic_mode}",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "fig9_basins.png", dpi=110)
    summary = {"figure": "9", "nx": nx, "ny": ny, "window": list(window), "ns": list(ns), "delta": delta,
               "short_fraction": fractions, "orbits_with_sticking": res.n_stuck_orbits,
               "stick_counts": stick_counts(res, delta), "release": rinfo, "engine": res.summary()}
    (out / "basins.json").write_text(json.dumps(summary, indent=1))
    return summary


# ------------------------------------------------------------------------------------ Fig. 10

def uncertainty(outdir="out/transients", profile="quick", n_points=None, eps=None, ns=(500, 1000), seed=0,
                box=PAPER_BOX, delta=DELTA, params: Params = PAPER_PARAMS, n_boot=200, progress=None, lanes=None):
    """Fig. 10: fraction f(eps) of eps-uncertain points among ``n_points`` random points of ``box``
    (deterministic ``seed``); B, C = (tau0 +- eps, sdot0).  Fits f ~ eps^phi for each n."""
    n_points = _profile(profile, 300, 3000) if n_points is None else int(n_points)
    if eps is None:
        eps = np.logspace(-9, -3, _profile(profile, 7, 13))
    eps = np.asarray(eps, float)
    if n_points < 10:
        raise ValueError(f"n_points={n_points} is out of range: allowed n_points >= 10")
    if eps.ndim != 1 or eps.size < 3 or np.any(~np.isfinite(eps)) or np.any(eps <= 0) or np.any(eps > 0.1):
        raise ValueError("eps is out of range: allowed at least 3 values with 0 < eps <= 0.1")
    ns = tuple(sorted(int(n) for n in ns))
    rng = np.random.default_rng(seed)
    tA = rng.uniform(box[0], box[1], n_points)
    sA = rng.uniform(box[2], box[3], n_points)
    sA = np.where(sA == 0.0, box[3] * 1e-12, sA)
    E = eps.size
    tau = np.concatenate([tA, (tA[:, None] + eps).ravel(), (tA[:, None] - eps).ravel()])
    sd = np.concatenate([sA, np.repeat(sA, E), np.repeat(sA, E)])
    res = transient_times(tau, sd, params, delta=delta, deltas=(delta,), cap=ns[-1], progress=progress,
                          label="uncertainty", lanes=lanes)
    dur, _, rinfo = release_durations(res, delta, confirm=profile == "paper")
    dA = dur[:n_points]
    dB = dur[n_points:n_points * (1 + E)].reshape(n_points, E)
    dC = dur[n_points * (1 + E):].reshape(n_points, E)
    fits = {}
    out = _outdir(outdir)
    for n in ns:
        unc = A._uncertain(dA, dB, dC, n)
        try:
            fits[n] = A.fit_uncertainty(eps, unc, n, n_boot=n_boot, seed=seed)
        except ValueError as e:
            fits[n] = None
            print(f"uncertainty: n={n}: {e}")
    np.savez_compressed(out / "uncertainty.npz", eps=eps, tauA=tA, sdotA=sA, dA=dA, dB=dB, dC=dC, ns=np.array(ns),
                        f=np.array([A._uncertain(dA, dB, dC, n).mean(axis=0) for n in ns]))
    with open(out / "uncertainty.csv", "w") as fh:
        fh.write("eps," + ",".join(f"f_n{n}" for n in ns) + "\n")
        fs = [A._uncertain(dA, dB, dC, n).mean(axis=0) for n in ns]
        for i, e in enumerate(eps):
            fh.write(f"{e!r}," + ",".join(repr(float(f[i])) for f in fs) + "\n")
    fig, ax = subplots(figsize=(6, 4.5))
    for n, mk in zip(ns, ("s", "o", "^", "v")):
        f = A._uncertain(dA, dB, dC, n).mean(axis=0)
        se = np.sqrt(f * (1.0 - f) / n_points)  # binomial standard error of each f(eps)
        pos = f > 0
        lo = np.minimum(se, 0.999 * f)  # keep the lower bar on the log axis
        eb = ax.errorbar(eps[pos], f[pos], yerr=[lo[pos], se[pos]], fmt=mk, mfc="none" if mk == "s" else None,
                         capsize=2, label=f"n = {n} (bars: sqrt(f(1-f)/{n_points}))")
        ax.set_xscale("log"); ax.set_yscale("log")
        ft = fits[n]
        if ft is not None:
            ax.loglog(eps, 10 ** ft.log10_C * eps ** ft.phi, "-", lw=0.8, color=eb[0].get_color(),
                      label=f"fit: phi = {ft.phi:.4f} +- {ft.phi_se_ls:.4f} (boot {ft.phi_se_boot:.4f})")
    ax.set_xlabel(r"$\epsilon$")
    ax.set_ylabel(r"$f(\epsilon)$")
    ax.set_title(f"Fig. 10: uncertain fraction, {n_points} points in the paper's box", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "fig10_uncertainty.png", dpi=110)
    summary = {"figure": "10", "n_points": n_points, "eps": eps.tolist(), "seed": seed, "delta": delta,
               "fits": {str(n): (fits[n].as_dict() if fits[n] is not None else None) for n in ns},
               "paper": {"500": [0.010, 0.001], "1000": [0.003, 0.002]}, "release": rinfo,
               "engine": res.summary()}
    (out / "uncertainty.json").write_text(json.dumps(summary, indent=1))
    return summary


# ------------------------------------------------------------------------------------ Fig. 11

def transients(outdir="out/transients", profile="quick", nx=None, ny=None, cap=None, box=PAPER_BOX, delta=DELTA,
               deltas=DELTAS, params: Params = PAPER_PARAMS, ic_mode="pre-impact", s0=None, n_lo=None, n_hi=None,
               n_boot=200, seed=0, progress=None, lanes=None, stick_time: float = STICK_TIME,
               release: str = "certified"):
    """Fig. 11: survival N(n) on an ``nx`` x ``ny`` mesh of ``box``; Eq. (14) fit for every recorded
    delta (the dependence on delta).

    The orbits that stick are composed with their wall's post-release duration, ``first_stick +
    T_post`` (:func:`release_durations`): ``release="certified"`` (default) uses ``T_post`` certified
    in ball arithmetic for the decimal parameters (confirmed at a second precision in the paper
    profile), ``"float64"`` the engine's own post-release orbit (a sample).  The summary's
    ``release`` entry gives, per wall stuck to, the certified values for the decimal parameters and
    for their float64 roundings at the main ``delta``, and the float64 sample; ``fits_float64_sample``
    is the Eq. (14) fit with the sample instead."""
    if release not in RELEASE_SOURCES:
        raise ValueError(f"release={release!r} is out of range: allowed one of {', '.join(RELEASE_SOURCES)}")
    nq = _profile(profile, 60, 400)
    nx = nq if nx is None else int(nx)
    ny = nx if ny is None else int(ny)
    cap = _profile(profile, 20000, 20000) if cap is None else int(cap)
    confirm = profile == "paper"
    T, S = grid(box, nx, ny)
    res = transient_times(T.ravel(), S.ravel(), params, ic_mode=ic_mode, s0=s0, delta=delta, deltas=deltas, cap=cap,
                          progress=progress, label="transients", lanes=lanes, stick_time=stick_time)
    out = _outdir(outdir)
    fits = {}
    hit_used = np.empty(res.hit.shape, np.int64)
    release_info = {}
    for j, d in enumerate(res.deltas):
        dur, cens, info = release_durations(res, d, source=release, confirm=confirm, stick_time=stick_time)
        release_info[f"{d:g}"] = info
        hit_used[:, j] = np.where(cens, -1, dur)
        try:
            fits[float(d)] = A.fit_survival(dur, cens, cap=cap, n_lo=n_lo, n_hi=n_hi, n_boot=n_boot, seed=seed)
        except ValueError as e:
            fits[float(d)] = None
            print(f"transients: delta={d:g}: {e}")
    # the main delta: also the float64 roundings of the parameters (certified) and the float64 sample
    main_info = release_info[f"{float(delta):g}"]
    for w, entry in main_info.items():
        entry["certified_float64_rounding"] = certified_t_post(params, int(w), float(delta), rounding="float64",
                                                               stick_time=stick_time, confirm=confirm)
    dur_s, cens_s = res.duration(delta)
    try:
        fit_sample = A.fit_survival(dur_s, cens_s, cap=cap, n_lo=n_lo, n_hi=n_hi, n_boot=n_boot, seed=seed)
    except ValueError:
        fit_sample = None
    dur, cens = hit_used[:, res.column(delta)], None
    cens = dur < 0
    dur = np.where(cens, cap, dur)
    n, N = A.survival(dur, cap)
    composed = composed_mask(res, delta)
    np.savez_compressed(out / "transients.npz", tau0=T, sdot0=S, hit=hit_used.reshape(T.shape + (-1,)),
                        hit_float64_sample=res.hit.reshape(T.shape + (-1,)), deltas=res.deltas, delta=delta, cap=cap,
                        status=res.status.reshape(T.shape), nstick=res.nstick.reshape(T.shape),
                        first_stick=res.first_stick.reshape(T.shape), stick_wall=res.stick_wall.reshape(T.shape),
                        composed=composed.reshape(T.shape), stick_time=stick_time, release=release,
                        params=np.array([params.alpha, params.beta, params.gamma, params.r]), n=n, N=N)
    with open(out / "survival.csv", "w") as fh:
        fh.write("n,N\n")
        step = max(1, len(n) // 4000)
        for i in range(0, len(n), step):
            fh.write(f"{n[i]},{N[i]}\n")
    main = fits.get(float(delta))
    fig, ax = subplots(figsize=(6, 4.5))
    ax.semilogy(n, np.where(N > 0, N, np.nan), "-", lw=1, label=f"N(n), delta = {delta:g}")
    if main is not None:
        xs = np.array([main.n_lo, main.n_hi])
        ax.semilogy(xs, main.N0 * np.exp(-main.kappa * xs / main.mean_n), "k--", lw=1,
                    label=f"Eq. (14): <n> = {main.mean_n:.0f}, kappa = {main.kappa:.3f} +- {main.kappa_se_boot:.3f}")
    ax.set_xlabel("n")
    ax.set_ylabel("N(n): orbits still transient")
    ax.set_title(f"Fig. 11: {nx}x{ny} mesh, cap {cap}, IC {ic_mode}, T_post {release} "
                 f"(paper: <n>={PAPER['mean_n'].printed}, kappa={PAPER['kappa'].printed})", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "fig11_survival.png", dpi=110)
    summary = {"figure": "11", "nx": nx, "ny": ny, "cap": cap, "box": list(box), "delta": delta,
               "ic_mode": ic_mode, "s0": s0, "stick_time": stick_time, "release_source": release,
               "params_decimal": decimal_params(params),
               "fits": {f"{d:g}": (f.as_dict() if f is not None else None) for d, f in fits.items()},
               "fits_float64_sample": fit_sample.as_dict() if fit_sample is not None else None,
               "stick_counts": stick_counts(res, delta), "n_composed": int(composed.sum()),
               "release": release_info,
               "paper": {"mean_n": int(PAPER["mean_n"].value), "kappa": [PAPER["kappa"].value, PAPER["kappa"].error]}, "engine": res.summary()}
    (out / "transients.json").write_text(json.dumps(summary, indent=1))
    return summary


# ------------------------------------------------------------ sensitivity to the sticking decision

#: Other values of the chatter threshold (``mapimpl.sticking.STICK_TIME``) tried by :func:`stick_time_sensitivity`.
STICK_TIMES = (1e-7, 1e-5)


def stick_time_sensitivity(outdir="out/transients", profile="quick", stick_times=STICK_TIMES, stride=None,
                           n_boot=100, seed=0, progress=None, lanes=None) -> dict:
    """<n>, kappa and the sticking fraction of Eq. (14) for other values of the chatter threshold
    ``stick_time`` (the predicted accumulation time below which chatter is replaced by sticking,
    :mod:`mapimpl.sticking`), on a sub-mesh of the Fig. 11 run in ``outdir`` (every ``stride``-th row
    and column of its mesh; default: 1 in the quick profile, 4 in the paper profile -- a 100 x 100
    sub-mesh -- to bound the cost).  The run's own threshold is taken from its saved durations (not recomputed); every
    threshold uses its own certified ``T_post`` (the post-release orbit's sticking decisions depend on
    it too).  Reads ``<outdir>/transients.npz`` written by :func:`transients`."""
    stride = _profile(profile, 1, 4) if stride is None else int(stride)
    if stride < 1:
        raise ValueError(f"stride={stride!r} is out of range: allowed an integer >= 1")
    for st in stick_times:
        if not (math.isfinite(float(st)) and 0 < float(st) <= 1e-2):
            raise ValueError(f"stick_times: {st!r} is out of range: allowed 0 < stick_time <= 1e-2")
    out = Path(outdir)
    try:
        z = np.load(out / "transients.npz")
    except OSError:
        raise ValueError(f"outdir={str(outdir)!r} has no transients.npz: run transients() there first") from None
    if str(z["release"]) != "certified":
        raise ValueError("the Fig. 11 run in outdir did not use the certified T_post")
    p = Params(*[float(x) for x in z["params"]])
    base = float(z["stick_time"])
    cap, delta = int(z["cap"]), float(z["delta"])
    k = [float(x) for x in z["deltas"]].index(delta)
    T, S = z["tau0"][::stride, ::stride], z["sdot0"][::stride, ::stride]
    confirm = profile == "paper"
    rows = []
    for st in sorted({base, *(float(x) for x in stick_times)}):
        if st == base:
            h = z["hit"][::stride, ::stride, k].ravel().astype(np.int64)
            cens = h < 0
            dur = np.where(cens, cap, h)
            comp = z["composed"][::stride, ::stride].ravel()
            sw = z["stick_wall"][::stride, ::stride].ravel()
            counts = {str(w): int(np.sum(comp & (sw == w))) for w in (0, -1)}
        else:
            res = transient_times(T.ravel(), S.ravel(), p, delta=delta, deltas=(delta,), cap=cap, progress=progress,
                                  label=f"stick_time={st:g}", lanes=lanes, stick_time=st)
            dur, cens, _ = release_durations(res, delta, confirm=confirm, stick_time=st)
            comp = composed_mask(res, delta)
            counts = stick_counts(res, delta)
        tp = certified_t_post(p, 0, delta, stick_time=st, confirm=confirm)
        try:
            f = A.fit_survival(dur, cens, cap=cap, n_boot=n_boot, seed=seed).as_dict()
        except ValueError as e:
            f = None
            print(f"stick_time={st:g}: {e}")
        rows.append({"stick_time": st, "base": st == base, "n_ic": int(dur.size),
                     "sticking_fraction": float(comp.mean()), "stick_counts": counts,
                     "T_post_upper": tp["value"], "T_post_upper_status": tp["status"], "fit": f})
    summary = {"stride": stride, "nx": int(T.shape[1]), "ny": int(T.shape[0]), "cap": cap, "delta": delta,
               "rows": rows}
    (out / "stick_time_sensitivity.json").write_text(json.dumps(summary, indent=1))
    return summary


# --------------------------------------------------------------- the float64 horizon (a sample, not a value)

def float64_horizon(params: Params = PAPER_PARAMS, profile="quick", delta: float = DELTA, n_side: int | None = None,
                    impacts: int | None = None) -> dict:
    """The number of impacts after which a float64 transient orbit has lost the true one: the
    transient Lyapunov exponent ``lambda1`` (:func:`validation.transient.float64_release.transient_lyapunov`, a
    small grid of the Fig. 11 box: 6 x 6 orbits x 2000 impacts quick, 8 x 8 x 3000 paper) and
    ``ln(delta / u) / lambda1`` (roundoff ``u = 2^-53`` grown to the capture distance) and
    ``ln(1 / u) / lambda1`` (no digit left).  ``n_side`` and ``impacts`` override the profile's grid."""
    from . import float64_release as REL

    p_side, p_impacts = _profile(profile, (6, 2000), (8, 3000))
    n_side = p_side if n_side is None else int(n_side)
    impacts = p_impacts if impacts is None else int(impacts)
    ly = REL.transient_lyapunov(params, n_side=n_side, impacts=impacts)
    lam = float(ly["lambda1"])
    return {**ly, "n_side": n_side, "impacts": impacts, "delta": delta,
            "horizon_delta": REL.float64_horizon(lam, delta), "horizon_1": REL.float64_horizon(lam, 1.0)}
