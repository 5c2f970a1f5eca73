"""The many-orbit engine (mapimpl/engine): one micro-step equals one map step (Eqs. 11-13 with the
sticking policy), determinism over lanes/devices/compaction (issue 10 item 4), the canonical release
(issue 10 item 3: composed durations equal followed ones), the observers, early exit, Ctrl-C."""

import threading
import time

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from gear_rattle.mapimpl.engine.options import Execution
from gear_rattle.mapimpl import Params
from gear_rattle.core.params import ParamArrays
from gear_rattle.mapimpl.engine import kernel as K
from gear_rattle.mapimpl.engine.driver import run
from gear_rattle.mapimpl.engine.observers import (
    BandEscape,
    Capture,
    Impact,
    Laminar,
    Sample,
    Tangent,
    givens_qr,
    orbit_distance,
)
from gear_rattle.mapimpl.engine.transients import grid, periodic_target, transient_times
from gear_rattle.core.paper import PAPER_PARAMS
from gear_rattle.mapimpl.impact_map import iterate
from gear_rattle.core.state import make_state
from gear_rattle.core.status import Status

P = PAPER_PARAMS
LANES = 64  # one kernel shape for most engine tests (one compilation)


@pytest.fixture(scope="module")
def target():
    return periodic_target(P)


def _ref_states(params, tau0, sdot0, n):
    tr = jax.jit(iterate, static_argnums=2)(make_state(tau0, sdot0), params.arrays(), n)
    th = np.concatenate([[tau0 % (2 * np.pi)], np.asarray(tr.states.theta)])
    sd = np.concatenate([[sdot0], np.asarray(tr.states.sdot)])
    w = np.concatenate([[0 if sdot0 > 0 else -1], np.asarray(tr.states.wall)])
    cyc = np.concatenate([[0], np.asarray(tr.states.cycles)])
    return th, sd, w, cyc, np.asarray(tr.infos.stuck)


def _queue(th, sd, w, params, n_ic=None):
    return K.prepare_queue(jnp.asarray(th), jnp.asarray(sd), jnp.asarray(w, jnp.int32), params.arrays(), n_ic=n_ic)


@pytest.mark.parametrize("tau0,sdot0", [(3.1, 0.2), (3.4, 0.01), (3.29, 0.0568)])
def test_micro_steps_equal_the_map_step(tau0, sdot0):
    """One engine map iteration from every state of a 200-impact reference orbit
    (mapimpl.impact_map.step, Eqs. 11-13), sticking episodes included, agrees to 1e-13."""
    th, sd, w, _, stuck = _ref_states(P, tau0, sdot0, 200)
    k = K.make_consts(10**6, ())
    q = _queue(th[:-1], sd[:-1], w[:-1], P)
    one = jax.jit(jax.vmap(lambda st, par: K.trace(q._replace(start=st, par=par, n_ic=1), k, 1)))
    first = lambda tree: jax.tree_util.tree_map(lambda x: x[:, None], tree)  # noqa: E731  (one-orbit queues)
    h = np.asarray(one(first(q.start), first(q.par)))
    dth = np.abs(np.angle(np.exp(1j * (h[:, 1, 0] - th[1:]))))
    assert np.all(h[:, 1, 2] == w[1:])
    assert dth.max() < 1e-13 and np.abs(h[:, 1, 1] - sd[1:]).max() < 1e-13
    if tau0 == 3.4:
        assert stuck.any()  # the comparison covers sticking steps


def test_engine_states_and_turns_equal_the_map_orbit():
    """Sample observer: the engine's pre-impact states (theta, sdot, wall, cycles) of a 40-impact orbit
    equal the map's (the orbit is chaotic: ulp-level differences grow ~10x per 3 impacts, so the first
    10 impacts agree to 1e-13 and all 40 to 1e-6) and exactly in walls and turns; the final state too."""
    th, sd, w, cyc, _ = _ref_states(P, 3.2, 0.3, 40)
    r = run([3.2], [0.3], [0], P, Sample(keep=41), cap=40, execution=Execution(lanes=8, devices=1), progress=False)
    s = r.obs[0]
    dth = np.abs(np.angle(np.exp(1j * (s["theta"][0] - th))))
    dsd = np.abs(s["sdot"][0] - sd)
    assert dth[:11].max() < 1e-13 and dsd[:11].max() < 1e-13
    assert dth.max() < 1e-6 and dsd.max() < 1e-6
    assert np.array_equal(s["wall"][0], w) and np.array_equal(s["cycles"][0], cyc)
    assert int(r.n[0]) == 40 and int(r.cycles[0]) == int(cyc[-1]) and int(r.status[0]) == Status.STOPPED


