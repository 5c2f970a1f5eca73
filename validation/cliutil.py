"""Shared helpers of the CLI subcommands: parameter options, validated inputs, output files.

Every option is validated when it is parsed (argparse ``type=`` converters below: the message names
the option and its allowed range, exit status 2) or, for conditions that involve several options or
the file system, by the command before any computation starts (:func:`check_output_file`,
:func:`check_output_dir`).  Nothing is written before every output has been checked.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
import tempfile
from pathlib import Path

from ..core.checks import TAU0_MAX
from ..core.params import Params


class CliError(Exception):
    """A user error on the command line: printed as one line, exit status 2."""


# --------------------------------------------------------------------------------- upper bounds
#: Sane upper bounds of the integer options (memory and run time stay bounded; a larger value is
#: refused with a message naming the option and this range).
MAX_IMPACTS = 10_000_000        # impacts of one orbit kept in memory (simulate, timeseries, transients)
MAX_AVERAGED = 50_000_000       # impacts streamed through an average (lyapunov; the library's limit)
MAX_VALUES = 20_000             # parameter values of a diagram (validation.dynamics.bifurcation.MAX_POINTS)
MAX_MESH = 2_000                # mesh points per axis of the transient experiments
MAX_SEED = 2**32 - 1            # numpy's seed range


def add_param_args(p: argparse.ArgumentParser, alpha=3.0, beta=0.1, gamma=0.1, r=0.9) -> None:
    """Add --alpha --beta --gamma --r (Eqs. 4-6 and 11) with the given defaults."""
    g = p.add_argument_group("model parameters (Eqs. 4-6, 11)")
    g.add_argument("--alpha", type=float, default=alpha, help=f"driving amplitude, 0 <= alpha <= 1e10 (default {alpha})")
    g.add_argument("--beta", type=float, default=beta, help=f"damping, 0 < beta <= 1e10 (default {beta})")
    g.add_argument("--gamma", type=float, default=gamma, help=f"constant torque term, |gamma| <= 1e10 (default {gamma})")
    g.add_argument("--r", type=float, default=r, help=f"restitution coefficient, 0 < r <= 1 (default {r})")


def params_from(args: argparse.Namespace) -> Params:
    """Validated Params from parsed arguments (ValueError names the parameter and its range)."""
    return Params(args.alpha, args.beta, args.gamma, args.r)


# ------------------------------------------------------------------------------ option types

def int_range(name: str, lo: int, hi: int):
    """argparse type: an integer ``lo <= v <= hi``, with a message naming the option and the range."""

    def conv(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}={text!r} is not an integer") from None
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError(f"{name}={text} is out of range: allowed {lo} <= {name} <= {hi}")
        return v

    conv.__name__ = "integer"
    return conv


def positive_int(name: str, hi: int):
    """argparse type: an integer ``1 <= v <= hi``."""
    return int_range(name, 1, hi)


def nonneg_int(name: str, hi: int):
    """argparse type: an integer ``0 <= v <= hi``."""
    return int_range(name, 0, hi)


def seed_int(name: str = "--seed"):
    """argparse type: a random seed, ``0 <= v <= 2**32 - 1``."""
    return int_range(name, 0, MAX_SEED)


def _fmt(x: float) -> str:
    """A bound as people write it: 1e6, 0.1, 1e-9."""
    return f"{x:g}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


def real(name: str, *, lo: float | None = None, hi: float | None = None, lo_open: bool = False,
         max_abs: float | None = None):
    """argparse type: a finite float, optionally ``lo <= v`` (``lo < v`` with ``lo_open``), ``v <= hi``
    and ``|v| <= max_abs``; the message names the option and the allowed range."""
    parts = []
    if lo is not None:
        parts.append(f"{name} {'>' if lo_open else '>='} {_fmt(lo)}")
    if hi is not None:
        parts.append(f"{name} <= {_fmt(hi)}")
    if max_abs is not None:
        parts.append(f"|{name}| <= {_fmt(max_abs)}")
    allowed = "a finite number" + (" with " + " and ".join(parts) if parts else "")

    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}={text!r} is not a number") from None
        ok = math.isfinite(v)
        ok = ok and (lo is None or (v > lo if lo_open else v >= lo)) and (hi is None or v <= hi)
        ok = ok and (max_abs is None or abs(v) <= max_abs)
        if not ok:
            raise argparse.ArgumentTypeError(f"{name}={text} is out of range: allowed {allowed}")
        return v

    conv.__name__ = "number"
    return conv


def tau0_type(name: str = "--tau0"):
    """argparse type of an initial time: finite, ``|tau0| <= TAU0_MAX`` (the library's range,
    :func:`mapimpl.orbit.check_tau0`)."""
    return real(name, max_abs=TAU0_MAX)


# ---------------------------------------------------------------------------------- outputs

def _nearest_existing(path: Path) -> Path:
    p = path
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


def _check_creatable_in(path: Path, option: str) -> None:
    """The directory that will hold ``path`` exists or can be created, and accepts new files."""
    anc = _nearest_existing(path.parent)
    if not anc.is_dir():
        raise CliError(f"{option}: cannot create {str(path)!r}: {str(anc)!r} is not a directory")
    try:  # a real probe (permissions, read-only or pseudo file systems): created and removed at once
        with tempfile.TemporaryFile(dir=anc, prefix=".gear-rattle-probe-"):
            pass
    except OSError as e:
        raise CliError(f"{option}: cannot write in directory {str(anc)!r}: {e.strerror or e}") from None


def plot_formats() -> dict:
    """File extensions matplotlib can write (``{'png': 'Portable Network Graphics', ...}``)."""
    from matplotlib.backend_bases import FigureCanvasBase

    return FigureCanvasBase.get_supported_filetypes()


def check_output_file(path: str | None, option: str, *, plot: bool = False) -> None:
    """Fail before any computation if ``path`` cannot be written: it is an existing directory or not
    writable, its directory cannot be created or written, or (``plot``) its extension is not a format
    matplotlib writes.  ``None`` and ``'-'`` (stdout) pass, except for plots."""
    if path is None or (path == "-" and not plot):
        return
    p = Path(path)
    if plot:
        fmts = plot_formats()
        ext = p.suffix[1:].lower()
        if ext not in fmts:
            raise CliError(f"{option}={path!r}: the file extension must be one of {', '.join(sorted(fmts))} "
                           "(the figure format)")
    if p.is_dir():
        raise CliError(f"{option}={path!r} is a directory: allowed a file name")
    if p.exists() and not os.access(p, os.W_OK):
        raise CliError(f"{option}={path!r}: the file exists and is not writable")
    _check_creatable_in(p, option)


def check_output_dir(path: str, option: str) -> None:
    """Fail before any computation if the output directory ``path`` cannot be used: it is an existing
    file, or it cannot be created or written in."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise CliError(f"{option}={path!r} is an existing file: allowed a directory (existing or new)")
    if p.is_dir():
        try:
            with tempfile.TemporaryFile(dir=p, prefix=".gear-rattle-probe-"):
                pass
        except OSError as e:
            raise CliError(f"{option}: cannot write in directory {path!r}: {e.strerror or e}") from None
        return
    _check_creatable_in(p / "x", option)


