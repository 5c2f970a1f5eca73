"""Shared helpers of the CLI subcommands: parameter options, validated inputs, output files.

Every option is validated when it is parsed (argparse ``type=`` converters below: the message names
the option and its allowed range, exit status 2) or, for conditions that involve several options or
the file system, by the command before any computation starts (:func:`check_output_file`,
:func:`check_output_dir`).  Nothing is written before every output has been checked.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import math
import os
import sys
import tempfile
from pathlib import Path

from ..core.checks import TAU0_MAX
from ..core.checks import (
    MAX_AVERAGED as MAX_AVERAGED,
    MAX_IMPACTS as MAX_IMPACTS,
    MAX_VALUES as MAX_VALUES,
)  # re-exported
from ..core.paper import PAPER_FIG3
from ..core.params import PARAM_NAMES, Params
from .clierror import COMMAND, CliError, CommandFailed  # (the command line's errors; re-exported)


# --------------------------------------------------------------------------------- upper bounds
#: Sane upper bounds of the integer options (memory and run time stay bounded; a larger value is
#: refused with a message naming the option and this range).  The orbit's impacts (MAX_IMPACTS, kept in
#: memory: simulate, timeseries, transients), the averaged impacts (MAX_AVERAGED: lyapunov) and a
#: diagram's parameter values (MAX_VALUES) are the library's own bounds (core.checks), not re-typed.
MAX_MESH = 2_000  # mesh points per axis of the transient experiments
MAX_SEED = 2**32 - 1  # numpy's seed range


def add_param_args(p: argparse.ArgumentParser, defaults: Params = PAPER_FIG3) -> None:
    """Add --alpha --beta --gamma --r (Eqs. 4-6 and 11) with the given defaults (default: the paper's
    Figs. 3-7, :data:`core.paper.PAPER_FIG3`), kept apart so that :func:`given_params` knows which
    were given."""
    d = defaults.as_dict()
    g = p.add_argument_group("model parameters (Eqs. 4-6, 11)")
    g.add_argument(
        "--alpha", type=float, default=None, help=f"driving amplitude, 0 <= alpha <= 1e10 (default {d['alpha']})"
    )
    g.add_argument("--beta", type=float, default=None, help=f"damping, 0 < beta <= 1e10 (default {d['beta']})")
    g.add_argument(
        "--gamma", type=float, default=None, help=f"constant torque term, |gamma| <= 1e10 (default {d['gamma']})"
    )
    g.add_argument("--r", type=float, default=None, help=f"restitution coefficient, 0 < r <= 1 (default {d['r']})")
    p.set_defaults(_param_defaults=d)


def given_params(args: argparse.Namespace) -> list[str]:
    """The parameter options given on the command line (``['--r']``)."""
    return [f"--{k}" for k in PARAM_NAMES if getattr(args, k, None) is not None]


def params_from(args: argparse.Namespace) -> Params:
    """Validated Params from parsed arguments (ValueError names the parameter and its range)."""
    d = args._param_defaults
    return Params(*(d[k] if getattr(args, k) is None else getattr(args, k) for k in PARAM_NAMES))


def check_scan(args: argparse.Namespace, lo: float, hi: float, *, strict: bool = False) -> tuple[float, float]:
    """``(lo, hi)`` of a scan of ``--param`` from ``--lo``/``--hi`` (defaults ``lo``, ``hi``): both values
    of the parameter (its range, :data:`core.params.RANGES`) and ``lo <= hi`` (``lo < hi`` if ``strict``);
    one-line :class:`CliError` naming the option before anything is computed."""
    from ..core.params import RANGES, check_value

    lo = args.lo if args.lo is not None else lo
    hi = args.hi if args.hi is not None else hi
    for opt, v in (("--lo", lo), ("--hi", hi)):
        try:
            check_value(args.param, v)
        except ValueError:
            raise CliError(
                f"{opt}={v!r} is out of range: allowed a value of --param {args.param}, {RANGES[args.param]}"
            ) from None
    if not (lo < hi if strict else lo <= hi):
        raise CliError(f"--lo={lo!r}, --hi={hi!r} are out of range: allowed lo {'<' if strict else '<='} hi")
    return lo, hi


def progress_arg(args: argparse.Namespace):
    """A library function's ``progress=``: False with ``--quiet``, else True (a bar per stage when stderr
    is a terminal, else a line per stage that lasts a few seconds: :mod:`gear_rattle.validation.progress`)."""
    return False if getattr(args, "quiet", False) else True


# ------------------------------------------------------------------------------ option types


def _integer(text: str) -> int | None:
    """``text`` as an integer, also in decimal exponent notation when its value is exactly an integer
    (``--impacts 1e6``, ``2.0e3``); None for anything else (``1.5``, ``nan``, ``0x10``)."""
    from decimal import Decimal, InvalidOperation

    try:
        return int(text)
    except ValueError:
        pass
    try:
        d = Decimal(text.strip())
    except (InvalidOperation, ValueError):
        return None
    if not d.is_finite():
        return None
    if d.adjusted() > 30:  # beyond every option's range (and not worth converting): the range message
        return 10**31 if d > 0 else -(10**31)
    return int(d) if d == d.to_integral_value() else None


def int_range(name: str, lo: int, hi: int):
    """argparse type: an integer ``lo <= v <= hi``, with a message naming the option and the range."""

    def conv(text: str) -> int:
        v = _integer(text)
        if v is None:
            raise argparse.ArgumentTypeError(f"{name}={text!r} is not an integer: allowed {lo} <= {name} <= {hi}")
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


def real(
    name: str, *, lo: float | None = None, hi: float | None = None, lo_open: bool = False, max_abs: float | None = None
):
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
    :func:`core.checks.check_tau0`)."""
    return real(name, max_abs=TAU0_MAX)


