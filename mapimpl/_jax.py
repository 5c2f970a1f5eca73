"""Import side effects of the project's JAX set-up.

* float64 everywhere (``jax_enable_x64``).
* On the CPU, one XLA device per available core (``jax_num_cpu_devices``), so that the transient
  engine (:mod:`validation.transient.engine`) can run one queue of orbits per core: a single XLA CPU
  device executes our small element-wise kernels on one thread.  Set ``GEAR_RATTLE_CPU_DEVICES=N``
  to choose ``N``; nothing is changed when ``XLA_FLAGS`` already sets
  ``--xla_force_host_platform_device_count``, when ``jax_num_cpu_devices`` was set, or when JAX has
  already started (the device count is then whatever it is).  Other computations run on the
  default device as before.
"""

import os

import jax

jax.config.update("jax_enable_x64", True)

_ENV = "GEAR_RATTLE_CPU_DEVICES"


def _wanted_cpu_devices() -> int:
    raw = os.environ.get(_ENV)
    if raw is None:
        try:
            return max(1, len(os.sched_getaffinity(0)))
        except (AttributeError, OSError):  # pragma: no cover - non-Linux
            return max(1, os.cpu_count() or 1)
    try:
        n = int(raw)
    except ValueError:
        n = 0
    if not 1 <= n <= 1024:
        raise ValueError(f"{_ENV}={raw!r} is out of range: allowed an integer 1 <= {_ENV} <= 1024")
    return n


# (jax_num_cpu_devices exists from JAX 0.5; older versions keep one CPU device)
if "xla_force_host_platform_device_count" not in os.environ.get("XLA_FLAGS", "") \
        and getattr(jax.config, "jax_num_cpu_devices", 0) < 0:
    _n = _wanted_cpu_devices()
    try:
        jax.config.update("jax_num_cpu_devices", _n)
    except (RuntimeError, AttributeError):  # JAX already started: keep its device count
        pass
