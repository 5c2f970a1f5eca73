"""The project's JAX set-up (``gear_rattle.core.jax_config``; its old private name ``core._jax`` is an alias).

Importing any ``gear_rattle`` module switches JAX to float64 (``jax_enable_x64``): every kernel
computes in double precision.  Nothing else happens on import, and JAX itself is not imported here
(:func:`float64_jax`): ``gear-rattle check`` and ``import gear_rattle`` run with numpy alone.

:func:`use_cpu_devices` is the opt-in second half, called by the command line (and by tests and
benchmarks) before JAX starts:

* on the CPU, one XLA device per available core, so that the engine (:mod:`gear_rattle.mapimpl.engine`)
  can run one queue of orbits per core -- a single XLA CPU device executes its small element-wise
  kernels on one thread;
* the XLA:CPU compiler options of :data:`ENGINE_XLA_FLAGS` (on the jaxlib versions they were tested
  with, :data:`ENGINE_XLA_TESTED`; ``GEAR_RATTLE_XLA_TUNING=0`` leaves them out), under which the
  engine's kernel runs about twice as fast (docs/engine.md, "Compiling the kernel").

A library user who wants the same calls it before the first JAX computation.  Results are correct
either way; float64 samples of chaotic orbits (docs/release.md) depend on the compiler and its options.

**Subnormal numbers.**  XLA on the CPU computes with subnormals flushed to zero (inputs and results,
whatever the flags): inside jitted code ``1e-320 > 0`` is false.  Where the *sign* of a number that
may be a subnormal input decides a branch (the wall a pre-impact velocity points to), the decision is
taken on its bits with :func:`positive`; everywhere else a subnormal acts as the zero it is within
rounding (the tracks agree on subnormal inputs: tests/test_extremes.py).
"""

from __future__ import annotations

import os
import sys


def float64_jax() -> None:
    """JAX in float64 without importing it: ``jax_enable_x64`` at once where JAX is already imported,
    else ``JAX_ENABLE_X64=1`` in the environment, which JAX reads when it is imported (and which the
    processes this one starts inherit).  Called when this module is imported, so that every module
    of the package that imports JAX, after it, computes in float64."""
    jax = sys.modules.get("jax")
    if jax is not None and hasattr(jax, "config"):
        jax.config.update("jax_enable_x64", True)
    else:
        os.environ["JAX_ENABLE_X64"] = "1"


float64_jax()


def positive(x):
    """``x > 0`` for float64 ``x``, decided on its bits: true for a positive subnormal too, which XLA on
    the CPU compares as zero (see the module docstring).  Works on host values and inside jit."""
    import jax
    import jax.numpy as jnp

    return jax.lax.bitcast_convert_type(jnp.asarray(x, jnp.float64), jnp.int64) > 0


#: Environment variable of the command line's persistent compilation cache (:func:`use_compilation_cache`):
#: ``0`` turns it off, a path puts it there.
JAX_CACHE_ENV = "GEAR_RATTLE_JAX_CACHE"
#: Compilations shorter than this are not cached (JAX's own default is 1 s; see :func:`use_compilation_cache`).
CACHE_MIN_COMPILE_S = 0.2
#: Environment variable that sets the number of XLA CPU devices chosen by :func:`use_cpu_devices`.
CPU_DEVICES_ENV = "GEAR_RATTLE_CPU_DEVICES"
#: Environment variable: ``0`` keeps :func:`use_cpu_devices` from adding :data:`ENGINE_XLA_FLAGS`.
XLA_TUNING_ENV = "GEAR_RATTLE_XLA_TUNING"
#: XLA:CPU options for the engine's kernel: the loop emitters with multi-output fusion (a value that
#: several results need is computed once, in one loop, rather than re-computed in each result's loop or
#: written to memory between loops) and whole-loop compilation of while loops (the engine's block of
#: micro-steps runs as one compiled function instead of one runtime call per fused loop per micro-step).
ENGINE_XLA_FLAGS = (
    "--xla_cpu_use_fusion_emitters=false",
    "--xla_backend_extra_options=xla_cpu_use_multi_output_fusion=true,"
    "xla_cpu_small_while_loop_byte_threshold=1000000000",
)
#: jaxlib versions (major, minor) with which :data:`ENGINE_XLA_FLAGS` were tested; XLA aborts the process
#: on a flag it does not know, so other versions run without them.
ENGINE_XLA_TESTED = ((0, 10),)


def jaxlib_version() -> tuple[int, int]:
    """The installed jaxlib's ``(major, minor)`` version; ``(0, 0)`` where it cannot be read."""
    try:
        from jaxlib.version import __version__ as v

        major, minor = (int(x) for x in v.split(".")[:2])
        return major, minor
    except Exception:  # noqa: BLE001  # pragma: no cover - unusual installs: no version, no tuning
        return (0, 0)


def engine_xla_flags() -> tuple[str, ...]:
    """The :data:`ENGINE_XLA_FLAGS` that :func:`use_cpu_devices` applies here: all of them on a tested
    jaxlib version unless ``GEAR_RATTLE_XLA_TUNING=0``, else none."""
    if os.environ.get(XLA_TUNING_ENV, "1").strip() == "0" or jaxlib_version() not in ENGINE_XLA_TESTED:
        return ()
    return ENGINE_XLA_FLAGS


def xla_tuning_active() -> bool:
    """Whether this process runs with :data:`ENGINE_XLA_FLAGS` (set in ``XLA_FLAGS`` before JAX started)."""
    flags = os.environ.get("XLA_FLAGS", "")
    return all(f in flags for f in ENGINE_XLA_FLAGS)


