"""Long runs on the command line: an orbit computed in chunks is bitwise one scan and compiles once,
Ctrl-C stops it at once, progress draws only on a terminal, and the dense flights of a plot compile
once (first written for issue 11, items 3, 9 and 10)."""

import _thread
import io
import threading
import time

import numpy as np
import pytest

from gear_rattle.core.params import Params
from gear_rattle.validation.cli import main


def run_cli(args, capsys):
    try:
        rc = main(args)
    except SystemExit as e:  # refused while parsing: argparse exits with status 2
        rc = e.code
    out = capsys.readouterr()
    return rc, out.out, out.err


# --------------------------------------------------------- item 3: map_orbit in chunks, Ctrl-C


def _same(a, b):
    for f in ("n", "tau", "theta", "wall", "sdot", "kind"):
        x, y = getattr(a, f), getattr(b, f)
        assert x.dtype == y.dtype and x.shape == y.shape, f
        if x.dtype.kind == "f":
            assert np.array_equal(x.view(np.int64), y.view(np.int64)), f  # bitwise, NaNs included
        else:
            assert np.array_equal(x, y), f
    assert a.status == b.status


def test_chunked_orbit_is_bitwise_one_scan():
    """Chunks of 32 impacts give bitwise the orbit of one scan (here the 1024-long scan truncated to
    the orbit), for a chaotic orbit (Fig. 3) and one with sticking episodes (stick/release rows)."""
    from gear_rattle.mapimpl.orbit import map_orbit

    for p, n in ((Params(3.0, 0.1, 0.1, 0.9), 100), (Params(2.0, 0.1, 1.0, 0.5), 120)):
        one = map_orbit(p, 0.0, 0.5, n)
        chunked = map_orbit(p, 0.0, 0.5, n, chunk=32)  # 4 chunks of the short-run length
        _same(one, chunked)
    assert "stick" in set(chunked.kind) and "release" in set(chunked.kind)


def test_chunked_orbit_compiles_once_and_stops_when_ended():
    from gear_rattle.mapimpl.orbit import _iterate_jit, map_orbit

    P = Params(3.0, 0.1, 0.1, 0.9)
    map_orbit(P, 0.0, 0.5, 100)
    size = _iterate_jit._cache_size()
    a = map_orbit(P, 0.1, 0.4, 2500)  # other length, other state: no new compilation
    assert _iterate_jit._cache_size() == size and len(a.n) == 2501
    stuck = Params(0.5, 0.1, 0.9, 0.5)  # gamma > R: chatter, then stuck forever
    t0 = time.perf_counter()
    s = map_orbit(stuck, 0.0, 0.5, 1_000_000)  # ends after ~20 impacts: not a million steps
    assert s.status == "stuck_forever" and len(s.n) < 100
    assert time.perf_counter() - t0 < 30  # 0.01 s measured with both cores busy: a guard, not a timing
    _same(s, map_orbit(stuck, 0.0, 0.5, 200))


@pytest.mark.parametrize("track", ["map", "diffrax"])
def test_ctrl_c_stops_a_long_simulate_at_once(track, tmp_path, capsys):
    """Ctrl-C took ~27 s to act (one XLA call for the whole orbit). Now it acts between chunks of
    1024 impacts: one line, exit 130, no output file.  The orbit asked for (5e6 impacts) would take
    minutes in one call; the bound below is ~20 chunk times even on a loaded machine.  Measured
    2026-11-25 with both cores busy (two spinning processes besides three other sessions' work):
    0.011-0.019 s over three interrupts, so the 5 s bound has a margin of > 200x.  The diffrax track
    (issue 23 item 3: one XLA call for the whole orbit, 100000 impacts took 55 s to act) runs in chunks
    of 256 impacts the same way (core.state.run_in_chunks)."""
    from gear_rattle.mapimpl.tracks import orbit

    orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 300, track=track)  # compile first: measure the run, not XLA
    out = tmp_path / "long.csv"
    fired = []

    def interrupt():
        fired.append(time.perf_counter())
        _thread.interrupt_main()

    timer = threading.Timer(1.5, interrupt)
    timer.start()
    try:
        rc = main(["simulate", "--track", track, "--impacts", "5000000", "--output", str(out)])
    finally:
        timer.cancel()
    latency = time.perf_counter() - fired[0]
    err = capsys.readouterr().err
    assert rc == 130
    assert err.strip() == "gear-rattle simulate: interrupted"
    assert not out.exists()
    assert latency < 5.0, f"Ctrl-C acted after {latency:.1f} s"


