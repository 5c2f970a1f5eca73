"""Intermittency (r2), interior crisis (r1) and boundary crisis (alpha1): the sudden changes of
Section 3 and Fig. 8, located with error bars.

* ``r2`` (alpha = 3): saddle-node (fold) of the 6-impact period-1 orbit, located to ~12 digits by
  Newton on the extended system (:mod:`validation.dynamics.continuation`).  Above r2 the orbit is gone and its
  ghost gives type-I intermittency: :func:`laminar_statistics` measures laminar phases (runs of impacts
  within ``eps`` of the fold orbit) and :func:`fit_power_law` fits ``<l> ~ (r - r2)^(-nu)`` with the
  known r2 (theory: ``nu = 1/2``).
* ``r1`` (alpha = 3): interior crisis in which the 6-band attractor collides with the unstable
  6-impact orbit born at r2 (the saddle branch of the fold).  Below r1 the orbit stays in the old
  bands for long stretches and bursts out (crisis-induced intermittency).  A burst is an impact whose
  6-impact return time ``tau_{n+6} - tau_n`` differs from ``2 pi`` by more than ``burst_threshold``
  (inside the 6 bands it never does).  :func:`burst_statistics` gives the mean time between bursts;
  :func:`fit_crisis` fits ``T = C |mu - mu_c|^(-g)`` for ``mu_c`` with an error bar.  Above r1,
  :func:`distance_to_orbit` of the attractor to the saddle orbit shows the mechanism (it shrinks to
  zero at r1).
* ``alpha1`` (r = 0.9): boundary crisis.  The 4-impact orbit is born at a fold alpha_sn < alpha1 and
  coexists with the chaotic attractor; at alpha1 the attractor touches the saddle 4-impact orbit on
  its basin boundary and becomes a chaotic saddle.  :func:`transient_lifetimes` measures the mean
  lifetime of the chaotic transient before capture by the stable 4-impact orbit (censored runs handled
  by the exponential maximum-likelihood estimate) and :func:`fit_crisis` fits the Grebogi-Ott-Yorke
  law ``T ~ (alpha - alpha1)^(-g)``; the theory exponent for a 2-D map, ``g = 1/2 + ln|m_u| / |ln|m_s||``
  with the multipliers of the mediating orbit, is :func:`goy_exponent`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...mapimpl import _jax  # noqa: F401

from ...mapimpl.flight import TWO_PI
from ...mapimpl.impact_map import make_state
from ...mapimpl.params import Params
from ...mapimpl.periodic import find_periodic
from .bifurcation import _adv_batch, _rec_batch, check_int, param_arrays
from .continuation import Branch, continue_orbit, orbit_states

_TP = float(TWO_PI)

#: Starting guesses on the attractors of the paper (found by long runs; any nearby guess works).
R2_START = Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.80)      # stable 6-impact orbit (Fig. 4)
ALPHA1_START = Params(alpha=1.30, beta=0.1, gamma=0.1, r=0.9)  # stable 4-impact orbit (Fig. 8)


def attractor_point(params: Params, n: int = 5000, tau0: float = 0.0, sdot0: float = 0.5) -> tuple[float, float]:
    """The state ``(theta, sdot)`` after ``n`` impacts from ``(tau0, sdot0)``: a guess on the attractor."""
    st = make_state(np.array([tau0]), np.array([sdot0]))
    st = _adv_batch(st, param_arrays(params, "r", [params.r]), check_int("n", n, 1, 10_000_000))
    return float(st.theta[0]), float(st.sdot[0])


def six_impact_branch(base: Params = R2_START, r_min: float = 0.735, r_max: float = 0.83, ds: float = 2e-3,
                      max_points: int = 200) -> Branch:
    """Continue the 6-impact period-1 orbit of Fig. 4 from ``base`` (r = 0.8) up through its fold r2 and
    down the saddle branch to ``r_min``.  ``branch.folds[0]`` is r2."""
    th, sd = attractor_point(base)
    return continue_orbit(base, "r", th, sd, 6, 1, mu_range=(r_min, r_max), direction=1, ds=ds,
                          max_points=max_points)


def four_impact_branch(base: Params = ALPHA1_START, a_min: float = 1.15, a_max: float = 1.32, ds: float = 2e-3,
                       max_points: int = 200) -> Branch:
    """Continue the 4-impact period-1 orbit of Fig. 8 from ``base`` (alpha = 1.3) down through its fold
    and up the saddle branch to ``a_max``."""
    th, sd = attractor_point(base)
    return continue_orbit(base, "alpha", th, sd, 4, 1, mu_range=(a_min, a_max), direction=-1, ds=ds,
                          max_points=max_points)


def orbit_on_branch(branch: Branch, mu: float, part: str = "saddle"):
    """Newton-refined orbit of ``branch`` at parameter ``mu``: ``part="saddle"`` (after the first fold)
    or ``"node"`` (before it).  Returns a :class:`mapimpl.periodic.PeriodicOrbit`."""
    if part not in ("saddle", "node"):
        raise ValueError(f"part={part!r} is out of range: allowed 'saddle' or 'node'")
    a = branch.arrays()
    k = int(np.argmax(a["mu"])) if branch.param == "r" else int(np.argmin(a["mu"]))
    sl = slice(k, None) if part == "saddle" else slice(0, k + 1)
    mus, taus, sds = a["mu"][sl], a["tau"][sl], a["sdot"][sl]
    if not (mus.min() <= mu <= mus.max()):
        raise ValueError(f"{branch.param}={mu!r} is out of range: allowed [{mus.min()}, {mus.max()}] on the {part} branch")
    j = int(np.argmin(np.abs(mus - mu)))
    params = branch.params.replace(**{branch.param: mu})
    return find_periodic(params, taus[j], sds[j], branch.impacts, branch.turns)


def distance_to_orbit(theta: np.ndarray, sdot: np.ndarray, orb_theta: np.ndarray, orb_sdot: np.ndarray) -> np.ndarray:
    """Euclidean distance in the (theta mod 2 pi, sdot) plane from each point to the nearest orbit point."""
    theta, sdot = np.asarray(theta), np.asarray(sdot)
    d = np.full(theta.shape, np.inf)
    for t0, s0 in zip(orb_theta, orb_sdot):
        dt = np.abs(theta - t0)
        dt = np.minimum(dt, _TP - dt)
        d = np.minimum(d, np.hypot(dt, sdot - s0))
    return d


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start indices and lengths of the runs of True in a 1-D boolean array."""
    m = np.concatenate([[False], mask, [False]]).astype(np.int8)
    dm = np.diff(m)
    starts = np.nonzero(dm == 1)[0]
    ends = np.nonzero(dm == -1)[0]
    return starts, ends - starts