def _add_engine_xla_flags() -> None:
    from jax._src import xla_bridge

    started = getattr(xla_bridge, "backends_are_initialized", lambda: True)()
    if started:
        return
    flags = os.environ.get("XLA_FLAGS", "")
    extra = [f for f in engine_xla_flags() if f.split("=")[0] not in flags]
    if extra:
        os.environ["XLA_FLAGS"] = " ".join([flags, *extra]).strip()


def _wanted_cpu_devices(n: int | None) -> int:
    from .checks import check_int

    if n is not None:
        return check_int("n", n, 1, 1024)
    raw, src = os.environ.get(CPU_DEVICES_ENV), CPU_DEVICES_ENV
    if raw is None:
        try:
            return max(1, len(os.sched_getaffinity(0)))
        except (AttributeError, OSError):  # pragma: no cover - non-Linux
            return max(1, os.cpu_count() or 1)
    try:
        v = int(raw)
    except (TypeError, ValueError):
        v = 0
    if not 1 <= v <= 1024:
        raise ValueError(f"{src}={raw!r} is out of range: allowed an integer 1 <= {src} <= 1024")
    return v


def use_cpu_devices(n: int | None = None) -> int:
    """Ask JAX for ``n`` XLA CPU devices (default: ``$GEAR_RATTLE_CPU_DEVICES``, else one per
    available core) and return the number of CPU devices JAX will use.

    Also adds :func:`engine_xla_flags` to ``XLA_FLAGS`` (those it does not name already).  Must run
    before JAX's first computation.  Nothing is changed when JAX has already started (the count is then
    whatever it is); the device count is left alone when ``XLA_FLAGS`` already sets
    ``--xla_force_host_platform_device_count`` or on JAX versions without ``jax_num_cpu_devices``
    (before 0.5).  Raises ``ValueError`` for a bad ``n`` or environment value.
    """
    import jax

    want = _wanted_cpu_devices(n)
    _add_engine_xla_flags()
    if "xla_force_host_platform_device_count" in os.environ.get("XLA_FLAGS", ""):
        return len(jax.devices("cpu"))
    if getattr(jax.config, "jax_num_cpu_devices", None) is None:  # pragma: no cover - old JAX
        return len(jax.devices("cpu"))
    try:
        jax.config.update("jax_num_cpu_devices", want)
    except (RuntimeError, AttributeError):  # JAX already started: keep its device count
        pass
    return len(jax.devices("cpu"))


def compilation_cache_dir() -> str | None:
    """Where :func:`use_compilation_cache` keeps compiled kernels: ``$GEAR_RATTLE_JAX_CACHE`` if set (``0``,
    ``off`` or empty: nowhere, None), else ``$XDG_CACHE_HOME/gear-rattle/jax``, else
    ``~/.cache/gear-rattle/jax``."""
    raw = os.environ.get(JAX_CACHE_ENV)
    if raw is not None:
        raw = raw.strip()
        return None if raw.lower() in ("", "0", "off", "false", "no") else os.path.expanduser(raw)
    base = os.environ.get("XDG_CACHE_HOME", "").strip() or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "gear-rattle", "jax")


def use_compilation_cache(path: str | None = None, note=None) -> str | None:
    """Turn on JAX's persistent compilation cache in ``path`` (default :func:`compilation_cache_dir`)
    and return the directory used, or None (turned off, or not writable).

    The command line calls it at start-up (never the library): every command compiles the engine and
    the map anew otherwise, ~10 s of XLA per block width and device.  Compilations shorter than
    :data:`CACHE_MIN_COMPILE_S` are not stored (small eager operations: not worth a file).  The cache
    can never break a command: a directory that cannot be created or written leaves the cache off with
    one ``note(message)`` (default: a line on stderr); an unreadable or corrupt entry is a miss that JAX
    recompiles, reported as a warning (one line through the command line's warning boundary).  A cached
    kernel is the compiled one: results are bitwise the same (docs/engine.md)."""
    import tempfile

    path = compilation_cache_dir() if path is None else path
    if path is None:
        return None
    try:
        os.makedirs(path, exist_ok=True)
        with tempfile.TemporaryFile(dir=path, prefix=".gear-rattle-probe-"):
            pass
    except OSError as e:
        msg = (
            f"JAX compilation cache off: cannot write {path!r} ({e.strerror or e}); set {JAX_CACHE_ENV}=0 "
            "to silence this, or to a writable directory"
        )
        if note is None:
            print(f"gear-rattle: note: {msg}", file=sys.stderr)  # noqa: T201 - the command line's note
        else:
            note(msg)
        return None
    import jax

    jax.config.update("jax_compilation_cache_dir", path)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", CACHE_MIN_COMPILE_S)
    # worker processes this one starts (the atlas's Dask workers) read JAX's own variables
    os.environ.setdefault("JAX_COMPILATION_CACHE_DIR", path)
    os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", str(CACHE_MIN_COMPILE_S))
    return path


__all__ = [
    "float64_jax",
    "positive",
    "JAX_CACHE_ENV",
    "CACHE_MIN_COMPILE_S",
    "CPU_DEVICES_ENV",
    "XLA_TUNING_ENV",
    "ENGINE_XLA_FLAGS",
    "ENGINE_XLA_TESTED",
    "jaxlib_version",
    "engine_xla_flags",
    "xla_tuning_active",
    "use_cpu_devices",
    "compilation_cache_dir",
    "use_compilation_cache",
]