# ------------------------------------------------------------------------- the start of an orbit
#: The default start of an orbit on the command line: ``(tau0, sdot0)`` just before an impact on ``s = 0``.
START = (0.0, 0.5)


def add_s0_arg(p, help: str) -> None:
    """Add ``--s0``: a free-flight start at ``s = s0``, ``-1 <= s0 <= 0`` (default none: pre-impact starts)."""
    p.add_argument("--s0", type=real("--s0", lo=-1.0, hi=0.0), default=None, help=help)


def add_stick_time_arg(p, default: float | None) -> None:
    """``--stick-time T``: the sticking policy's threshold, in the library's range ``0 <= T <= MAX_STICK_TIME``
    (:func:`mapimpl.sticking.check_stick_time`); ``default`` None: the input's own (``case``)."""
    from ..mapimpl.sticking import MAX_STICK_TIME, STICK_TIME  # JAX: only the commands that compute call this

    p.add_argument(
        "--stick-time",
        type=real("--stick-time", lo=0.0, hi=MAX_STICK_TIME),
        default=default,
        metavar="T",
        help="the sticking policy's threshold: a chatter whose predicted accumulation time is at most T sticks "
        f"to the wall, 0 <= T <= {MAX_STICK_TIME:g} (default {STICK_TIME:g}; every track takes it)",
    )


def add_start_args(
    p, start: tuple[float, float] | None = START, *, what: str = "initial", none: str = "none", s0: str | None = None
) -> None:
    """Add the start options of an orbit to ``p`` (a parser or an argument group): ``--tau0`` (a time,
    ``|tau0| <= 1e6``) and ``--sdot0`` (the velocity just before impact 0, nonzero: > 0 hits ``s = 0``,
    < 0 hits ``s = -1``); with ``s0`` (its help text) also ``--s0``, a free-flight start, where any
    finite ``--sdot0`` is allowed.  ``start``: their defaults (None: no default, the help says ``none``);
    ``what``: the word before "time" and "velocity".  :func:`check_start_args` checks them together."""
    d_tau, d_sdot = (None, None) if start is None else start
    p.add_argument(
        "--tau0",
        type=tau0_type(),
        default=d_tau,
        help=f"{what} time, |tau0| <= 1e6 (default {none if start is None else d_tau})",
    )
    p.add_argument(
        "--sdot0",
        type=real("--sdot0"),
        default=d_sdot,
        help=f"{what} pre-impact velocity, nonzero (> 0 hits s = 0, < 0 hits s = -1"
        f"{'; with --s0 any finite value' if s0 else ''}) (default {none if start is None else d_sdot})",
    )
    if s0 is not None:
        add_s0_arg(p, s0)