def _stream(params_list_name: str, base: Params, values, n: int, chunk: int, consume, tau0=2.97, sdot0=-0.55,
            transient: int = 2000, progress=None, n_per_value: int = 1, ics=None):
    """Run one orbit per (value, ic), in chunks, handing each chunk's ``(theta, sdot, active)`` to
    ``consume(chunk_index, theta, sdot, active)``; ``consume`` returns True to stop early."""
    values = np.repeat(np.asarray(values, dtype=np.float64), n_per_value)
    p = param_arrays(base, params_list_name, values)
    if ics is None:
        st = make_state(np.full(values.size, tau0), np.full(values.size, sdot0))
    else:
        st = make_state(np.asarray(ics[0], float), np.asarray(ics[1], float))
    if transient:
        st = _adv_batch(st, p, transient)
    done, i = 0, 0
    while done < n:
        k = min(chunk, n - done)
        st, rec = _rec_batch(st, p, k)
        th, sd, _w, _stk, act = (np.asarray(a) for a in rec)
        done += k
        if progress is not None:
            progress(done, n)
        if consume(i, th, sd, act):
            break
        i += 1
    return done


@dataclass
class LaminarStats:
    """Laminar phases near the ghost of the fold orbit: per ``r``, the mean laminar length (impacts),
    its standard error and the number of complete phases."""

    r: np.ndarray
    mean: np.ndarray
    sem: np.ndarray
    count: np.ndarray
    eps: float
    n_impacts: int


