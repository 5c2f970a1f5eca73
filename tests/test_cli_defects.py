"""The command-line defects a new user hit (issue 11), each reproduced here so that it cannot return.

Most checks fail while the arguments are parsed or validated, before any computation, so they run
in-process and fast; the few that compute use short orbits."""

import _thread
import argparse
import io
import threading
import time

import numpy as np
import pytest

from gear_rattle.core.params import Params
from gear_rattle.validation.cli import build_parser, main

COMMANDS_WITH_TAU0 = ("simulate", "bifurcation", "lyapunov", "timeseries", "orbit find")


def run_cli(args, capsys):
    try:
        rc = main(args)
    except SystemExit as e:  # refused while parsing: argparse exits with status 2
        rc = e.code
    out = capsys.readouterr()
    return rc, out.out, out.err


def assert_usage_error(args, capsys, *needles, absent=()):
    """Exit status 2, one line on stderr naming the option, no traceback."""
    rc, _, err = run_cli(args, capsys)
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err
    for n in needles:
        assert n in err, err
    for n in absent:
        assert n not in err, err
    return err


def subparsers():
    p = build_parser()
    sub = next(a for a in p._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices


# ------------------------------------------------------------------ item 2: the range of tau0

def test_library_rejects_tau0_out_of_range():
    from gear_rattle.mapimpl.orbit import initial_state, map_orbit

    P = Params(3.0, 0.1, 0.1, 0.9)
    for tau0 in (1e19, -1e300, 1e6 * (1 + 1e-15), float("nan"), float("inf")):
        with pytest.raises(ValueError, match=r"tau0=.*\|tau0\| <= 1e6"):
            initial_state(P, tau0, 0.5)
        with pytest.raises(ValueError, match="tau0"):
            initial_state(P, tau0, 0.5, s0=-0.5)
        with pytest.raises(ValueError, match="tau0"):
            map_orbit(P, tau0, 0.5, 3)
    st = initial_state(P, -1e6, 0.5)  # the boundary is allowed
    assert float(st.tau) == pytest.approx(-1e6, rel=1e-15)


@pytest.mark.parametrize("command", COMMANDS_WITH_TAU0)
@pytest.mark.parametrize("value", ["1e19", "1e300", "nan", "-inf"])
def test_every_command_rejects_tau0_out_of_range(command, value, capsys):
    """simulate --tau0 1e19 printed overflowed times with exit 0; now every command that takes
    --tau0 refuses it, naming the option and the range."""
    extra = ["--sdot0", "0.5"] if command == "orbit find" else []
    assert_usage_error([*command.split(), "--tau0", value, *extra], capsys, "--tau0", "1e6")


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


# ------------------------------------------------------------------- item 4: no tracebacks

@pytest.mark.parametrize("args,needle", [
    (["simulate", "--impacts", "99999999999999999999"], "--impacts"),
    (["orbit", "find", "--impacts", "99999999999999999999"], "--impacts"),
    (["simulate", "--impacts", "3", "--plot", "/proc/x.png"], "--plot"),
    (["bifurcation", "--values", "10", "--keep", "99999999"], "--keep"),
])
def test_no_traceback(args, needle, capsys):
    assert_usage_error(args, capsys, needle)


def test_report_out_is_a_file(tmp_path, capsys):
    f = tmp_path / "a-file"
    f.write_text("x")
    assert_usage_error(["report", "--out", str(f), "--sections", "timeseries"], capsys, "--out", "existing file")
    assert f.read_text() == "x"


def test_timeseries_too_short_for_a_period(capsys):
    """r = 0.5: 30 impacts chatter and stick within one forcing period: no stroboscopic sample."""
    assert_usage_error(["timeseries", "--r", "0.5", "--impacts", "20", "--transient", "10"], capsys,
                       "--impacts=20", "--transient=10")


def test_every_integer_option_has_an_upper_bound():
    """No integer option takes int() unbounded (99999999999999999999 ended in a JAX traceback)."""
    for name, sp in subparsers().items():
        for a in sp._actions:
            if a.type is int:
                assert a.choices, f"{name} {a.option_strings}: plain int without choices"
            if getattr(a.type, "__name__", "") == "integer":
                with pytest.raises(argparse.ArgumentTypeError, match="out of range"):
                    a.type("99999999999999999999")


# --------------------------------------------------------- item 5: outputs checked up front

def test_failed_plot_leaves_no_data_file(tmp_path, capsys):
    data, fig = tmp_path / "p.csv", tmp_path / "x.bogus"
    assert_usage_error(["simulate", "--impacts", "3", "--output", str(data), "--plot", str(fig)], capsys,
                       "--plot", "png")
    assert not data.exists() and not fig.exists()


@pytest.mark.parametrize("case", ["output-is-dir", "parent-is-file", "same-file", "plot-no-ext"])
def test_outputs_validated_before_computing(case, tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    args = {"output-is-dir": ["--output", str(tmp_path)],
            "parent-is-file": ["--output", str(f / "sub" / "o.csv")],
            "same-file": ["--output", str(tmp_path / "a.png"), "--plot", str(tmp_path / "a.png")],
            "plot-no-ext": ["--plot", str(tmp_path / "figure")]}[case]
    for command in ("simulate", "bifurcation", "lyapunov", "timeseries"):
        assert_usage_error([command, *args], capsys, "--output" if case != "plot-no-ext" else "--plot")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


@pytest.mark.parametrize("command", ["basins", "uncertainty", "transients"])
def test_transient_out_dir_checked_before_computing(command, tmp_path, capsys, monkeypatch):
    """--out was checked only after the whole computation (12 s for the quick basins)."""
    import gear_rattle.validation.transient.experiments as E

    def boom(*a, **k):
        raise AssertionError("computed before the output directory was checked")

    monkeypatch.setattr(E, command, boom)
    f = tmp_path / "file"
    f.write_text("x")
    assert_usage_error([command, "--out", str(f)], capsys, "--out", "existing file")
    assert_usage_error([command, "--out", str(f / "below")], capsys, "--out", "not a directory")


# --------------------------------------------------------------- item 6: the right names

def test_messages_name_the_option(capsys):
    assert_usage_error(["bifurcation", "--tau0", "nan"], capsys, "--tau0", absent=("sdot0",))
    assert_usage_error(["uncertainty", "--ns", "-1"], capsys, "--ns", absent=("cap",))
    assert_usage_error(["report", "--seed=-1"], capsys, "--seed", absent=("FAILED",))
    assert_usage_error(["report", "--sections", "nope"], capsys, "--sections", "timeseries")
    assert_usage_error(["uncertainty", "--eps-min", "1e-3", "--eps-max", "1e-4"], capsys, "--eps-min")


# --------------------------------------------------------- item 7: negative numbers as values

@pytest.mark.parametrize("text,value", [("-1e-2", -0.01), ("-.5", -0.5), ("-3E+1", -30.0), ("-2", -2.0),
                                        ("-1.5e0", -1.5)])
def test_negative_numbers_in_any_notation(text, value):
    p = build_parser()
    assert p.parse_args(["simulate", "--gamma", text]).gamma == value
    assert p.parse_args(["simulate", "--tau0", text]).tau0 == value
    a = p.parse_args(["basins", "--window", text, "1", text, "0.5"])
    assert a.window == [value, 1.0, value, 0.5]


def test_negative_gamma_runs(capsys):
    rc, out, _ = run_cli(["simulate", "--gamma", "-1e-2", "--tau0", "-3E+1", "--impacts", "5"], capsys)
    assert rc == 0 and len(out.strip().splitlines()) == 7


def test_negative_inf_is_a_value_not_an_option(capsys):
    assert_usage_error(["simulate", "--sdot0", "-inf"], capsys, "--sdot0", absent=("expected one argument",))


# ----------------------------------------------- item 8: one name per meaning, defaults in help

def test_one_name_for_output_directory_and_quiet():
    for name, sp in subparsers().items():
        opts = set(sp._option_string_actions)
        assert not opts & {"--outdir", "--no-progress", "--no_progress"}, name
    for name in ("report", "basins", "uncertainty", "transients"):
        opts = set(subparsers()[name]._option_string_actions)
        assert {"--out", "--quiet"} <= opts, name
    for name in ("bifurcation", "lyapunov", "orbit"):
        assert "--quiet" in subparsers()[name]._option_string_actions, name


def _default_text(d):
    if isinstance(d, list):
        return "default " + " ".join(map(str, d))
    return f"default {d}"


def test_help_shows_every_default():
    """Every option's help names its default (the value itself, or for None what happens instead);
    on/off flags (default off) and required positionals have none to show."""
    missing = []
    for name, sp in subparsers().items():
        fmt = sp._get_formatter()
        for a in sp._actions:
            if isinstance(a, argparse._HelpAction) or isinstance(a, argparse._StoreTrueAction):
                continue
            if a.help == argparse.SUPPRESS:  # an old name kept working (cliutil.add_renamed)
                continue
            if not a.option_strings and a.required:
                continue
            h = fmt._expand_help(a) if a.help else ""
            if a.default is None:
                ok = "default" in h
            elif isinstance(a.default, list):
                ok = _default_text(a.default) in h or (a.dest == "window" and "default 0 2pi 0 0.5" in h)
            else:
                ok = _default_text(a.default) in h
            if not ok:
                missing.append(f"{name} {'/'.join(a.option_strings) or a.dest}: {h!r}")
    assert not missing, missing


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
