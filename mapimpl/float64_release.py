"""The release orbit in float64: the counterparts of the certified ``T_post`` (docs/release.md).

The float64 engine's own ``T_post`` (:func:`float64_release_duration`, a sample of a chaotic orbit,
not a value), where a float64 orbit leaves the true one (:func:`float64_horizon`,
:func:`float64_departure`), the Lyapunov exponent of the transient (:func:`transient_lyapunov`),
the wall every initial condition first sticks to (:func:`sticking_walls`) and a state that sticks
at once (:func:`stick_at_once_state`).  The certified values are in :mod:`mapimpl.certified`.
"""

from __future__ import annotations

import math

from ..core.paper import DELTA
from .certified.capture import Target
from .certified.release import certify_post_release
from ..core.params import Params
from .sticking import STICK_TIME


def stick_at_once_state(params: Params, wall: int = 0, tau0: float | None = None) -> tuple[float, float]:
    """A pre-impact state that sticks at once to ``wall`` (rule): at phase ``tau0`` (default: where
    the contact force presses hardest, ``phi -+ pi/2``) with speed half the largest one that sticks
    at once, ``|sdot0| = STICK_TIME (1 - r) f_in / (4 r)``, rounded to 3 significant digits."""
    if wall not in (0, -1):
        raise ValueError(f"wall={wall!r} is out of range: allowed 0 or -1")
    d = 1.0 if wall == 0 else -1.0
    if tau0 is None:
        tau0 = math.atan(params.beta) - d * math.pi / 2
        tau0 = tau0 % (2 * math.pi)
    f = -params.alpha * math.sin(tau0) + params.alpha * params.beta * math.cos(tau0) + params.gamma
    f_in = d * f
    if not (f_in > 0 and params.r < 1.0):
        raise ValueError(
            f"tau0={tau0!r}: the contact force does not press into wall {wall} there "
            "(or r = 1): no state sticks at once"
        )
    speed = float(f"{STICK_TIME * (1 - params.r) * f_in / (4 * params.r):.3g}")
    return float(tau0), d * speed


def float64_release_duration(params: Params, wall: int = 0, delta: float = DELTA, cap: int = 200_000) -> dict:
    """The float64 engine's own ``T_post`` (:func:`mapimpl.engine.transients.transient_times`) from a
    state that sticks at once (:func:`stick_at_once_state`; iteration 0 sticks, so the capture
    iteration is ``T_post``).  Returns ``{"value", "status", "tau0", "sdot0", "nstick"}`` (``value``
    None when the orbit is not captured within ``cap``)."""
    from .engine.options import Execution
    from .engine.transients import transient_times
    from ..core.status import Status

    tau0, sdot0 = stick_at_once_state(params, wall)
    one = Execution(lanes=1, devices=1)
    res = transient_times(params, [tau0], [sdot0], delta=delta, cap=cap, execution=one, progress=False)
    dur, censored = res.duration(delta)
    return {
        "value": None if censored[0] else int(dur[0]),
        "status": Status(int(res.status[0])).label,
        "tau0": tau0,
        "sdot0": sdot0,
        "nstick": int(res.nstick[0]),
        "cap": int(cap),
    }


def float64_horizon(lam: float, distance: float = 1.0) -> float:
    """Impacts after which a float64 orbit's rounding error (unit roundoff ``u = 2^-53``) has grown
    to ``distance`` at the Lyapunov rate ``lam`` (per impact): ``ln(distance / u) / lam``.  With
    ``distance = 1`` the float64 orbit has no digit left in common with the true one."""
    if not lam > 0:
        raise ValueError(f"lam={lam!r} is out of range: allowed lam > 0 (a chaotic orbit)")
    return math.log(distance / 2.0**-53) / lam


def float64_departure(
    params: Params,
    wall: int = 0,
    n: int = 300,
    prec: int = 1024,
    thresholds=(1e-12, 1e-8, 1e-3, 1e-1),
    target: Target | None = None,
) -> dict:
    """Where the float64 map's post-release orbit leaves the true one: the map track
    (:func:`mapimpl.orbit.map_orbit`) from a state that sticks at once to ``wall``, compared with the
    certified orbit (``prec`` bits, midpoints) impact by impact; for each threshold, the first
    post-release impact whose error (sup of the wrapped phase error and the sdot error, or a different
    wall) exceeds it.  ``params``: float64 (the map's own numbers, exact in the certification)."""
    from .orbit import map_orbit

    if target is None:
        target = Target((), (), ())
    a = certify_post_release(params, wall, prec=prec, target=target, max_impacts=n, record=True)
    tau0, sdot0 = stick_at_once_state(params, wall)
    seq = map_orbit(params, tau0, sdot0, len(a.orbit))
    _, th, sd, wl = seq.impact_arrays()
    err = []
    for k, (th_c, sd_c, w_c) in enumerate(a.orbit, start=1):
        if k >= len(th) or wl[k] != w_c:
            err.append(math.inf)
            continue
        dth = abs(th[k] - th_c) % (2 * math.pi)
        err.append(max(min(dth, 2 * math.pi - dth), abs(sd[k] - sd_c)))
    first = {f"{t:g}": next((k for k, e in enumerate(err, start=1) if e > t), None) for t in thresholds}
    return {"first_impact_above": first, "certified_impacts": len(a.orbit), "certified_status": a.status, "errors": err}