def test_results_do_not_depend_on_lanes_devices_chunks_or_compaction(target, monkeypatch):
    """Each orbit's arithmetic is its own (issue 10 item 4): 1 lane (padded to a lane quantum), 64 and
    256 lanes, one or two devices, small chunks and the tail compaction (256 lanes -> 32 once the queue
    is empty) leave every result bit-identical."""
    rng = np.random.default_rng(3)
    tau0, sdot0 = rng.uniform(3.0, 3.5, 300), rng.uniform(1e-6, 0.5, 300)
    kw = dict(cap=8000, progress=False, target=target)
    ref = transient_times(None, tau0, sdot0, execution=Execution(lanes=LANES, devices=1), **kw)
    sizes = []
    compact = K.compact
    monkeypatch.setattr(K, "compact", lambda lanes, size: (sizes.append(size), compact(lanes, size=size))[1])
    runs = [
        transient_times(None, tau0, sdot0, execution=Execution(lanes=256, devices=1), **kw),
        transient_times(None, tau0, sdot0, execution=Execution(lanes=1, devices=1, chunk=100), **kw),
    ]
    assert 32 in sizes  # the tail ran on 32 lanes
    if len(jax.devices()) >= 2:
        runs.append(transient_times(None, tau0, sdot0, execution=Execution(lanes=LANES, devices=2), **kw))
    for r in runs:
        for name in ("hit", "n", "status", "nstick", "first_stick"):
            assert np.array_equal(getattr(r, name), getattr(ref, name)), name
        assert all(np.array_equal(r.duration(d)[0], ref.duration(d)[0]) for d in ref.deltas)  # composed too
    assert (ref.status == Status.CAPPED).any() and (ref.status == Status.STOPPED).any()  # censored and finished


def test_single_orbit_equals_batch(target):
    """A queue of one orbit (the block is padded to LANE_QUANTUM lanes) gives the same duration as the
    same orbit in a batch: (3.2, 0.3) was 4666 vs 364 before the padding."""
    one = transient_times(None, [3.2], [0.3], execution=Execution(lanes=1, devices=1), progress=False, target=target)
    many = transient_times(
        None, [3.2] * 3, [0.3] * 3, execution=Execution(lanes=LANES, devices=1), progress=False, target=target
    )
    assert np.array_equal(one.hit[0], many.hit[0]) and np.array_equal(many.hit[0], many.hit[2])
    assert one.duration()[0][0] == many.duration()[0][0] == many.duration()[0][2]  # hit is raw: the durations too


def test_composed_release_equals_following_every_orbit(target):
    """Issue 10 item 3: every orbit that sticks is released at the canonical phase with sdot = 0 and so
    continues on one post-release orbit; stopping at the first stick and adding that orbit's duration
    gives bit-identical durations (Fig. 11 setting, ICs near sdot0 = 0 that chatter and stick)."""
    T, S = grid(nx=12, ny=12, box=(3.0, 3.5, 0.0, 0.1))
    kw = dict(cap=20000, execution=Execution(lanes=LANES, devices=1), progress=False, target=target)
    comp = transient_times(None, T.ravel(), S.ravel(), sticking="compose", **kw)
    foll = transient_times(None, T.ravel(), S.ravel(), sticking="follow", **kw)
    assert comp.n_stuck_orbits >= 10 and comp.post_release and comp.post_release[0].wall == 0
    assert all(np.array_equal(comp.duration(d)[0], foll.duration(d)[0]) for d in comp.deltas)
    assert np.array_equal(comp.status, foll.status)
    assert comp.impacts < foll.impacts
    # the engine returns raw facts: an orbit that stuck before capture has no hit of its own, and its
    # duration is first_stick + T_post (one post-release orbit)
    st = comp.first_stick >= 0
    tp = int(comp.post_release[0].t_post[comp.column()])
    late = comp.composed() & st
    assert late.any() and np.all(comp.hit[late, comp.column()] == -1)
    assert np.all(comp.duration()[0][late] == comp.first_stick[late] + tp)
    # another T_post (e.g. a certified one) replaces the float64 one for exactly those orbits
    from gear_rattle.mapimpl.engine.release import TPost, ReleaseSource, WallTPost

    seven = TPost(ReleaseSource.CERTIFIED, comp.delta, {0: WallTPost(0, 7, ReleaseSource.CERTIFIED, tp)})
    d2, _ = comp.duration(release=seven)
    assert np.all(d2[late] == comp.first_stick[late] + 7) and np.array_equal(d2[~late], comp.duration()[0][~late])
    with pytest.warns(DeprecationWarning, match="t_post"):
        assert np.array_equal(comp.duration(t_post={0: 7})[0], d2)