def check_start_args(args: argparse.Namespace) -> None:
    """The start options' joint rules, before computing: ``--tau0`` and ``--sdot0`` both or neither
    (where they have no default), and ``--sdot0`` nonzero unless ``--s0`` starts in free flight."""
    if (args.tau0 is None) != (args.sdot0 is None):
        raise CliError("--tau0 and --sdot0 must be given together")
    if args.sdot0 == 0 and getattr(args, "s0", None) is None:
        raise CliError(
            "--sdot0=0 is out of range: allowed nonzero (a pre-impact velocity; > 0 hits s = 0, < 0 hits s = -1)"
        )


# ---------------------------------------------------------------------------------- messages


def note(text: str) -> None:
    """A note for the person running the command: one line on stderr, ``gear-rattle COMMAND: note: text``.
    Notes never go to stdout (it carries the result only) and ``--quiet`` does not hide them."""
    from .progress import clear_status

    clear_status()
    print(f"{COMMAND[0]}: note: {' '.join(str(text).split())}", file=sys.stderr)  # noqa: T201 - the one note writer


def is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):  # no isatty, or a closed stream
        return False


def print_result(result: dict, human: list[str], files: list | None = None) -> None:
    """A command's result on stdout: strict JSON (``result``) when stdout is a pipe or a file, for
    programs; on a terminal the few ``human`` lines instead, and where the JSON is (the ``files``
    written, and ``... | cat`` or ``> result.json`` for the same JSON on stdout)."""
    from .progress import clear_status
    from .io import json_text
    from .io.atomic import commit_pending

    commit_pending()  # the files are in place before the result says where they are
    clear_status()
    if not is_terminal(sys.stdout):
        to_stdout(json_text(result) + "\n")
        return
    lines = list(human)
    where = ", ".join(str(f) for f in files or () if str(f).endswith(".json"))
    lines.append(
        "(the result as JSON: " + (f"{where}, or " if where else "") + "stdout redirected: `... > result.json`)"
    )
    to_stdout("\n".join(lines) + "\n")


def to_stdout(text: str) -> None:
    """``text`` on stdout (flushed); a closed stdout or one that cannot be written (``> /dev/full``) is a
    one-line :class:`CliError` (a broken pipe stays a BrokenPipeError: the command line stops quietly)."""
    from .progress import clear_status

    clear_status()
    if sys.stdout is None:
        raise CliError("stdout is closed: allowed an open stdout, or --output FILE where the command has it")
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except BrokenPipeError:
        raise
    except OSError as e:
        devnull = os.open(os.devnull, os.O_WRONLY)  # the exit's flush of what is left must not fail again
        os.dup2(devnull, sys.stdout.fileno())
        raise CliError(f"stdout: cannot write: {e.strerror or e}") from None


# ---------------------------------------------------------------------------------- outputs


def _nearest_existing(path: Path) -> Path:
    p = path
    while not _exists(p) and p != p.parent:
        p = p.parent
    return p


def _exists(p: Path) -> bool:
    try:
        return p.exists()
    except OSError:  # a name the system refuses (too long): it does not exist
        return False


def _check_creatable_in(path: Path, option: str, shown: Path | None = None) -> None:
    """The directory that will hold ``path`` exists or can be created, and accepts new files (messages
    name ``shown``, default ``path``)."""
    anc = _nearest_existing(path.parent)
    path = shown if shown is not None else path
    if not anc.is_dir():
        raise CliError(f"{option}: cannot create {str(path)!r}: {str(anc)!r} is not a directory")
    try:  # a real probe (permissions, read-only or pseudo file systems): created and removed at once
        with tempfile.TemporaryFile(dir=anc, prefix=".gear-rattle-probe-"):
            pass
    except OSError as e:
        why = e.strerror or str(e)
        if e.errno == errno.ENOENT:  # the directory exists but refuses new entries (/proc, /sys)
            why = "it does not accept new files"
        raise CliError(f"{option}: cannot create {str(path)!r}: directory {str(anc)!r}: {why}") from None


def _check_not_empty(path: str, option: str, what: str) -> None:
    if not str(path).strip():
        raise CliError(f"{option}={path!r} is empty: allowed {what}")
    _check_name_lengths(Path(path), option)