def transient_lyapunov(
    params: Params, n_side: int = 16, impacts: int = 3000, delta_far: float = 1e-2, box=None
) -> dict:
    """Largest Lyapunov exponent of the *transient* (the chaotic saddle), per impact: QR method
    (:mod:`mapimpl.lyapunov`) along the orbits of an ``n_side`` x ``n_side`` cell-centred
    grid of the Fig. 11 box, counting only the impacts before the orbit first comes within
    ``delta_far`` of the 4-impact target and no sticking step (Q restarts there).

    Returns ``{"lambda1", "impacts_used", "orbits", "orbits_reaching_target"}``."""
    import numpy as np

    from ..core import jax_config  # noqa: F401
    import jax
    import jax.numpy as jnp

    from .engine.observers import orbit_distance
    from .engine.transients import grid, periodic_target
    from ..core.paper import PAPER_BOX
    from ..core.status import Status
    from .impact_map import step
    from ..core.state import make_state

    tg = periodic_target(params)
    po_th, po_v, po_w = jnp.asarray(tg.theta), jnp.asarray(tg.sdot), jnp.asarray(tg.wall)
    TAU, SD = grid(PAPER_BOX if box is None else box, n_side, n_side)
    st = make_state(jnp.asarray(TAU.ravel()), jnp.asarray(SD.ravel()))
    p = params.arrays()

    def one(s):
        def body(c, _):
            s, Q, acc, cnt, live = c
            s1, info = step(s, p)
            J = jnp.where(info.stuck, jnp.eye(2), info.jac)
            Qn, R = jnp.linalg.qr(J @ Q)
            dg = jnp.diagonal(R)
            far = orbit_distance(s1.theta, s1.sdot, s1.wall, po_th, po_v, po_w) >= delta_far
            live1 = live & (s1.status == Status.ACTIVE) & far
            use = live1 & ~info.stuck
            acc = acc + jnp.where(use, jnp.log(jnp.abs(dg[0])), 0.0)
            Qn = jnp.where(use, Qn * jnp.sign(dg)[None, :], jnp.eye(2))
            return (s1, Qn, acc, cnt + use.astype(jnp.int64), live1), None

        c0 = (s, jnp.eye(2), jnp.asarray(0.0), jnp.asarray(0, jnp.int64), jnp.asarray(True))
        (_, _, acc, cnt, live), _ = jax.lax.scan(body, c0, None, length=impacts)
        return acc, cnt, live

    acc, cnt, live = jax.jit(jax.vmap(one))(st)
    acc, cnt, live = np.asarray(acc), np.asarray(cnt), np.asarray(live)
    used = int(cnt.sum())
    if used == 0:
        raise RuntimeError("no transient impacts to measure")
    return {
        "lambda1": float(acc.sum() / used),
        "impacts_used": used,
        "orbits": int(acc.size),
        "orbits_reaching_target": int((~live).sum()),
    }


def sticking_walls(
    tau0, sdot0, params: Params, *, cap: int = 200_000, lanes: int | None = None, delta: float = DELTA, progress=None
) -> dict:
    """Which wall every pre-impact initial condition first sticks to within ``cap`` iterations (before a
    capture within ``delta``): the transient engine itself (``sticking="compose"``, which stops each orbit
    at its first sticking).

    Returns numpy arrays ``{"first_wall" (0, -1, or 1 = never stuck), "first_stick" (impact index,
    -1: never), "status", "n"}``.
    """
    import numpy as np

    from .engine.options import Execution
    from .engine.transients import transient_times

    res = transient_times(
        params,
        np.atleast_1d(np.asarray(tau0, float)),
        np.atleast_1d(np.asarray(sdot0, float)),
        delta=delta,
        deltas=(delta,),
        cap=int(cap),
        sticking="compose",
        execution=Execution(lanes=lanes),
        progress=progress,
        label="sticking walls",
    )
    stuck = res.first_stick >= 0
    return {
        "first_wall": np.where(stuck, res.stick_wall, 1),
        "first_stick": np.asarray(res.first_stick),
        "status": np.asarray(res.status),
        "n": np.asarray(res.n),
    }


__all__ = [
    "stick_at_once_state",
    "float64_release_duration",
    "float64_horizon",
    "float64_departure",
    "transient_lyapunov",
    "sticking_walls",
]