def test_early_exit_and_refill():
    """The block loop stops as soon as the queue is done, long before max_blocks; padded queue entries
    beyond n_ic are never loaded."""
    m = 40
    q = _queue(np.full(64, 3.2), np.full(64, 0.3), np.zeros(64, np.int32), P, n_ic=m)
    k = K.make_consts(5, ())
    carry = (K.idle_lanes(8, ()), K.empty_results(64, ()), jnp.asarray(0, jnp.int32))
    (lanes, res, nxt), nb = K.run_blocks(carry, q, k, (), block=32, max_blocks=64)
    assert int(nxt) == m and bool(jnp.all(lanes.mode == K.MODE_IDLE))
    assert 1 <= int(nb) < 64  # 40 orbits of 5 impacts on 8 lanes: a few blocks
    st = np.asarray(res.status)
    assert np.all(np.asarray(res.n)[:m] == 5) and np.all(st[:m] == Status.CAPPED)
    assert np.all(st[m:] == Status.NOT_RUN)


def test_compact_keeps_busy_lanes_in_order():
    lanes = K.idle_lanes(8, ())._replace(
        mode=jnp.array(
            [K.MODE_IDLE, K.MODE_A, K.MODE_IDLE, K.MODE_N, K.MODE_IDLE, K.MODE_IDLE, K.MODE_B, K.MODE_IDLE], jnp.int32
        ),
        ic=jnp.array([-1, 5, -1, 2, -1, -1, 9, -1], jnp.int32),
    )
    out = K.compact(lanes, size=4)
    assert out.mode.shape == (4,)
    assert np.asarray(out.ic).tolist() == [5, 2, 9, -1]
    assert np.asarray(out.mode).tolist() == [K.MODE_A, K.MODE_N, K.MODE_B, K.MODE_IDLE]


def test_per_orbit_parameters_equal_separate_runs():
    """Lanes carry their own parameters: one run over two parameter sets equals two runs.  Sample(keep=41)
    and cap=40 as in test_engine_states_and_turns_equal_the_map_orbit: the separate runs reuse its kernel."""
    pa = Params(3.0, 0.1, 0.1, 0.8)
    both = run(
        [3.2, 3.2],
        [0.3, 0.3],
        [0, 0],
        ParamArrays(alpha=[3.0, 1.245], beta=0.1, gamma=0.1, r=[0.8, 0.9]),
        Sample(keep=41),
        cap=40,
        execution=Execution(lanes=8, devices=1),
        progress=False,
    )
    for i, p in enumerate((pa, P)):
        one = run(
            [3.2], [0.3], [0], p, Sample(keep=41), cap=40, execution=Execution(lanes=8, devices=1), progress=False
        )
        assert np.array_equal(both.obs[0]["theta"][i], one.obs[0]["theta"][0])


def test_parameters_keep_one_form_down_to_the_lanes():
    """Issue 32 item 2: the queue and every lane carry the caller's ParamArrays (the field names of
    Params) with the release constants beside them, not renamed keys or positional arguments."""
    pa = ParamArrays(jnp.array([3.0, 1.245]), jnp.full(2, 0.1), jnp.full(2, 0.1), jnp.array([0.8, 0.9]))
    q = K.prepare_queue(jnp.array([3.2, 3.3]), jnp.array([0.3, -0.2]), jnp.array([0, -1], jnp.int32), pa)
    assert isinstance(q.par.params, ParamArrays) and q.par.params._fields == tuple(vars(P))
    assert all(np.array_equal(x, y) for x, y in zip(q.par.params, pa)) and int(q.n_ic) == 2
    lanes = K.idle_lanes(8, ())
    assert isinstance(lanes.par.params, ParamArrays) and lanes.par.params.alpha.shape == (8,)
    assert lanes.par.top._fields == ("phase", "sin", "cos", "never") and lanes.at.theta.dtype == jnp.float64


