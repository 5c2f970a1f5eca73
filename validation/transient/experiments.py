"""The three experiments of Section 4, importable (the report generator calls them) and used by the
CLI commands ``gear-rattle basins | uncertainty | transients``.

Each function computes, writes ``<outdir>/<name>.npz`` (+ ``.csv`` / ``.json`` summary) and a PNG,
and returns a dict of results.  ``profile="quick"`` is small (well under a minute on 2 cores);
``profile="paper"`` is the paper's scale.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from matplotlib.patches import Rectangle

from ...mapimpl.params import Params
from ..figures import subplots
from . import analysis as A
from ...mapimpl.engine.transients import DELTA, DELTAS, PAPER_BOX, PAPER_PARAMS, grid, transient_times

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


# ------------------------------------------------------------------------------------- Fig. 9

def basins(outdir="out/transients", profile="quick", nx=None, ny=None, window=BASIN_WINDOW, ns=BASIN_NS,
           delta=DELTA, params: Params = PAPER_PARAMS, ic_mode="pre-impact", s0=None, progress=None, lanes=None):
    """Fig. 9: durations on an ``nx`` x ``ny`` mesh computed once (cap = max(ns)), thresholded at each
    n: black = duration < n ("short" transients)."""
    dnx, dny = _profile(profile, (120, 60), (400, 400))
    nx = dnx if nx is None else int(nx)
    ny = (dny if nx == dnx else nx) if ny is None else int(ny)
    ns = tuple(sorted(int(n) for n in ns))
    if not ns or ns[0] < 1:
        raise ValueError(f"ns={ns!r} is out of range: allowed integers >= 1")
    T, S = grid(window, nx, ny)
    res = transient_times(T.ravel(), S.ravel(), params, ic_mode=ic_mode, s0=s0, delta=delta, deltas=(delta,),
                          cap=ns[-1], progress=progress, label="basins", lanes=lanes)
    dur, cens = res.duration()
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
               "engine": res.summary()}
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
    dur, _ = res.duration()
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
               "paper": {"500": [0.010, 0.001], "1000": [0.003, 0.002]}, "engine": res.summary()}
    (out / "uncertainty.json").write_text(json.dumps(summary, indent=1))
    return summary


# ------------------------------------------------------------------------------------ Fig. 11

def transients(outdir="out/transients", profile="quick", nx=None, ny=None, cap=None, box=PAPER_BOX, delta=DELTA,
               deltas=DELTAS, params: Params = PAPER_PARAMS, ic_mode="pre-impact", s0=None, n_lo=None, n_hi=None,
               n_boot=200, seed=0, progress=None, lanes=None):
    """Fig. 11: survival N(n) on an ``nx`` x ``ny`` mesh of ``box``; Eq. (14) fit for every recorded
    delta (the dependence on delta)."""
    nq = _profile(profile, 60, 400)
    nx = nq if nx is None else int(nx)
    ny = nx if ny is None else int(ny)
    cap = _profile(profile, 20000, 20000) if cap is None else int(cap)
    T, S = grid(box, nx, ny)
    res = transient_times(T.ravel(), S.ravel(), params, ic_mode=ic_mode, s0=s0, delta=delta, deltas=deltas, cap=cap,
                          progress=progress, label="transients", lanes=lanes)
    out = _outdir(outdir)
    fits = {}
    for d in res.deltas:
        dur, cens = res.duration(d)
        try:
            fits[float(d)] = A.fit_survival(dur, cens, cap=cap, n_lo=n_lo, n_hi=n_hi, n_boot=n_boot, seed=seed)
        except ValueError as e:
            fits[float(d)] = None
            print(f"transients: delta={d:g}: {e}")
    dur, cens = res.duration()
    n, N = A.survival(dur, cap)
    np.savez_compressed(out / "transients.npz", tau0=T, sdot0=S, hit=res.hit.reshape(T.shape + (-1,)),
                        deltas=res.deltas, delta=delta, cap=cap, status=res.status.reshape(T.shape),
                        nstick=res.nstick.reshape(T.shape), n=n, N=N)
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
    ax.set_title(f"Fig. 11: {nx}x{ny} mesh, cap {cap}, IC {ic_mode} (paper: <n>=2272, kappa=0.893)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "fig11_survival.png", dpi=110)
    summary = {"figure": "11", "nx": nx, "ny": ny, "cap": cap, "box": list(box), "delta": delta,
               "ic_mode": ic_mode, "s0": s0,
               "fits": {f"{d:g}": (f.as_dict() if f is not None else None) for d, f in fits.items()},
               "paper": {"mean_n": 2272, "kappa": [0.893, 0.001]}, "engine": res.summary()}
    (out / "transients.json").write_text(json.dumps(summary, indent=1))
    return summary