def _check_name_lengths(path: Path, option: str) -> None:
    """Every name in ``path`` within the file system's limit (``NAME_MAX``, 255 bytes on Linux), and the
    whole within ``PATH_MAX``: a name the operating system would refuse is one line before computing."""
    anc = _nearest_existing(path.absolute().parent)
    try:
        name_max, path_max = os.pathconf(anc, "PC_NAME_MAX"), os.pathconf(anc, "PC_PATH_MAX")
    except (OSError, ValueError):
        name_max, path_max = 255, 4096
    for part in path.parts:
        n = len(os.fsencode(part))
        if n > name_max:
            shown = part if len(part) <= 40 else part[:20] + "..." + part[-12:]
            raise CliError(
                f"{option}: the name {shown!r} is {n} bytes long: allowed at most {name_max} bytes per "
                "name (the file system's limit)"
            )
    n = len(os.fsencode(str(path.absolute())))
    if n >= path_max:
        raise CliError(f"{option}: the path is {n} bytes long: allowed less than {path_max} bytes")


def plot_formats() -> dict:
    """File extensions matplotlib can write (``{'png': 'Portable Network Graphics', ...}``)."""
    from matplotlib.backend_bases import FigureCanvasBase

    return FigureCanvasBase.get_supported_filetypes()


#: The data formats of ``--output``, by the file's extension (stdout: ``--format``, default csv).
DATA_FORMATS = {".csv": "csv", ".json": "json", ".npz": "npz"}


def output_format(args: argparse.Namespace) -> str:
    """The format of ``--output``: from the file's extension (:data:`DATA_FORMATS`), on stdout or for a
    name without an extension (``/dev/null``) from ``--format`` (default csv).  An unknown extension, or ``--format`` naming another format than
    the extension, is a :class:`CliError` (one line, before computing)."""
    output, fmt = getattr(args, "output", None), getattr(args, "format", None)
    if output in (None, "-"):
        return fmt or "csv"
    ext = Path(output).suffix.lower()
    if not ext:  # /dev/null, a named pipe, a name without an extension: --format (default csv)
        return fmt or "csv"
    if ext not in DATA_FORMATS:
        raise CliError(
            f"--output={output!r}: the file extension must be one of {', '.join(DATA_FORMATS)} "
            "(it decides the data format)"
        )
    if fmt is not None and fmt != DATA_FORMATS[ext]:
        raise CliError(
            f"--format={fmt} does not match --output={output!r} ({DATA_FORMATS[ext]}): "
            "allowed the same format, or only one of them"
        )
    return DATA_FORMATS[ext]


def check_output_file(path: str | None, option: str, *, plot: bool = False) -> None:
    """Fail before any computation if ``path`` cannot be written: it is empty, an existing directory
    or not writable, its directory cannot be created or written, or (``plot``) its extension is not a
    format matplotlib writes.  ``None`` and ``'-'`` (stdout) pass, except for plots."""
    if path is None or (path == "-" and not plot):
        return
    _check_not_empty(path, option, "a file name")
    p = Path(path)
    if plot:
        fmts = plot_formats()
        ext = p.suffix[1:].lower()
        if ext not in fmts:
            raise CliError(
                f"{option}={path!r}: the file extension must be one of {', '.join(sorted(fmts))} (the figure format)"
            )
    if p.is_dir():
        raise CliError(f"{option}={path!r} is a directory: allowed a file name")
    if p.exists() and not os.access(p, os.W_OK):
        raise CliError(f"{option}={path!r}: the file exists and is not writable")
    _check_creatable_in(p, option)


def check_output_dir(path: str, option: str) -> None:
    """Fail before any computation if the output directory ``path`` cannot be used: it is empty, an
    existing file, or it cannot be created or written in."""
    _check_not_empty(path, option, "a directory name")
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
    _check_creatable_in(p / "x", option, shown=p)