def test_interrupt_stops_every_device_thread_promptly(target):
    """Ctrl-C (KeyboardInterrupt in the main thread) stops the engine within a kernel call or two.
    Latency from the interrupt to the exception, measured 2026-11-25 with both cores busy (two
    spinning processes besides other work): 0.14-0.22 s over three runs; the bound is 15 s."""
    import _thread

    rng = np.random.default_rng(4)
    tau0, sdot0 = rng.uniform(3.0, 3.5, 4000), rng.uniform(0.2, 0.5, 4000)
    fired = threading.Event()
    t_int = []

    def progress(done, total):
        if not fired.is_set():
            fired.set()
            t_int.append(time.perf_counter())
            _thread.interrupt_main()

    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        run(
            tau0,
            sdot0,
            np.zeros(4000, np.int32),
            P,
            Capture(target.theta, target.sdot, target.wall, [1e-3]),
            cap=10**7,
            execution=Execution(lanes=LANES),
            progress=progress,
        )
    assert fired.is_set()
    # a full run of these orbits (cap 1e7) takes minutes; the stop comes within a few kernel calls
    assert time.perf_counter() - t_int[0] < 15.0, time.perf_counter() - t0
    assert not any(t.name.startswith("ThreadPoolExecutor") and t.is_alive() for t in threading.enumerate())


# ------------------------------------------------------------------------------------ observers


def _ev(n, theta=0.0, sdot=0.5, wall=0, cycles=0, dt=1.0, loaded=False, stick=False, jac=None):
    return Impact(
        jnp.asarray(n, jnp.int32),
        jnp.asarray(theta),
        jnp.asarray(sdot),
        jnp.asarray(wall, jnp.int32),
        jnp.asarray(cycles, jnp.int32),
        jnp.asarray(dt),
        jnp.asarray(loaded),
        jnp.asarray(stick),
        None if jac is None else jnp.asarray(jac),
        jnp.asarray(not loaded),
    )


def _init(obs):
    return {k: jnp.broadcast_to(jnp.asarray(v, dt), shape) for k, (dt, shape, v) in obs.fields().items()}


def test_orbit_distance_wraps_phase_and_requires_the_wall():
    d = orbit_distance(
        jnp.asarray(6.28),
        jnp.asarray(0.5),
        jnp.asarray(0, jnp.int32),
        jnp.asarray([0.001, 3.0]),
        jnp.asarray([0.5, 0.5]),
        jnp.asarray([0, -1], jnp.int32),
    )
    assert abs(float(d) - (2 * np.pi - 6.28 + 0.001)) < 1e-15
    d2 = orbit_distance(
        jnp.asarray(3.0),
        jnp.asarray(0.5),
        jnp.asarray(0, jnp.int32),
        jnp.asarray([3.0]),
        jnp.asarray([0.5]),
        jnp.asarray([-1], jnp.int32),
    )
    assert float(d2) == np.inf


def test_capture_records_first_hits_and_stops_at_the_smallest_delta():
    c = Capture([1.0], [0.5], [0], [1e-2, 1e-4])
    o, k = _init(c), c.consts()
    o, stop = c.update(o, _ev(3, theta=1.005), k)
    assert np.asarray(o["hit"]).tolist() == [3, -1] and not bool(stop)
    o, stop = c.update(o, _ev(4, theta=1.00001), k)
    assert np.asarray(o["hit"]).tolist() == [3, 4] and bool(stop)


def test_band_escape_counts_bursts_after_enough_impacts_inside():
    """r1 (Fig. 7): p = 2 bands visited once per period; a burst is a 2-impact return time off 2 pi by
    more than the threshold after >= min_inside impacts in."""
    b = BandEscape(p=2, m=1, threshold=0.5, min_inside=3)
    o, k = _init(b), b.consts()
    dts = [np.pi] * 8 + [np.pi + 1.0] + [np.pi] * 2 + [np.pi + 1.0] + [np.pi] * 8 + [np.pi + 2.0]
    for i, dt in enumerate(dts, start=1):
        o, _ = b.update(o, _ev(i, dt=dt), k)
    # out-of-band return times at impacts 9, 10 (the window still holds the long one), 12, 13 and 21;
    # bursts only at 9 and 21: at 12 only 1 impact had been in since 10
    assert int(o["bursts"]) == 2 and int(o["first"]) == 9 and int(o["exposure"]) == len(dts)
    b1 = BandEscape(p=2, m=1, threshold=0.5, min_inside=3, stop_at_first=True)
    o1, k1 = _init(b1), b1.consts()
    stops = []
    for i, dt in enumerate(dts, start=1):
        o1, st = b1.update(o1, _ev(i, dt=dt), k1)
        stops.append(bool(st))
    assert stops.index(True) == 8  # impact 9