# ------------------------------------------------------------------------ item 9: progress


class FakeStream(io.StringIO):
    def __init__(self, tty):
        super().__init__()
        self.tty = tty

    def isatty(self):
        return self.tty


def test_progress_only_on_a_terminal_labelled(monkeypatch):
    """A bar draws only on a terminal (a log file or pipe gets nothing), always with its label, and a
    phase (compiling) shows the label and the time until the first count."""
    from gear_rattle.core.progress import Bar

    pipe = FakeStream(False)
    monkeypatch.setattr("sys.stderr", pipe)
    with Bar("work", total=10, unit="tiles") as bar:
        bar.update(5)
        bar(10, 10)
    assert pipe.getvalue() == "" and not bar.drawn
    tty = FakeStream(True)
    monkeypatch.setattr("sys.stderr", tty)
    bar = Bar("work", unit="tiles", phase="compiling")
    assert bar.drawn and tty.getvalue().lstrip("\r").startswith("work (compiling) 00:00")
    bar.update(3, 10)
    bar.update(10)
    bar.close()
    last = tty.getvalue().split("\r")[-1]
    assert last.startswith("work: 100%") and "10/10" in last and last.endswith("\n") and "nan" not in last
    quiet = FakeStream(True)
    monkeypatch.setattr("sys.stderr", quiet)
    Bar("work", total=3, enabled=False).close()
    assert quiet.getvalue() == ""
    with pytest.raises(ValueError, match="label"):
        Bar("", True)


# ------------------------------------------------------------ item 10: dense, one compilation


def test_dense_compiles_once_for_every_flight():
    """simulate --plot compiled `flight` anew for every flight length (35 s for 50 time units);
    the padded kernel compiles once for every orbit, span and parameter set, and gives the
    closed form (Eqs. 7-8) of each flight."""
    import jax.numpy as jnp

    from gear_rattle.mapimpl import dense as D
    from gear_rattle.mapimpl.flight import flight
    from gear_rattle.mapimpl.orbit import map_orbit

    a = map_orbit(Params(3.0, 0.1, 0.1, 0.9), 0.0, 0.5, 40)
    b = map_orbit(Params(2.0, 0.1, 1.0, 0.5), 0.0, 0.5, 60)  # sticking rows
    tau, s, v = D.dense(a, points_per_unit=60.0, t_end=a.tau[0] + 20.0)
    size = D._flight_block._cache_size()
    D.dense(a, points_per_unit=37.0)
    tb, sb, vb = D.dense(b, points_per_unit=60.0)
    assert D._flight_block._cache_size() == size == 1
    assert np.all(np.diff(tau) >= 0) and np.all((s >= -1) & (s <= 0))
    assert np.all((sb >= -1) & (sb <= 0))
    # one flight of a, sampled by dense, against the eager closed form
    t0, t1 = a.tau[3], a.tau[4]
    m = (tau > t0) & (tau < t1)
    fp = flight(jnp.asarray(tau[m] - t0), np.mod(t0, 2 * np.pi), -a.params.r * a.sdot[3], 3.0, 0.1, 0.1)
    assert np.max(np.abs(s[m] - np.clip(a.wall[3] + np.asarray(fp.ds), -1, 0))) < 1e-13
    assert np.max(np.abs(v[m] - np.asarray(fp.v))) < 1e-13
    # every event time is a sample, at its wall
    inside = a.tau < a.tau[0] + 20.0
    assert inside.sum() >= 5
    for t, w in zip(a.tau[inside], a.wall[inside]):
        k = np.flatnonzero(tau == t)
        assert k.size and np.all(s[k] == w)