def check_input_path(path: str, option: str, *, directory: bool) -> Path:
    """An input path that must exist: a directory (``directory``) or a readable file; one-line
    :class:`CliError` otherwise.  Returns it as a Path."""
    _check_not_empty(path, option, "a directory" if directory else "a file")
    p = Path(path)
    what = "a directory" if directory else "a file"
    if not p.exists():
        raise CliError(f"{option}={path!r} not found: allowed {what}")
    if directory != p.is_dir():
        raise CliError(f"{option}={path!r} is not {what}")
    if not os.access(p, os.R_OK | (os.X_OK if directory else 0)):
        raise CliError(f"{option}={path!r} is not readable")
    return p


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
    """Turn an OSError while writing an output into a one-line error naming the option and the path
    (:func:`output_fault`)."""
    try:
        yield
    except OSError as e:
        raise output_fault(e, option, path) from None


def output_fault(e: OSError, option: str | None = None, path=None) -> Exception:
    """The one-line error of an OSError met writing an output: a :class:`CommandFailed` (exit 1) when the
    device failed (disk full, quota, I/O error, file too large), a :class:`CliError` (exit 2) when the
    operating system refused the path (too long, invalid, permission, read-only, not a directory); the
    message names the option (where known) and the path, and says that an earlier file is kept (the
    output writer renames a whole new file into place or nothing, validation/io/atomic.py)."""
    from .io.atomic import DEVICE_ERRNOS, target_of

    where = e.filename if getattr(e, "filename", None) else path
    what = f"{option}: cannot write" if option else "cannot write"
    # the writer's temporary file or staging folder: name the output it stands for
    text = f"{what} {str(target_of(where))!r}" if where is not None else f"{what} (the file is not known)"
    text += f": {e.strerror or e}"
    if e.errno in DEVICE_ERRNOS:
        return CommandFailed(f"{text} (nothing written: an earlier file of that name is kept as it was)")
    return CliError(text)


def write_text(text: str, output: str | None, option: str = "--output") -> None:
    """Write to a file (parents created; atomically, validation/io/atomic.py) or to stdout when ``output``
    is None or '-'."""
    from .io.atomic import write_text_atomic

    if output in (None, "-"):
        to_stdout(text)
        return
    write_file(option, output, lambda path: write_text_atomic(path, text))


def write_file(option: str, path, write) -> None:
    """``write(path)`` (one of :mod:`validation.io`'s writers, all atomic) with the parent directory
    created; errors name the option."""
    with writing(option, str(path)):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        write(path)


# ------------------------------------------------------------------------- the output options


def add_output_options(
    p: argparse._ActionsContainer,
    *,
    output: str | None = None,
    plot: str | None = None,
    out: tuple[str, str] | None = None,
    quiet: str | None = "no progress bars",
) -> None:
    """The output options of a command, each added when its help text is given: ``--output FILE`` (a
    data file, its format from the extension, default stdout) with ``--format csv|json`` (the format on
    stdout), ``--plot FILE.png`` (a figure), ``--out DIR`` (``out = (default, help)``: an output
    directory) and ``--quiet`` (no progress bars; every command has it).  Checked together by
    :func:`check_outputs`, written by :func:`write_result` and :func:`write_plot`."""
    if output is not None:
        p.add_argument(
            "--output",
            default=None,
            metavar="FILE",
            help=f"{output}: .csv, .json or .npz, the format from the extension (default: stdout)",
        )
        p.add_argument(
            "--format",
            choices=("csv", "json"),
            default=None,
            help="format on stdout; with --output it must match the extension (default csv)",
        )
    if plot is not None:
        p.add_argument("--plot", default=None, metavar="FILE.png", help=plot)
    if out is not None:
        p.add_argument("--out", default=out[0], metavar="DIR", help=out[1])
    if quiet is not None:
        p.add_argument("--quiet", action="store_true", help=f"{quiet} (notes and errors still go to stderr)")


def check_outputs(args: argparse.Namespace) -> None:
    """Before any computation: every output option of :func:`add_output_options` the command has can be
    written (:func:`check_output_file`, :func:`check_output_dir`), the data format is known
    (:func:`output_format`), and ``--output`` and ``--plot`` name different files."""
    output, plot = getattr(args, "output", None), getattr(args, "plot", None)
    check_output_file(output, "--output")
    if hasattr(args, "output"):
        output_format(args)
    check_output_file(plot, "--plot", plot=True)
    check_distinct(**{"--output": output, "--plot": plot})
    if getattr(args, "out", None) is not None:
        check_output_dir(args.out, "--out")