def test_laminar_counts_only_complete_phases():
    """Type-I intermittency (Figs. 5-6): runs near the orbit of length >= min_length that began after an
    impact outside; the run in progress at the start and at the end are not counted."""
    lam = Laminar([1.0], [0.5], eps=0.1, min_length=3)
    o, k = _init(lam), lam.consts()
    near = [1, 1, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 0, 1, 1, 1, 1, 1, 0, 1, 1, 1, 1]
    for i, nr in enumerate(near):
        o, _ = lam.update(o, _ev(i, theta=1.0 if nr else 2.0), k)
    assert int(o["count"]) == 2 and float(o["total"]) == 4 + 5 and float(o["total_sq"]) == 16 + 25
    # the stay in progress at the end (impacts 19-22): the report's settling runs read its start from it
    assert int(o["run"]) == 4 and "run" in lam.outputs()
    o, _ = lam.update(o, _ev(len(near), theta=2.0), k)
    assert int(o["run"]) == 0


def test_sample_keeps_a_window_and_stops_after_it():
    s = Sample(keep=3, n_start=2)
    o, k = _init(s), s.consts()
    stops = []
    for n in range(6):
        o, st = s.update(o, _ev(n, theta=0.1 * n, cycles=n), k)
        stops.append(bool(st))
    assert np.allclose(np.asarray(o["theta"]), [0.2, 0.3, 0.4]) and np.asarray(o["cycles"]).tolist() == [2, 3, 4]
    assert stops == [False, False, False, False, True, True]


def test_givens_qr_reconstructs_and_keeps_a_positive_diagonal():
    rng = np.random.default_rng(5)
    for _ in range(20):
        Z = rng.normal(size=(2, 2))
        Q, R = givens_qr(jnp.asarray(Z))
        Q, R = np.asarray(Q), np.asarray(R)
        assert np.allclose(Q @ R, Z, atol=1e-14) and np.allclose(Q.T @ Q, np.eye(2), atol=1e-14)
        assert abs(R[1, 0]) < 1e-15 and R[0, 0] >= 0 and R[1, 1] >= 0


def test_tangent_lyapunov_equals_the_qr_method_and_the_floquet_rate():
    """Fig. 4 at r = 0.8 (alpha = 3): a stable 6-impact period-1 orbit.  The engine's tangent
    accumulation equals an independent route -- the map's step Jacobians (mapimpl.impact_map.step) multiplied
    along the map's own orbit with Householder QR (jnp.linalg.qr) -- from the same state to 1e-9,
    approaches lambda1 = ln|m1| / 6 (Floquet multipliers of mapimpl.periodic) as O(1/N), and
    lambda1 + lambda2 = mean ln|det J| (closed form, docs/model.md) to rounding."""
    from gear_rattle.mapimpl.impact_map import step
    from gear_rattle.mapimpl.periodic import find_periodic

    p = Params(3.0, 0.1, 0.1, 0.8)
    th, sd, w, _, _ = _ref_states(p, 0.0, 0.5, 3000)
    po = find_periodic(p, th[-1], sd[-1], 6)
    N = 6000
    r = run(
        [th[-1]],
        [sd[-1]],
        [w[-1]],
        p,
        Tangent(n_start=0),
        cap=N,
        execution=Execution(lanes=8, devices=1),
        progress=False,
    )
    t = r.obs[0]
    lam = t["log_r"][0] / t["n_free"][0]
    assert int(t["n_free"][0]) == N and int(t["n_stuck"][0]) == 0

    def body(c, _):
        s, Q, acc = c
        s1, info = step(s, p.arrays())
        Qn, R = jnp.linalg.qr(info.jac @ Q)
        d = jnp.diagonal(R)
        return (s1, Qn * jnp.sign(d)[None, :], acc + jnp.log(jnp.abs(d))), None

    (_, _, acc), _ = jax.jit(lambda s0: jax.lax.scan(body, (s0, jnp.eye(2), jnp.zeros(2)), None, length=N))(
        make_state(th[-1], sd[-1])
    )
    assert np.abs(lam - np.asarray(acc) / N).max() < 1e-9
    m = np.sort(np.abs(po.multipliers))[::-1]
    assert np.all(np.abs(lam - np.log(m) / 6) < 5.0 / N)
    elapsed = 2 * np.pi * (r.cycles[0] - t["cycles0"][0]) + r.theta[0] - t["theta0"][0]
    det_mean = 2 * np.log(p.r) - p.beta * elapsed / N + np.log(abs(t["sdot0"][0] / r.sdot[0])) / N
    assert abs(lam.sum() - det_mean) < 1e-13


