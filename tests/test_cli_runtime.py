"""The command line's runtime (issue 23): the persistent compilation cache and the one boundary for
Python warnings.

* The console script keeps compiled kernels in ``$GEAR_RATTLE_JAX_CACHE`` (default
  ``$XDG_CACHE_HOME/gear-rattle/jax``; ``0`` turns it off); a library import never turns it on.  An
  unwritable or corrupt cache never breaks a command: one note on stderr at most, the same output.
* A Python warning that reaches the command line is one line on stderr (``gear-rattle CMD: note:
  ...``), once per place that warns; stdout carries only the result.
"""

from __future__ import annotations

import os
import subprocess
import sys
import warnings

import numpy as np

from gear_rattle.core import jax_config
from gear_rattle.validation.cli import main


def _cli(args, tmp_path, cache):
    env = dict(os.environ, GEAR_RATTLE_JAX_CACHE=str(cache))
    return subprocess.run(
        [sys.executable, "-m", "gear_rattle", *args], capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300
    )


def test_library_import_leaves_the_cache_off():
    """Importing the package (and calling the CLI's main() from Python) does not configure JAX's cache."""
    import jax

    code = (
        "import jax, gear_rattle; from gear_rattle.validation.cli import main; "
        "main(['simulate', '--impacts', '1']); print(jax.config.values['jax_compilation_cache_dir'])"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip().endswith("None"), out.stderr
    assert jax.config.values["jax_compilation_cache_dir"] is None


def test_cache_default_place_and_opt_out(monkeypatch, tmp_path):
    monkeypatch.delenv(jax_config.JAX_CACHE_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert jax_config.compilation_cache_dir() == str(tmp_path / "xdg" / "gear-rattle" / "jax")
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert jax_config.compilation_cache_dir() == str(tmp_path / "home" / ".cache" / "gear-rattle" / "jax")
    for off in ("0", "off", ""):
        monkeypatch.setenv(jax_config.JAX_CACHE_ENV, off)
        assert jax_config.compilation_cache_dir() is None and jax_config.use_compilation_cache() is None
    monkeypatch.setenv(jax_config.JAX_CACHE_ENV, str(tmp_path / "mine"))
    assert jax_config.compilation_cache_dir() == str(tmp_path / "mine")


def test_unwritable_cache_is_one_note(tmp_path):
    notes = []
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    assert jax_config.use_compilation_cache(str(blocker / "jax"), note=notes.append) is None
    assert len(notes) == 1 and "cache off" in notes[0] and "GEAR_RATTLE_JAX_CACHE=0" in notes[0]
    r = _cli(["simulate", "--impacts", "3"], tmp_path, blocker / "jax")
    assert r.returncode == 0 and r.stdout.startswith("n,tau,")
    assert r.stderr.count("\n") == 1 and "note: JAX compilation cache off" in r.stderr


def test_cache_is_filled_reused_and_survives_corruption(tmp_path):
    """The first run stores the compiled kernels, the second reads them (the same output, bitwise);
    garbage in every entry costs a recompilation and notes on stderr, never the command."""
    cache = tmp_path / "cache"
    args = ["simulate", "--impacts", "300"]
    first = _cli(args, tmp_path, cache)
    assert first.returncode == 0 and first.stderr == ""
    entries = sorted(cache.iterdir())
    assert entries and all(e.name.endswith("-cache") for e in entries)
    second = _cli(args, tmp_path, cache)
    assert second.returncode == 0 and second.stdout == first.stdout and second.stderr == ""
    for e in entries:
        e.write_bytes(b"garbage")
    third = _cli(args, tmp_path, cache)
    assert third.returncode == 0 and third.stdout == first.stdout
    lines = third.stderr.strip().splitlines()
    assert lines and all(line.startswith("gear-rattle simulate: note: UserWarning:") for line in lines), third.stderr
    assert "delete it to rebuild it" in lines[0]


def test_warnings_become_one_line_notes(monkeypatch, capsys):
    """A numpy RuntimeWarning raised inside a command (issue 23: ``--beta 1e308`` printed two-line
    warnings with source lines) is one note per place that warns, on stderr; stdout is the result."""
    from gear_rattle.validation.commands import simulate

    real_run = simulate.run

    def noisy(args):
        for _ in range(3):
            np.float64(1e308) * np.float64(10.0)  # overflow: the same place warns thrice
        warnings.warn("something else", UserWarning, stacklevel=1)
        return real_run(args)

    monkeypatch.setattr(simulate, "run", noisy)
    rc = main(["simulate", "--impacts", "2"])
    out = capsys.readouterr()
    assert rc == 0 and out.out.startswith("n,tau,")
    lines = out.err.strip().splitlines()
    assert len(lines) == 2, out.err
    assert lines[0].startswith("gear-rattle simulate: note: RuntimeWarning: overflow")
    assert lines[1] == "gear-rattle simulate: note: UserWarning: something else"