def laminar_statistics(r_values, r2_orbit, n_impacts: int = 200_000, eps: float = 0.05, min_length: int = 12,
                       base: Params = R2_START, chunk: int = 20000, progress=None) -> LaminarStats:
    """Type-I intermittency above r2: laminar phases are runs of at least ``min_length`` impacts within
    ``eps`` of the fold orbit ``r2_orbit`` (a :class:`validation.dynamics.continuation.BifurcationPoint` or
    ``(theta, sdot)`` arrays of its 6 points).  One orbit per r value, vectorised."""
    n_impacts = check_int("n_impacts", n_impacts, 1000, 100_000_000)
    if not (np.isfinite(eps) and eps > 0):
        raise ValueError(f"eps={eps!r} is out of range: allowed eps > 0")
    r_values = np.atleast_1d(np.asarray(r_values, float))
    if hasattr(r2_orbit, "mu"):
        oth, osd = orbit_states(base.replace(r=r2_orbit.mu), r2_orbit.tau, r2_orbit.sdot, 6)
    else:
        oth, osd = r2_orbit
    lengths = [[] for _ in r_values]
    carry = np.zeros(r_values.size, int)

    def consume(i, th, sd, act):
        near = distance_to_orbit(th, sd, oth, osd) < eps
        for j in range(r_values.size):
            m = near[j]
            starts, lens = _runs(m)
            if carry[j] and starts.size and starts[0] == 0:
                lens[0] += carry[j]
            elif carry[j]:
                lengths[j].append(carry[j])
            if starts.size and starts[-1] + lens[-1] == m.size:  # run continues into the next chunk
                carry[j] = lens[-1]
                lens = lens[:-1]
            else:
                carry[j] = 0
            if i == 0 and starts.size and starts[0] == 0:
                lens = lens[1:]  # started inside a phase: incomplete
            lengths[j].extend(int(x) for x in lens)
        return False

    _stream("r", base, r_values, n_impacts, chunk, consume, progress=progress)
    mean, sem, cnt = [], [], []
    for L in lengths:
        L = np.array([x for x in L if x >= min_length], float)
        cnt.append(L.size)
        mean.append(L.mean() if L.size else np.nan)
        sem.append(L.std(ddof=1) / np.sqrt(L.size) if L.size > 1 else np.nan)
    return LaminarStats(r_values, np.array(mean), np.array(sem), np.array(cnt), float(eps), n_impacts)