def test_bad_inputs_name_the_argument(target):
    with pytest.raises(ValueError, match="wall"):
        run([3.2], [0.3], [1], P, (), cap=10)
    with pytest.raises(ValueError, match="sdot"):
        run([3.2], [0.0], [0], P, (), cap=10)
    with pytest.raises(ValueError, match="cap"):
        run([3.2], [0.3], [0], P, (), cap=0)
    with pytest.raises(ValueError, match="r"):
        run([3.2], [0.3], [0], {"alpha": 1.0, "beta": 0.1, "gamma": 0.1, "r": 1.5}, (), cap=10)
    with pytest.raises(ValueError, match="release"):
        transient_times(None, [3.2], [0.3], release="skip", target=target)
    with pytest.raises(ValueError, match="deltas"):
        Capture([1.0], [0.5], [0], [-1.0])
    with pytest.raises(ValueError, match="keep"):
        Sample(keep=0)


def test_engine_xla_options_only_on_tested_jaxlib_and_can_be_turned_off(monkeypatch):
    """use_cpu_devices adds ENGINE_XLA_FLAGS only on the jaxlib versions they were tested with (XLA aborts
    on a flag it does not know) and not with GEAR_RATTLE_XLA_TUNING=0."""
    from gear_rattle.core import jax_config as J

    monkeypatch.delenv(J.XLA_TUNING_ENV, raising=False)
    monkeypatch.setattr(J, "jaxlib_version", lambda: J.ENGINE_XLA_TESTED[0])
    assert J.engine_xla_flags() == J.ENGINE_XLA_FLAGS
    monkeypatch.setenv(J.XLA_TUNING_ENV, "0")
    assert J.engine_xla_flags() == ()
    monkeypatch.delenv(J.XLA_TUNING_ENV)
    monkeypatch.setattr(J, "jaxlib_version", lambda: (99, 0))
    assert J.engine_xla_flags() == ()


def test_durations_without_the_xla_options_agree(target):
    """The engine compiled without ENGINE_XLA_FLAGS (a fresh process with GEAR_RATTLE_XLA_TUNING=0: XLA's
    default CPU emitters, the kernel's materialising barriers, 512-lane blocks) gives the same durations
    as this process: identical for the transients shorter than 40 impacts (no chaotic amplification of
    the ulp-level differences of fused multiply-adds) on random ICs of the Fig. 9 window, where the
    tongues of short transients are.  Both sides capture on this module's periodic target (sent to the
    command exactly: JSON floats round-trip), so the fresh process does not spend its time finding it."""
    import json
    import os
    import subprocess
    import sys

    from gear_rattle.core.jax_config import xla_tuning_active

    rng = np.random.default_rng(5)
    tau0, sdot0 = rng.uniform(0, 2 * np.pi, 800), rng.uniform(1e-3, 0.5, 800)
    code = (
        "import json, sys, numpy as np; import gear_rattle as gr; gr.use_cpu_devices(); "
        "from gear_rattle.core.jax_config import xla_tuning_active; "
        "from gear_rattle.mapimpl.engine.transients import PeriodicTarget, transient_times; "
        "t, s, th, sd, w, mr, mi, res = (np.array(x) for x in json.loads(sys.stdin.read())); "
        "tg = PeriodicTarget(th, sd, w.astype(np.int32), mr + 1j * mi, float(res)); "
        "r = transient_times(None, t, s, cap=200, progress=False, target=tg); "
        "print(json.dumps([xla_tuning_active(), r.duration()[0].tolist()]))"
    )
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    env["GEAR_RATTLE_XLA_TUNING"] = "0"
    proc = subprocess.run(
        [sys.executable, "-c", code],
        input=json.dumps(
            [tau0.tolist(), sdot0.tolist()]
            + [np.asarray(x).tolist() for x in (target.theta, target.sdot, target.wall)]
            + [target.multipliers.real.tolist(), target.multipliers.imag.tolist(), target.residual]
        ),
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    tuned_there, d_there = json.loads(proc.stdout)
    d_here = transient_times(None, tau0, sdot0, cap=200, progress=False, target=target).duration()[0]
    assert not tuned_there
    short = (d_here < 40) | (np.asarray(d_there) < 40)
    assert short.sum() >= 15 and np.array_equal(d_here[short], np.asarray(d_there)[short])
    if not xla_tuning_active():
        pytest.skip("this process runs without the XLA options too: compared like with like")
