"""Progress without a terminal (issue 32 item 5): with stderr a log or a pipe (CI, ``| tee``) a long stage
writes a line that names it and the phase it is in (a 50 s compilation was silent), then at most one
line every few seconds and a last line; a short stage writes nothing, and so does a library call with
the default ``progress=None``.  The drawing is the command line's (validation/progress.py); the library
reports through core.progress (issue 32 item 3)."""

from __future__ import annotations

import io
import time

import pytest

from gear_rattle.core import progress as P
from gear_rattle.validation import progress as display


@pytest.fixture
def log(monkeypatch):
    """``log()``: stderr a pipe (not a terminal; set in the test itself, pytest's capture sets sys.stderr
    when the test starts), the lines on, and short delays: the first line after 0.3 s, then at most one
    every 0.8 s."""
    monkeypatch.setenv(display.LINES_ENV, "1")
    monkeypatch.setattr(display, "LOG_FIRST_S", 0.3)
    monkeypatch.setattr(display, "LOG_INTERVAL_S", 0.8)

    def start() -> io.StringIO:
        stream = io.StringIO()
        monkeypatch.setattr("sys.stderr", stream)
        return stream

    return start


def test_a_long_stage_announces_its_phase_then_a_line_every_few_seconds(log):
    log = log()
    bar = P.Bar("engine", enabled=P.wanted(True), phase="compiling")
    assert bar.drawn
    t0 = time.monotonic()
    time.sleep(1.0)  # compiling: nothing counted, the ticker writes the line
    for k in range(1, 9):
        bar.update(k * 1000, 8000)
        time.sleep(0.2)
    bar.close()
    elapsed = time.monotonic() - t0
    lines = log.getvalue().splitlines()
    assert lines[0].startswith("engine: compiling, ") and lines[0].endswith(" s"), lines
    assert lines[-1].startswith("engine: done, 8k impacts in "), lines
    counts = [ln for ln in lines[1:-1] if "impacts" in ln]
    assert all("/8k impacts (" in ln and "impacts/s" in ln for ln in counts), lines
    # at most one line per interval (the last line aside), and fewer lines than updates
    assert len(lines) - 1 <= 1 + elapsed / display.LOG_INTERVAL_S, lines
    bar.close()  # closed: nothing more
    assert log.getvalue().splitlines() == lines


def test_a_short_stage_and_the_library_default_write_nothing(log, monkeypatch):
    log = log()
    with P.Bar("case", total=3, unit="cases", enabled=True) as bar:  # a command's own stage, 0.1 s
        bar(1)
        time.sleep(0.1)
        bar(3)
    assert bar.drawn is False and log.getvalue() == ""
    lib = P.Bar("engine", enabled=P.wanted(None), phase="compiling")  # the library's default: a terminal only
    assert not lib.drawn
    time.sleep(0.5)
    lib.close()
    assert log.getvalue() == ""
    monkeypatch.setenv(display.LINES_ENV, "0")
    off = P.Bar("engine", enabled=P.wanted(True))
    assert not off.drawn
    assert P.wanted(False) is False and P.wanted(lambda d, t: None) is False


def test_a_stage_stopped_by_an_error_says_so(log):
    log = log()
    with pytest.raises(RuntimeError):
        with P.Bar("atlas", unit="tiles", enabled=True) as bar:
            bar.update(2, 10)
            time.sleep(0.6)
            raise RuntimeError("x")
    lines = log.getvalue().splitlines()
    assert lines[0].startswith("atlas: 2/10 tiles (20%)") and lines[-1].startswith("atlas: stopped, 2 tiles in ")


def test_the_command_line_asks_for_lines_and_the_library_for_a_terminal(monkeypatch):
    """A command passes ``progress=True`` (lines where there is no terminal), ``--quiet`` False; a library
    function hands ``progress`` to the display as where it may draw (the certified track: no JAX)."""
    import argparse

    import gear_rattle as gr
    from gear_rattle.validation.cliutil import progress_arg

    assert progress_arg(argparse.Namespace(quiet=False)) is True
    assert progress_arg(argparse.Namespace(quiet=True)) is False
    seen = []

    def recorder(label, **kw):
        seen.append((label, kw["where"]))

    monkeypatch.setattr(P, "_DISPLAY", [recorder])
    p = gr.Params(alpha=3.0, beta=0.1, gamma=0.1, r=0.9)
    for progress in (True, None, False):
        gr.orbit(p, 0.0, 0.5, 2, track="certified", progress=progress)
    assert seen == [("certified orbit", P.ANYWHERE), ("certified orbit", P.TERMINAL)]


def test_the_display_draws_a_bar_on_a_terminal(monkeypatch):
    monkeypatch.setattr(display, "stderr_is_terminal", lambda: True)
    monkeypatch.setattr(display, "TerminalBar", lambda *a: ("bar", a))
    monkeypatch.setenv(display.LINES_ENV, "0")  # lines off: a terminal still gets its bar
    assert display.display("x", where=P.TERMINAL)[0] == "bar"
    monkeypatch.setattr(display, "stderr_is_terminal", lambda: False)
    assert display.display("x", where=P.TERMINAL) is None
    with pytest.raises(TypeError, match="display=3 is not callable"):
        P.set_display(3)
