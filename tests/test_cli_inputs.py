"""The command line's inputs: every option is checked before any computation, and bad input is one
line on stderr naming the option and its range, exit status 2, no traceback (the start options
--tau0/--sdot0/--s0, integer bounds, output paths, negative numbers, names and defaults in --help).

Most checks fail while the arguments are parsed or validated, before any computation, so they run
in-process and fast; the few that compute use short orbits.  (First written for the defects a new user
hit, issue 11; the long-run behaviour -- chunks, Ctrl-C, progress, one compilation -- is in
test_cli_long_runs.py.)"""

import argparse

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


# ------------------------------------------------------------------- item 4: no tracebacks


@pytest.mark.parametrize(
    "args,needle",
    [
        (["simulate", "--impacts", "99999999999999999999"], "--impacts"),
        (["orbit", "find", "--impacts", "99999999999999999999"], "--impacts"),
        (["simulate", "--impacts", "3", "--plot", "/proc/x.png"], "--plot"),
        (["bifurcation", "--values", "10", "--keep", "99999999"], "--keep"),
    ],
)
def test_no_traceback(args, needle, capsys):
    assert_usage_error(args, capsys, needle)


def test_report_out_is_a_file(tmp_path, capsys):
    f = tmp_path / "a-file"
    f.write_text("x")
    assert_usage_error(["report", "--out", str(f), "--sections", "timeseries"], capsys, "--out", "existing file")
    assert f.read_text() == "x"


def test_timeseries_too_short_for_a_period(capsys):
    """r = 0.5: 30 impacts chatter and stick within one forcing period: no stroboscopic sample."""
    assert_usage_error(
        ["timeseries", "--r", "0.5", "--impacts", "20", "--transient", "10"], capsys, "--impacts=20", "--transient=10"
    )


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
    assert_usage_error(
        ["simulate", "--impacts", "3", "--output", str(data), "--plot", str(fig)], capsys, "--plot", "png"
    )
    assert not data.exists() and not fig.exists()


@pytest.mark.parametrize("case", ["output-is-dir", "parent-is-file", "same-file", "plot-no-ext"])
def test_outputs_validated_before_computing(case, tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    args = {
        "output-is-dir": ["--output", str(tmp_path)],
        "parent-is-file": ["--output", str(f / "sub" / "o.csv")],
        "same-file": ["--output", str(tmp_path / "a.png"), "--plot", str(tmp_path / "a.png")],
        "plot-no-ext": ["--plot", str(tmp_path / "figure")],
    }[case]
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


@pytest.mark.parametrize(
    "text,value", [("-1e-2", -0.01), ("-.5", -0.5), ("-3E+1", -30.0), ("-2", -2.0), ("-1.5e0", -1.5)]
)
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


# ------------------------------------------------------- the start options: one group, one check


@pytest.mark.parametrize("command", COMMANDS_WITH_TAU0)
def test_every_command_refuses_a_zero_pre_impact_velocity_the_same_way(command, capsys):
    """--tau0/--sdot0 are one option group (cliutil.add_start_args) with one joint check
    (cliutil.check_start_args): the same message in every command, before computing (issue 32 item 1)."""
    extra = ["--tau0", "1"] if command == "orbit find" else []
    err = assert_usage_error([*command.split(), "--sdot0", "0", *extra], capsys, "--sdot0=0 is out of range")
    assert err.strip().endswith("allowed nonzero (a pre-impact velocity; > 0 hits s = 0, < 0 hits s = -1)")
    helps = (
        subparsers()[command.split()[0]].format_help()
        if command != "orbit find"
        else subparsers()["orbit"].format_help()
    )
    assert "pre-impact velocity, nonzero (> 0 hits s = 0, < 0 hits s = -1" in " ".join(helps.split())


def test_a_free_flight_start_allows_any_velocity(capsys):
    rc, out, err = run_cli(["simulate", "--s0", "-0.5", "--sdot0", "0", "--impacts", "2"], capsys)
    assert rc == 0 and err == "" and out.count("\n") >= 2
