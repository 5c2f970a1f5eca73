"""Impact map, Eqs. (12)-(13): Jacobian, determinant identity, sticking, Figs. 2-3, batches."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st

from gear_rattle.mapimpl import Params
from gear_rattle.mapimpl.batch import batch_iterate, states
from gear_rattle.mapimpl.forcing import forcing, forcing_rate
from gear_rattle.core.status import Status
from gear_rattle.mapimpl.impact_map import step
from gear_rattle.core.state import make_state
from gear_rattle.mapimpl.orbit import map_orbit
from gear_rattle.mapimpl.sticking import STICK_TIME, release_delay
from mpref import first_root, map_jacobian
from tally import Tally

step_jit = jax.jit(step)
finite = dict(allow_nan=False, allow_infinity=False)


def _next(x, p):
    ns, _ = step(make_state(x[0], x[1]), p)
    return jnp.array([ns.tau, ns.sdot])


jac_autodiff = jax.jit(jax.jacfwd(_next))
next_jit = jax.jit(_next)


#: Analytic J against jax.jacfwd: both are float64 evaluations of the same derivative, whose entries
#: are divided by sdot_{n+1} (d tau1/d tau = (sdot0 + E1 a0)/v1, docs/model.md), so their rounding
#: grows like scale (1 + 1/|sdot_{n+1}|), scale = 1 + max|J|.  Measured over four runs of 1000-3000
#: random examples: max |J - Jad| / scale = 1.7e-13, 1.4e-12, 2.8e-13, 1.8e-13 (a heavy tail);
#: normalised by (1 + 1/|sdot_{n+1}|) (last two runs): 5.3e-14 and 1.2e-13; bound 1e-12.
J_JAD_TOL = 1e-12
#: Where jacfwd misses J_JAD_TOL, the 50-digit reference decides: jacfwd differentiates the finder's
#: iterations (its tangent is that of the last bracket/root step, not the implicit derivative), the
#: analytic J is the implicit derivative itself.  Bound on the analytic J against the reference,
#: relative to scale (1 + 1/|sdot_{n+1}|): the counterexample below, found by Hypothesis on
#: 2026-11-25 (jacfwd off by 6.0e-12, analytic J within 7e-16 of the reference), and J_JAD_TOL's
#: own measurements bound the analytic route's error well below this.
J_REF_TOL = 1e-13
#: det J against the closed form, relative to scale^2: a 2x2 determinant of entries <= scale (~4.5 eps);
#: measured max 1.2e-16 (four runs, 10000 random examples).
DET_TOL = 1e-15


def test_jacobian_analytic_vs_autodiff_and_det_identity():
    """Jacobian of the impact map Eqs. (12)-(13): the analytic J (implicit differentiation of
    s(tau_{n+1}) = wall, docs/model.md) equals jax.jacfwd through the finder, and
    det J = r^2 exp(-beta dt) sdot_n / sdot_{n+1} (tolerances J_JAD_TOL, DET_TOL; measured over 10000
    random examples).  Excluded (assume, counted): sticking steps (J = 0), ended orbits and impacts
    with |sdot_{n+1}| < 1e-3 (near grazing); none of 4000 random examples (two runs) was excluded.
    Where jacfwd and J differ by more than J_JAD_TOL, a 50-digit reference (central differences of
    the root, tests/mpref.py) must confirm the analytic J to J_REF_TOL and be closer to it than to
    jacfwd: jacfwd through an iterative finder is the less accurate route."""
    tally = Tally()

    @given(
        tau=st.floats(0, 6.28, **finite),
        sdot=st.floats(0.05, 2.5, **finite),
        sign=st.sampled_from([1.0, -1.0]),
        alpha=st.floats(0.5, 4, **finite),
        beta=st.floats(0.01, 1, **finite),
        gamma=st.floats(-0.3, 0.3, **finite),
        r=st.floats(0.5, 0.95, **finite),
    )
    @example(
        tau=0.9914057411330726, sdot=1.7208734625361166, sign=1.0, alpha=3.287109375, beta=0.01, gamma=0.0, r=0.5
    )  # jacfwd off by 6.0e-12: decided by the reference
    def prop(tau, sdot, sign, alpha, beta, gamma, r):
        p = Params(alpha, beta, gamma, r).arrays()
        x = jnp.array([tau, sign * sdot])
        ns, info = step_jit(make_state(x[0], x[1]), p)
        tally.exclude_if(bool(info.stuck), "sticking step (J = 0)")
        tally.exclude_if(int(ns.status) != Status.ACTIVE, "orbit ended")
        tally.exclude_if(abs(float(ns.sdot)) < 1e-3, "near-grazing impact")
        J = np.asarray(info.jac)
        Jad = np.asarray(jac_autodiff(x, p))
        scale = 1 + np.abs(J).max()
        bound = scale * (1 + 1 / abs(float(ns.sdot)))
        if np.abs(J - Jad).max() > J_JAD_TOL * bound:
            ref = np.array(map_jacobian(tau, sign * sdot, alpha, beta, gamma, r, float(info.dt)), dtype=float)
            assert np.abs(J - ref).max() <= J_REF_TOL * bound
            assert np.abs(J - ref).max() < np.abs(Jad - ref).max()
        det = r * r * np.exp(-beta * float(info.dt)) * float(x[1]) / float(ns.sdot)
        assert abs(np.linalg.det(J) - det) <= DET_TOL * scale**2
        tally.checked()

    prop()
    tally.assert_enough(settings.default.max_examples, 0.9)


def test_jacobian_vs_central_differences():
    """Analytic Jacobian of Eqs. (12)-(13) against central differences of the map, h = 1e-6, at the
    paper's Fig. 3 parameters.  The difference quotient's rounding error is ~eps |tau_{n+1}| / h
    <= 2.2e-16 * 20 / 1e-6 = 4e-9 (its truncation error, h^2 times the third derivative over 6, is
    ~1e-12), so the bound is 5e-9 (1 + max|J|); measured max 5.8e-10 (1 + max|J|).  All 10 states
    must be checked."""
    p = Params(3.0, 0.1, 0.1, 0.9).arrays()
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(10):
        x = jnp.array([rng.uniform(0, 6.28), rng.choice([-1, 1]) * rng.uniform(0.2, 2)])
        ns, info = step_jit(make_state(x[0], x[1]), p)
        if bool(info.stuck) or abs(float(ns.sdot)) < 0.05:
            continue
        h = 1e-6
        fd = np.stack(
            [(np.asarray(next_jit(x + h * e, p)) - np.asarray(next_jit(x - h * e, p))) / (2 * h) for e in jnp.eye(2)],
            axis=1,
        )
        J = np.asarray(info.jac)
        assert np.abs(J - fd).max() <= 5e-9 * (1 + np.abs(J).max())
        checked += 1
    assert checked == 10


def test_step_matches_50_digit_root_small_beta():
    """One map step (Eqs. 12-13) for beta = 1e-8 against the printed Eqs. (7)-(8) solved at 50 digits.
    Measured 8.9e-16 (tau, < 8 here: ulp 8.9e-16) and 7.8e-16 (sdot); bound 5e-15 on both."""
    P = Params(3.0, 1e-8, 0.1, 0.9)
    for tau, sd in [(0.4, 0.8), (2.0, -1.3), (5.0, 0.3)]:
        ns, _ = step_jit(make_state(tau, sd), P.arrays())
        wall = 0.0 if sd > 0 else -1.0
        ref = first_root(tau, wall, -P.r * sd, P.alpha, P.beta, P.gamma, t_hi=20, n=4000)
        assert abs(float(ns.tau) - (tau + float(ref[0]))) < 5e-15
        assert abs(float(ns.sdot) - float(ref[2])) < 5e-15


def test_fig2_is_periodic_fig3_is_not():
    """Paper Fig. 2 (alpha = 0.5): a periodic impact sequence (3 impacts per driving period);
    Fig. 3 (alpha = 3): no period up to 12 impacts.

    After 540 impacts the Fig. 2 orbit has converged to rounding: its 3-periodic velocities repeat to
    5.6e-16 (bound 4e-15, ~9 ulp of |sdot| < 2), every other shift differs by 1.36; three impacts
    take 2 pi to the rounding of the elapsed tau ~ 1260 (measured 2.1e-13 = 0.9 ulp; bound 4 ulp).
    The Fig. 3 orbit (last 500 of 600 impacts) differs from each of its shifts by at least 3.35 (bound 1)."""
    o2 = map_orbit(Params(0.5, 0.1, 0.1, 0.9), 0.0, 0.5, 600)
    tau, th, sd, w = o2.impact_arrays()
    tail = slice(-60, None)
    periods = [p for p in range(1, 13) if np.max(np.abs(sd[tail][p:] - sd[tail][:-p])) <= 4e-15]
    assert periods and periods[0] == 3
    assert np.all(np.abs(np.diff(tau[-61::3]) - 2 * np.pi) <= 4 * np.spacing(tau[-1]))
    o3 = map_orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 600)
    sd3 = o3.impact_arrays()[2][-500:]
    for p in range(1, 13):
        assert np.max(np.abs(sd3[p:] - sd3[:-p])) > 1.0


def test_chatter_ends_in_sticking_and_release_at_force_zero():
    """alpha = 2, gamma = 1, r = 0.5: bounces accumulate at a wall, the tooth sticks, and it is
    released where the contact force f changes sign (upper wall: f decreasing through 0; lower
    wall: f increasing through 0).  f vanishes at the release times to the rounding of the elapsed
    tau (up to 38 here): |df/dtau| <= R = alpha sqrt(1 + beta^2) = 2.01 times ulp(tau) <= 7.1e-15;
    bound 4 R ulp(tau), measured 1.0e-14 = 0.7 R ulp(38)."""
    P = Params(2.0, 0.1, 1.0, 0.5)
    o = map_orbit(P, 0.0, 0.5, 150)
    assert o.status == "active"
    assert o.n_sticking >= 3
    rel = o.kind == "release"
    f = np.asarray(forcing(o.tau[rel], P.alpha, P.beta, P.gamma))
    df = np.asarray(forcing_rate(o.tau[rel], P.alpha, P.beta))
    direction = np.where(o.wall[rel] == 0, 1.0, -1.0)
    R = P.alpha * np.hypot(1.0, P.beta)
    assert np.all(np.abs(f) <= 4 * R * np.spacing(np.abs(o.tau[rel]))) and np.all(direction * df < 0)
    # time increases through every event; sticking happens at the wall of the impact before it
    assert np.all(np.diff(o.tau) >= 0)
    for i in np.flatnonzero(o.kind == "stick"):
        assert o.kind[i - 1] == "impact" and o.wall[i] == o.wall[i - 1]
        assert 0 <= o.tau[i] - o.tau[i - 1] <= STICK_TIME


def test_sticking_policy_threshold():
    """Slow impact into a pressing wall: sticks iff the accumulation time 2u/((1-r) f) <= STICK_TIME."""
    P = Params(3.0, 0.1, 0.1, 0.9)
    theta = 4.0  # f(4) ~ 2.17 > 0: presses into s = 0
    f = float(forcing(theta, P.alpha, P.beta, P.gamma))
    u_crit = STICK_TIME * (1 - P.r) * f / 2
    for sdot, expect in [(0.5 * u_crit / P.r, True), (2.0 * u_crit / P.r, False)]:
        _, info = step_jit(make_state(theta, sdot), P.arrays())
        assert bool(info.stuck) == expect


def test_terminal_states_do_not_loop():
    # |gamma| > alpha sqrt(1+beta^2): the force never changes sign -> chatter, stick, stuck forever
    o = map_orbit(Params(0.5, 0.1, 0.9, 0.5), 0.0, 0.5, 200)
    assert o.status == "stuck_forever"
    # alpha = gamma = 0: coasts to rest inside the gap -> no further impact
    s, _ = step_jit(make_state(0.0, 0.01), Params(0.0, 0.1, 0.0, 0.9).arrays())
    assert int(s.status) == Status.NO_IMPACT
    assert int(step_jit(s, Params(0.0, 0.1, 0.0, 0.9).arrays())[0].status) == Status.NO_IMPACT


def test_release_delay_closed_form():
    """Release of a stuck tooth where the contact force f = gamma - R sin(tau - phi) of Eq. (3) changes
    sign (closed form): |f| at the release <= 1e-14 (measured 1.7e-15: |df/dtau| <= R = 1.02 times the
    ulp of a phase < 12.5, 1.8e-15), and f > 0 strictly before it (measured min 2.4e-4 on the grid)."""
    P = Params(1.0, 0.2, 0.3, 0.8)
    for wall in (0, -1):
        d = wall and -1 or 1
        for th in np.linspace(0, 6.2, 7):
            dl = float(release_delay(th, wall, P.alpha, P.beta, P.gamma))
            grid = th + np.linspace(0, dl, 2000)[1:-1]
            f = d * np.asarray(forcing(grid, P.alpha, P.beta, P.gamma))
            fr = d * float(forcing(th + dl, P.alpha, P.beta, P.gamma))
            assert abs(fr) < 1e-14
            if d * float(forcing(th, P.alpha, P.beta, P.gamma)) > 0:
                assert np.all(f > 0)  # still pressing until the release


def test_batch_equals_single():
    """The vmapped batch gives the single-orbit numbers to rounding: one step from the same states
    agrees to a few ulps (XLA compiles the vmapped and the scalar kernel separately, so bitwise
    equality is not promised; bound 8e-16 relative = 3.6 ulp, measured 2.2e-16), and a non-chaotic
    orbit (Fig. 2 parameters) on its attractor, where it contracts, keeps that per-step level after 40
    impacts (bound 4e-15, ~9 ulp of |sdot| < 2; measured 8.9e-16, amplification of a perturbation over
    those impacts at most 1.45).  The states are settled first (200 impacts): the transients from the
    random states amplify an ulp up to ~2800-fold within 40 impacts, so they test the orbit, not the
    batch."""
    P = Params(3.0, 0.1, 0.1, 0.9)
    rng = np.random.default_rng(1)
    tau, sd = rng.uniform(0, 6.28, 64), rng.uniform(0.05, 0.5, 64) * rng.choice([-1, 1], 64)
    tr = batch_iterate(states(tau, sd), P.arrays(), 1)
    for i in range(0, 64, 7):
        o = map_orbit(P, tau[i], sd[i], 1)
        assert int(tr.states.wall[i, 0]) == o.wall[-1]
        assert abs(float(tr.states.tau[i, 0]) - o.tau[-1]) <= 8e-16 * max(1.0, abs(o.tau[-1]))
        assert abs(float(tr.states.sdot[i, 0]) - o.sdot[-1]) <= 8e-16 * max(1.0, abs(o.sdot[-1]))
    P2 = Params(0.5, 0.1, 0.1, 0.9)
    settled = [map_orbit(P2, tau[i], abs(sd[i]), 200).impact_arrays() for i in range(4)]
    th0, sd0 = np.array([s[1][-1] for s in settled]), np.array([s[2][-1] for s in settled])
    tr2 = batch_iterate(states(th0, sd0), P2.arrays(), 40)
    for i in range(4):
        o = map_orbit(P2, th0[i], sd0[i], 40)
        assert np.max(np.abs(np.asarray(tr2.states.sdot[i]) - o.impact_arrays()[2][1:])) <= 4e-15


def test_free_flight_start():
    """First impact from a free-flight state (Eqs. 7-8) against the 50-digit root: measured 2.2e-16,
    bound 4e-15 (a few ulp of tau < 4)."""
    P = Params(3.0, 0.1, 0.1, 0.9)
    o = map_orbit(P, 0.3, -0.2, 5, s0=-0.4)
    ref = first_root(0.3, -0.4, -0.2, P.alpha, P.beta, P.gamma, t_hi=20, n=4000)
    assert abs(o.tau[0] - (0.3 + float(ref[0]))) < 4e-15
    assert o.wall[0] == ref[1]


@pytest.mark.parametrize(
    "bad", [dict(alpha=-1), dict(beta=0), dict(beta=float("inf")), dict(r=0), dict(r=1.01), dict(gamma=float("nan"))]
)
def test_bad_params(bad):
    base = dict(alpha=3.0, beta=0.1, gamma=0.1, r=0.9)
    base.update(bad)
    name = next(iter(bad))
    with pytest.raises(ValueError, match=f"parameter {name}="):
        Params(**base)


def test_bad_initial_state():
    P = Params(3.0, 0.1, 0.1, 0.9)
    with pytest.raises(ValueError, match="sdot0"):
        map_orbit(P, 0.0, 0.0, 5)
    with pytest.raises(ValueError, match="s0"):
        map_orbit(P, 0.0, 0.1, 5, s0=0.5)
    with pytest.raises(ValueError, match="n_impacts"):
        map_orbit(P, 0.0, 0.1, -1)


def test_phase_kept_for_long_orbits():
    """tau mod 2 pi comes from the reduced phase, not from the large elapsed time: the whole turns never
    enter the phase arithmetic, so the phase after one step is bitwise the same with 10^7 turns."""
    P = Params(0.5, 0.1, 0.1, 0.9)
    s = make_state(1.0, 0.5)._replace(cycles=jnp.asarray(10**7, jnp.int64))
    ns, _ = step_jit(s, P.arrays())
    assert int(ns.cycles) >= 10**7
    ns0, _ = step_jit(make_state(1.0, 0.5), P.arrays())
    assert float(ns.theta) == float(ns0.theta)


def test_periodic_orbit_walls_align_with_states():
    """PeriodicOrbit.walls[k] is the wall hit by the pre-impact state (tau[k], sdot[k])."""
    from gear_rattle.mapimpl.periodic import find_periodic

    P = Params(0.5, 0.1, 0.1, 0.9)
    o = map_orbit(P, 0.0, 0.5, 300)
    _, th, sd, _ = o.impact_arrays()
    po = find_periodic(P, th[-3], sd[-3], 3)
    assert po.converged
    assert np.array_equal(po.walls, np.where(po.sdot > 0, 0, -1))


def test_newton_stops_when_landed_on_the_root():
    """The root polish stops once the Newton correction is below rounding (no bisection fallback):
    the impact is found in few safe steps and matches the 50-digit root of Eqs. (7)-(8) to a few ulp
    (t = 0.254, ulp 5.6e-17; measured 1 ulp, bound 4 ulp)."""
    from gear_rattle.mapimpl.finder import first_impact

    h = jax.jit(first_impact)(4.0, 0.0, -0.3, 3.0, 0.1, 0.1)
    ref = first_root(4.0, 0.0, -0.3, 3.0, 0.1, 0.1, t_lo=1e-4, t_hi=1.0, n=2000)
    assert abs(float(h.t) - float(ref[0])) <= 4 * np.spacing(float(ref[0]))