def write_result(args: argparse.Namespace, result=None, *, arrays=None, table=None, data=None) -> None:
    """``--output`` of a result in the format of :func:`output_format`, through the one writer of each
    format (:mod:`validation.io`): NPZ of ``result.arrays()``, CSV of ``result.table()`` (``(header,
    rows)``), JSON of ``result.as_dict()`` (else of its arrays); or of the callables ``arrays``,
    ``table`` and ``data`` given instead.  A file, or stdout (None or ``-``)."""
    from .io import csv_text, json_text, write_npz

    arrays = arrays or result.arrays
    table = table or result.table
    data = data or getattr(result, "as_dict", None) or arrays
    fmt = output_format(args)
    if fmt == "npz":
        if args.output in (None, "-"):  # pragma: no cover - output_format gives npz for a file only
            raise CliError("--format npz: allowed with --output FILE.npz only (binary)")
        write_file("--output", args.output, lambda path: write_npz(path, **arrays()))
    elif fmt == "json":
        write_text(json_text(data()) + "\n", args.output)
    else:
        write_text(csv_text(*table()), args.output)


def write_plot(args: argparse.Namespace, fig) -> None:
    """``--plot``: save the figure ``fig`` (when the option was given) by the one figure writer,
    :func:`validation.io.save_figure`, with the parent directory created; errors name the option."""
    from .io import save_figure

    if args.plot:
        write_file("--plot", args.plot, lambda path: save_figure(fig, path))


# ------------------------------------------------------------------------ renamed options


class _Renamed(argparse.Action):
    """An option's old name: stores into the new option's destination and notes the rename on stderr."""

    def __init__(self, option_strings, dest, new: str = "", **kwargs):
        self.new = new
        super().__init__(option_strings, dest, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        print(  # noqa: T201
            f"{parser.prog}: note: {option_string} is deprecated: use {self.new} (same meaning)",
            file=sys.stderr,
        )
        setattr(namespace, self.dest, values)


def add_renamed(p: argparse.ArgumentParser, old: str, new: str, **kwargs) -> None:
    """Keep the old spelling ``old`` of the option ``new`` working (hidden from --help, a note on
    stderr when used); ``kwargs``: the new option's ``type``/``nargs``."""
    dest = new.lstrip("-").replace("-", "_")
    p.add_argument(
        old, dest=dest, action=_Renamed, new=new, default=argparse.SUPPRESS, help=argparse.SUPPRESS, **kwargs
    )


@contextlib.contextmanager
def suite_writer(suite: Path, option: str, value: str):
    """The lock of a suite folder (:func:`writelock.suite_lock`; ``option value``: how the command names the
    folder) held for the block -- every command that writes a suite (``case``, ``fuzz``) holds it: another
    writer is refused in one line (exit status 1); a suite folder this run created is removed again if it
    is left empty."""
    from .writelock import StoreBusy, suite_lock

    existed = suite.exists()
    lock = suite_lock(suite)
    try:
        lock.acquire()
    except StoreBusy as e:
        raise CommandFailed(str(e)) from None
    except BaseException:
        if not existed:
            with contextlib.suppress(OSError):
                suite.rmdir()
        raise
    try:
        if lock.stale:
            note(f"{option} {value}: the lock of a run that was killed was taken over ({lock.path})")
        yield lock
    finally:
        lock.release()
        if not existed:
            with contextlib.suppress(OSError):
                suite.rmdir()  # only if empty: nothing was written


__all__ = [
    "MAX_MESH",
    "MAX_SEED",
    "add_param_args",
    "given_params",
    "params_from",
    "check_scan",
    "progress_arg",
    "int_range",
    "positive_int",
    "nonneg_int",
    "seed_int",
    "real",
    "tau0_type",
    "START",
    "add_s0_arg",
    "add_start_args",
    "check_start_args",
    "note",
    "is_terminal",
    "print_result",
    "to_stdout",
    "plot_formats",
    "DATA_FORMATS",
    "output_format",
    "check_output_file",
    "check_output_dir",
    "check_input_path",
    "check_distinct",
    "writing",
    "output_fault",
    "write_text",
    "write_file",
    "add_output_options",
    "check_outputs",
    "write_result",
    "write_plot",
    "add_renamed",
    "suite_writer",
]