def check_distinct(**files: str | None) -> None:
    """Two output options must not name the same file (``check_distinct(**{'--output': a, '--plot': b})``)."""
    seen: dict[Path, str] = {}
    for option, path in files.items():
        if path in (None, "-"):
            continue
        key = Path(path).resolve()
        if key in seen:
            raise CliError(f"{seen[key]} and {option} name the same file {path!r}")
        seen[key] = option


@contextlib.contextmanager
def writing(option: str, path: str | None):
    """Turn an OSError while writing an output into a one-line error naming the option."""
    try:
        yield
    except OSError as e:
        where = e.filename if getattr(e, "filename", None) else path
        raise CliError(f"{option}: cannot write {str(where)!r}: {e.strerror or e}") from None


def write_text(text: str, output: str | None, option: str = "--output") -> None:
    """Write to a file (parents created) or to stdout when ``output`` is None or '-'."""
    if output in (None, "-"):
        sys.stdout.write(text)
        return
    path = Path(output)
    with writing(option, output):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def write_file(option: str, path: str, write) -> None:
    """``write(path)`` (a figure's or an array file's writer) with the parent directory created;
    errors name the option."""
    with writing(option, path):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        write(path)


def save_figure(fig, path: str, option: str = "--plot", dpi: int = 150) -> None:
    """``fig.savefig(path)`` with the parent directory created; errors name the option."""
    write_file(option, path, lambda x: fig.savefig(x, dpi=dpi))


# ------------------------------------------------------------------------- the output options

def add_output_options(p: argparse.ArgumentParser, *, fmt: str | None = None, output: str | None = None,
                       plot: str | None = None, out: tuple[str, str] | None = None, quiet: str | None = None) -> None:
    """The output options of a command, each added when its help text is given: ``--format`` (csv or
    json), ``--output`` (a data file, default stdout), ``--plot FILE.png`` (a figure), ``--out DIR``
    (``out = (default, help)``: an output directory) and ``--quiet`` (no progress).  Checked together by
    :func:`check_outputs`, written by :func:`write_output` and :func:`write_plot`."""
    if fmt is not None:
        p.add_argument("--format", choices=("csv", "json"), default="csv", help=fmt)
    if output is not None:
        p.add_argument("--output", default=None, help=output)
    if plot is not None:
        p.add_argument("--plot", default=None, metavar="FILE.png", help=plot)
    if out is not None:
        p.add_argument("--out", default=out[0], metavar="DIR", help=out[1])
    if quiet is not None:
        p.add_argument("--quiet", action="store_true", help=quiet)


def check_outputs(args: argparse.Namespace) -> None:
    """Before any computation: every output option of :func:`add_output_options` the command has can be
    written (:func:`check_output_file`, :func:`check_output_dir`), and ``--output`` and ``--plot`` name
    different files."""
    output, plot = getattr(args, "output", None), getattr(args, "plot", None)
    check_output_file(output, "--output")
    check_output_file(plot, "--plot", plot=True)
    check_distinct(**{"--output": output, "--plot": plot})
    if getattr(args, "out", None) is not None:
        check_output_dir(args.out, "--out")


def write_output(args: argparse.Namespace, result=None, *, arrays=None, table=None) -> None:
    """``--output`` of a result with ``arrays()`` (NPZ) and ``table()`` (CSV ``(header, rows)``), or of
    the callables ``arrays`` and ``table``: an NPZ file when the name ends in ``.npz``, else CSV in the
    file or on stdout (None or ``-``)."""
    from .io import csv_text, write_npz

    arrays = arrays or result.arrays
    table = table or result.table
    if args.output and args.output.endswith(".npz"):
        write_file("--output", args.output, lambda path: write_npz(path, **arrays()))
    else:
        write_text(csv_text(*table()), args.output)


def write_plot(args: argparse.Namespace, fig, dpi: int = 150) -> None:
    """``--plot``: save the figure ``fig`` (when the option was given)."""
    if args.plot:
        save_figure(fig, args.plot, "--plot", dpi=dpi)
