"""The project's JAX set-up.

Importing any ``gear_rattle`` module switches JAX to float64 (``jax_enable_x64``): every kernel
computes in double precision.  Nothing else happens on import.

:func:`use_cpu_devices` is the opt-in second half, called by the command line (and by tests and
benchmarks) before JAX starts: on the CPU, one XLA device per available core, so that the engine
(:mod:`gear_rattle.mapimpl.engine`) can run one queue of orbits per core -- a single XLA CPU device
executes its small element-wise kernels on one thread.  A library user who wants the same calls it
before the first JAX computation.
"""

from __future__ import annotations

import os

import jax

jax.config.update("jax_enable_x64", True)

#: Environment variable that sets the number of XLA CPU devices chosen by :func:`use_cpu_devices`.
CPU_DEVICES_ENV = "GEAR_RATTLE_CPU_DEVICES"


def _wanted_cpu_devices(n: int | None) -> int:
    if n is not None:
        raw, src = n, "n"
    else:
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
    if isinstance(raw, float) and raw != v:
        v = 0
    if not 1 <= v <= 1024:
        raise ValueError(f"{src}={raw!r} is out of range: allowed an integer 1 <= {src} <= 1024")
    return v


def use_cpu_devices(n: int | None = None) -> int:
    """Ask JAX for ``n`` XLA CPU devices (default: ``$GEAR_RATTLE_CPU_DEVICES``, else one per
    available core) and return the number of CPU devices JAX will use.

    Must run before JAX's first computation.  Nothing is changed when ``XLA_FLAGS`` already sets
    ``--xla_force_host_platform_device_count``, when JAX has already started (the count is then
    whatever it is), or on JAX versions without ``jax_num_cpu_devices`` (before 0.5).  Raises
    ``ValueError`` for a bad ``n`` or environment value.
    """
    want = _wanted_cpu_devices(n)
    if "xla_force_host_platform_device_count" in os.environ.get("XLA_FLAGS", ""):
        return len(jax.devices("cpu"))
    if getattr(jax.config, "jax_num_cpu_devices", None) is None:  # pragma: no cover - old JAX
        return len(jax.devices("cpu"))
    try:
        jax.config.update("jax_num_cpu_devices", want)
    except (RuntimeError, AttributeError):  # JAX already started: keep its device count
        pass
    return len(jax.devices("cpu"))