def fit_power_law(x: np.ndarray, y: np.ndarray, yerr: np.ndarray | None = None) -> tuple[float, float, float]:
    """Weighted least-squares fit ``log y = a + s log x``; returns ``(slope, slope_err, a)``."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    if ok.sum() < 3:
        raise ValueError("fit_power_law needs at least 3 positive finite points")
    lx, ly = np.log(x[ok]), np.log(y[ok])
    w = None
    if yerr is not None:
        rel = np.asarray(yerr, float)[ok] / y[ok]
        w = np.where(np.isfinite(rel) & (rel > 0), 1.0 / rel, 1.0)
    coef, cov = np.polyfit(lx, ly, 1, w=w, cov="unscaled" if w is not None else True)
    if w is not None:  # scale by the reduced chi^2 when it exceeds 1 (honest error bars)
        res = (ly - np.polyval(coef, lx)) * w
        chi2 = float(np.sum(res ** 2) / max(ok.sum() - 2, 1))
        cov = cov * max(chi2, 1.0)
    return float(coef[0]), float(np.sqrt(cov[0, 0])), float(coef[1])


@dataclass
class CrisisStats:
    """Characteristic times near a crisis: per parameter value, the mean time ``T`` (impacts) between
    bursts (interior crisis) or before capture (boundary crisis), its standard error, the number of
    events and the number of impacts observed."""

    param: str
    values: np.ndarray
    T: np.ndarray
    T_err: np.ndarray
    events: np.ndarray
    exposure: np.ndarray


def burst_statistics(r_values, n_impacts: int = 300_000, burst_threshold: float = 0.6, base: Params = R2_START,
                     chunk: int = 20000, transient: int = 5000, progress=None) -> CrisisStats:
    """Crisis-induced intermittency below r1 (alpha = 3): mean number of impacts between bursts out of the
    six pre-crisis bands.  A burst starts at an impact whose 6-impact return time differs from 2 pi
    by more than ``burst_threshold`` after at least 60 impacts inside the bands."""
    n_impacts = check_int("n_impacts", n_impacts, 1000, 100_000_000)
    if not (np.isfinite(burst_threshold) and 0 < burst_threshold < np.pi):
        raise ValueError(f"burst_threshold={burst_threshold!r} is out of range: allowed 0 < threshold < pi")
    r_values = np.atleast_1d(np.asarray(r_values, float))
    events = np.zeros(r_values.size, int)
    last_th = [None] * r_values.size
    inside = np.zeros(r_values.size, int)

    def consume(i, th, sd, act):
        for j in range(r_values.size):
            t = th[j] if last_th[j] is None else np.concatenate([last_th[j], th[j]])
            dth = np.diff(t)
            dth = np.where(dth < 0, dth + _TP, dth)
            cum = np.concatenate([[0.0], np.cumsum(dth)])
            D = np.abs(cum[6:] - cum[:-6] - _TP)
            out = D > burst_threshold
            # a burst: a run of >= 60 'inside' impacts (carried over chunks) followed by an 'out' impact
            starts, lens = _runs(~out)
            ends = starts + lens
            good = (lens + np.where(starts == 0, inside[j], 0) >= 60) & (ends < out.size)
            events[j] += int(good.sum())
            inside[j] = (lens[-1] + (inside[j] if starts[-1] == 0 else 0)) if (starts.size and ends[-1] == out.size) else 0
            last_th[j] = th[j][-6:]
        return False

    done = _stream("r", base, r_values, n_impacts, chunk, consume, transient=transient, progress=progress)
    T = np.where(events > 0, done / np.maximum(events, 1), np.inf)
    return CrisisStats("r", r_values, T, T / np.sqrt(np.maximum(events, 1)), events, np.full(r_values.size, done))


def transient_lifetimes(alpha_values, n_ics: int = 64, cap: int = 100_000, capture_eps: float = 1e-3,
                        base: Params = ALPHA1_START, seed: int = 0, chunk: int = 5000, progress=None,
                        box=((3.0, 3.5), (0.0, 0.5))) -> CrisisStats:
    """Mean lifetime of the chaotic transient after the crisis alpha1 (r = 0.9): ``n_ics`` random initial
    conditions in ``box`` (the paper's box of Figs. 9-11: 3 < tau0 < 3.5, 0 < sdot0 < 0.5) per alpha value
    are iterated until they come within ``capture_eps`` of the stable 4-impact orbit (at most ``cap``
    impacts).  The mean lifetime is the exponential maximum-likelihood estimate with censoring:
    ``T = (total observed time) / (number captured)``."""
    n_ics = check_int("n_ics", n_ics, 1, 100000)
    cap = check_int("cap", cap, 1, 100_000_000)
    alpha_values = np.atleast_1d(np.asarray(alpha_values, float))
    rng = np.random.default_rng(seed)
    m = alpha_values.size * n_ics
    tau0 = rng.uniform(box[0][0], box[0][1], m)
    sd0 = rng.uniform(box[1][0], box[1][1], m)
    orbits = []
    g = None
    for a in alpha_values:  # stable 4-impact orbit at each alpha (node branch, from a long run)
        pa = base.replace(alpha=a)
        th, sd = attractor_point(pa, 20000) if g is None else g
        o = find_periodic(pa, th, sd, 4)
        if not (o.converged and o.stable):
            th, sd = attractor_point(ALPHA1_START, 20000)
            o = find_periodic(pa, th, sd, 4)
        if not (o.converged and o.stable):
            raise ValueError(f"alpha={a!r}: no stable 4-impact orbit found (allowed alpha above the fold, ~1.2046)")
        orbits.append(o)
        g = (o.tau[0], o.sdot[0])
    life = np.full(m, -1, int)

    def consume(i, th, sd, act):
        for j in range(m):
            if life[j] >= 0:
                continue
            o = orbits[j // n_ics]
            near = distance_to_orbit(th[j], sd[j], o.tau, o.sdot) < capture_eps
            idx = np.nonzero(near)[0]
            if idx.size:
                life[j] = i * chunk + int(idx[0])
        return bool(np.all(life >= 0))

    _stream("alpha", base, alpha_values, cap, chunk, consume, transient=0, progress=progress,
            n_per_value=n_ics, ics=(tau0, sd0))
    L = life.reshape(alpha_values.size, n_ics)
    obs = np.where(L >= 0, L, cap).sum(axis=1).astype(float)
    k = (L >= 0).sum(axis=1)
    T = np.where(k > 0, obs / np.maximum(k, 1), np.inf)
    return CrisisStats("alpha", alpha_values, T, T / np.sqrt(np.maximum(k, 1)), k, obs)


def fit_crisis(values: np.ndarray, T: np.ndarray, T_err: np.ndarray, side: str, mu_bounds: tuple[float, float]):
    """Fit ``log T = log C - g log|mu - mu_c|`` (``side="above"``: data at mu > mu_c; ``"below"``: mu < mu_c)
    by profile least squares over ``mu_c`` in ``mu_bounds``.  Returns ``(mu_c, mu_c_err, g, g_err)``;
    the error of mu_c is the half-width of the region where chi^2 rises by 1 (after scaling chi^2 by its
    reduced value when that exceeds 1)."""
    if side not in ("above", "below"):
        raise ValueError(f"side={side!r} is out of range: allowed 'above' or 'below'")
    v, T, e = (np.asarray(a, float) for a in (values, T, T_err))
    ok = np.isfinite(T) & np.isfinite(e) & (T > 0)
    v, T, e = v[ok], T[ok], e[ok]
    if v.size < 4:
        raise ValueError("fit_crisis needs at least 4 finite characteristic times")
    lo, hi = mu_bounds
    edge = v.min() if side == "above" else v.max()
    if side == "above":
        hi = min(hi, edge - 1e-12)
    else:
        lo = max(lo, edge + 1e-12)
    if not lo < hi:
        raise ValueError(f"mu_bounds={mu_bounds!r} leave no room for mu_c on the {side} side of the data")
    w = T / e
    ly = np.log(T)

    def chi2(mc):
        x = np.log(np.abs(v - mc))
        coef = np.polyfit(x, ly, 1, w=w)
        return float(np.sum(((ly - np.polyval(coef, x)) * w) ** 2)), coef

    grid = np.linspace(lo, hi, 2001)[:-1] if side == "above" else np.linspace(lo, hi, 2001)[1:]
    c = np.array([chi2(g)[0] for g in grid])
    k = int(np.argmin(c))
    from scipy.optimize import minimize_scalar

    a_, b_ = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    r = minimize_scalar(lambda g: chi2(g)[0], bounds=(a_, b_), method="bounded", options={"xatol": 1e-12})
    mc = float(r.x)
    cmin, coef = chi2(mc)
    red = max(cmin / max(v.size - 3, 1), 1.0)
    inside = grid[c <= cmin + red]
    err = float(max(mc - inside.min(), inside.max() - mc)) if inside.size else float("nan")
    # slope error at the best mu_c
    x = np.log(np.abs(v - mc))
    _, cov = np.polyfit(x, ly, 1, w=w, cov="unscaled")
    return mc, err, float(-coef[0]), float(np.sqrt(cov[0, 0] * red))


def goy_exponent(multipliers) -> float:
    """Grebogi-Ott-Yorke critical exponent ``1/2 + ln|m_u| / |ln|m_s||`` of a crisis mediated by a saddle
    orbit with multipliers ``m_u`` (unstable) and ``m_s`` (stable) of a 2-D map."""
    m = np.sort(np.abs(np.asarray(multipliers, complex)))
    if not (m[0] < 1.0 < m[1]):
        raise ValueError(f"multipliers {multipliers!r} are out of range: allowed a saddle (|m_s| < 1 < |m_u|)")
    return float(0.5 + np.log(m[1]) / abs(np.log(m[0])))


def fit_crisis_fixed(values, T, T_err, g: float) -> tuple[float, float, float]:
    """Fit ``T = C |mu - mu_c|^(-g)`` with the exponent ``g`` fixed (e.g. by :func:`goy_exponent`):
    ``T^(-1/g)`` is linear in ``mu`` and vanishes at ``mu_c``.  Weighted linear least squares; returns
    ``(mu_c, mu_c_err, reduced_chi2)`` (the error is scaled by sqrt(chi^2) when chi^2 > 1)."""
    v, T, e = (np.asarray(a, float) for a in (values, T, T_err))
    ok = np.isfinite(T) & np.isfinite(e) & (T > 0) & (e > 0)
    v, T, e = v[ok], T[ok], e[ok]
    if v.size < 3:
        raise ValueError("fit_crisis_fixed needs at least 3 finite characteristic times")
    if not (np.isfinite(g) and g > 0):
        raise ValueError(f"g={g!r} is out of range: allowed g > 0")
    y = T ** (-1.0 / g)
    ey = y / g * e / T
    A = np.vstack([np.ones_like(v), v]).T
    W = np.diag(1.0 / ey ** 2)
    cov = np.linalg.inv(A.T @ W @ A)
    c = cov @ A.T @ W @ y
    res = (y - A @ c) / ey
    chi = float(res @ res / max(v.size - 2, 1))
    cov = cov * max(chi, 1.0)
    mc = -c[0] / c[1]
    Jg = np.array([-1.0 / c[1], c[0] / c[1] ** 2])
    return float(mc), float(np.sqrt(Jg @ cov @ Jg)), chi


#: Run-size profiles of the crisis/intermittency analyses: "quick" (each well under a minute on one
#: core, coarse) and "paper" (the numbers quoted in docs/dynamics.md; minutes each).
PROFILES = {
    "quick": {"laminar_dr": np.logspace(-5, -3, 4), "laminar_n": 60_000,
              "burst_r": np.array([0.74125, 0.74135, 0.74140, 0.74143]), "burst_n": 60_000,
              "life_alpha": np.array([1.2450, 1.2460, 1.2480, 1.2520]), "life_ics": 16, "life_cap": 20_000},
    "paper": {"laminar_dr": np.logspace(-5.5, -2.5, 7), "laminar_n": 200_000,
              "burst_r": np.array([0.74115, 0.74125, 0.74135, 0.74140, 0.74143]), "burst_n": 300_000,
              "life_alpha": np.array([1.2440, 1.2445, 1.2450, 1.2460, 1.2480, 1.2520, 1.2600]), "life_ics": 64,
              "life_cap": 100_000},
}


def _profile(name: str) -> dict:
    if name not in PROFILES:
        raise ValueError(f"profile={name!r} is out of range: allowed one of {tuple(PROFILES)}")
    return PROFILES[name]


def locate_r2(profile: str = "quick", branch: Branch | None = None, progress=None) -> dict:
    """r2 (fold of the 6-impact orbit) and the type-I intermittency slope of the mean laminar length."""
    pr = _profile(profile)
    br = branch or six_impact_branch()
    if not br.folds:
        raise RuntimeError("the 6-impact branch has no fold in its range")
    f = br.folds[0]
    dr = pr["laminar_dr"]
    ls = laminar_statistics(f.mu + dr, f, n_impacts=pr["laminar_n"], progress=progress)
    slope, err, _ = fit_power_law(dr, ls.mean, ls.sem)
    return {"r2": f.mu, "fold": f, "branch": br, "laminar": ls, "dr": dr, "slope": slope, "slope_err": err}


def locate_r1(profile: str = "quick", branch: Branch | None = None, progress=None) -> dict:
    """r1 from the mean time between bursts below r1, fitted with the GOY exponent of the saddle orbit."""
    pr = _profile(profile)
    br = branch or six_impact_branch()
    rs = pr["burst_r"]
    bs = burst_statistics(rs, n_impacts=pr["burst_n"], progress=progress)
    sad = orbit_on_branch(br, float(rs.max()) + 5e-5, "saddle")
    g = goy_exponent(sad.multipliers)
    r1, err, chi = fit_crisis_fixed(bs.values, bs.T, bs.T_err, g)
    lower = float(bs.values[bs.events > 0].max()) if np.any(bs.events > 0) else float("nan")
    return {"r1": r1, "r1_err": err, "chi2": chi, "goy_exponent": g, "saddle": sad, "bursts": bs,
            "lower_bound": lower}


def locate_alpha1(profile: str = "quick", progress=None) -> dict:
    """alpha1 from the mean transient lifetime above it, fitted with the GOY exponent of the saddle
    4-impact orbit; also the stable 4-impact orbit and its multipliers at alpha = 1.245 (Fig. 9)."""
    pr = _profile(profile)
    br = four_impact_branch()
    a = pr["life_alpha"]
    ts = transient_lifetimes(a, n_ics=pr["life_ics"], cap=pr["life_cap"], progress=progress)
    sad = orbit_on_branch(br, float(a.min()), "saddle")
    g = goy_exponent(sad.multipliers)
    a1, err, chi = fit_crisis_fixed(ts.values, ts.T, ts.T_err, g)
    node = orbit_on_branch(br, 1.245, "node")
    return {"alpha1": a1, "alpha1_err": err, "chi2": chi, "goy_exponent": g, "saddle": sad, "node": node,
            "branch": br, "lifetimes": ts}
