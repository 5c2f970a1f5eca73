"""The engine's settings as objects, each checked once, when it is made (as diffrax passes ``SaveAt``,
``PIDController`` and ``Event`` objects): a frozen dataclass whose constructor checks every field
(:mod:`gear_rattle.core.checks`: a ``ValueError`` naming the field and its range) and holds the checked
value, so that the functions it is handed to -- :func:`.driver.run`, :func:`.transients.transient_times`,
the analyses -- check nothing again.

* :class:`StepRules` -- how an orbit is computed: the sticking policy's chatter threshold
  (:mod:`mapimpl.sticking`) and the impact finder's caps (:mod:`mapimpl.finder`).  Results depend on them.
* :class:`Execution` -- how the orbits are spread: lanes per device, micro-steps per block, initial
  conditions per kernel launch, the devices.  Results do not depend on it (the kernel's determinism,
  :mod:`.kernel`).

What is measured along an orbit and when it stops are the observers (:mod:`.observers`); the impact
budget (``cap``) and the display (``progress``, ``label``) stay keywords of the calls (one value each,
given at nearly every call: docs/architecture.md, "Options as objects").
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ...core.checks import check_int, check_real
from ..finder import MAX_STEPS, T_MAX
from ..sticking import MAX_STICK_TIME, STICK_TIME

#: Largest ``Execution.lanes``, ``Execution.block`` and ``Execution.chunk``.
MAX_LANES, MAX_BLOCK, MAX_CHUNK = 1 << 22, 1 << 16, 1 << 26
#: Largest ``StepRules.t_max`` (time units) and ``StepRules.max_steps``.
MAX_T_MAX, MAX_MAX_STEPS = 1e6, 1_000_000


@dataclass(frozen=True)
class StepRules:
    """How every orbit of a run is computed: ``stick_time`` -- the sticking policy's chatter threshold
    (:data:`mapimpl.sticking.STICK_TIME`, ``0 <= stick_time <= 1e-2``); ``t_max`` and ``max_steps`` -- the
    impact finder's caps on one flight (``0 < t_max <= 1e6`` time units, ``1 <= max_steps <= 1e6`` safe
    steps; :data:`gear_rattle.core.horizons.T_MAX`, :data:`~gear_rattle.mapimpl.finder.MAX_STEPS`).  Checked when made."""

    stick_time: float = STICK_TIME
    t_max: float = T_MAX
    max_steps: int = MAX_STEPS

    def __post_init__(self) -> None:
        object.__setattr__(self, "stick_time", check_real("stick_time", self.stick_time, 0.0, MAX_STICK_TIME))
        object.__setattr__(self, "t_max", check_real("t_max", self.t_max, 0.0, MAX_T_MAX, lo_open=True))
        object.__setattr__(self, "max_steps", check_int("max_steps", self.max_steps, 1, MAX_MAX_STEPS))


@dataclass(frozen=True)
class Execution:
    """How the engine spreads a run (results do not depend on it): ``lanes`` -- orbits advanced together
    per device (default: :func:`.driver.default_lanes`; ``1 <= lanes <= 2**22``, padded to a multiple of
    :data:`.kernel.LANE_QUANTUM`); ``block`` -- micro-steps between refills of idle lanes (``1 <= block <=
    2**16``); ``chunk`` -- initial conditions per kernel launch (default: bounded by memory; ``1 <= chunk <=
    2**26``); ``devices`` -- a count of the default backend's devices or a sequence of JAX devices
    (default all; kept as a tuple).  Checked when made: a count against the devices JAX has, which starts
    JAX's backend (call :func:`gear_rattle.use_cpu_devices` first where it is wanted)."""

    lanes: int | None = None
    block: int = 32
    chunk: int | None = None
    devices: int | tuple | None = None

    def __post_init__(self) -> None:
        if self.lanes is not None:
            object.__setattr__(self, "lanes", check_int("lanes", self.lanes, 1, MAX_LANES))
        object.__setattr__(self, "block", check_int("block", self.block, 1, MAX_BLOCK))
        if self.chunk is not None:
            object.__setattr__(self, "chunk", check_int("chunk", self.chunk, 1, MAX_CHUNK))
        object.__setattr__(self, "devices", _checked_devices(self.devices))

    def device_list(self) -> list:
        """The JAX devices the run is spread over: ``devices`` (a count: the first ones of the default
        backend), default all devices of JAX's default backend."""
        import jax

        if self.devices is None:
            return list(jax.devices())
        if isinstance(self.devices, tuple):
            return list(self.devices)
        return list(jax.devices()[: self.devices])


def _checked_devices(devices) -> int | tuple | None:
    """``devices`` of :class:`Execution`, checked: None, a count ``1 <= devices <=`` the default backend's
    devices, or a non-empty sequence of JAX devices (as a tuple)."""
    if devices is None:
        return None
    import jax

    if isinstance(devices, Sequence) and not isinstance(devices, str):
        if not devices or not all(isinstance(d, jax.Device) for d in devices):
            raise ValueError(f"devices={devices!r} is out of range: allowed a count or a non-empty list of JAX devices")
        return tuple(devices)
    return check_int("devices", devices, 1, len(jax.devices()))


#: The engine's defaults (every field its default).
DEFAULT_RULES, DEFAULT_EXECUTION = StepRules(), Execution()

#: The keyword arguments that became fields of :class:`StepRules` and :class:`Execution` (issue 39): the
#: old calls ``run(..., lanes=8)`` still work, with a DeprecationWarning naming the object.
RULES_FIELDS = ("stick_time", "t_max", "max_steps")
EXECUTION_FIELDS = ("lanes", "block", "chunk", "devices")


def options_from_keywords(
    function: str,
    keywords: dict,
    rules: StepRules | None,
    execution: Execution | None,
    rule_fields: tuple[str, ...] = RULES_FIELDS,
    stacklevel: int = 3,
) -> tuple[StepRules, Execution]:
    """``(rules, execution)`` of a call of ``function`` that may still pass their fields as keywords (the
    old spelling, deprecated: one DeprecationWarning naming the new one); a keyword that is neither is a
    ``TypeError`` as Python gives it, and a field given both ways is an error.  ``rule_fields``: the
    fields of :class:`StepRules` that ``function`` took as keywords; ``stacklevel``: the warning's, as
    ``warnings.warn`` counts it from here (3: the caller of the function that calls this one)."""
    import warnings

    from ...core.checks import InputTypeError

    bad = sorted(set(keywords) - set(rule_fields) - set(EXECUTION_FIELDS))
    if bad:
        raise TypeError(f"{function}() got an unexpected keyword argument {bad[0]!r}")
    old_rules = {k: keywords[k] for k in rule_fields if k in keywords}
    old_exec = {k: keywords[k] for k in EXECUTION_FIELDS if k in keywords}
    for given, old, cls in ((rules, old_rules, "StepRules"), (execution, old_exec, "Execution")):
        if given is not None and old:
            raise InputTypeError(f"give {cls}(...) or its fields {sorted(old)} as keywords, not both")
    if rules is not None and not isinstance(rules, StepRules):
        raise InputTypeError(f"rules is a {type(rules).__name__}: allowed a StepRules or None")
    if execution is not None and not isinstance(execution, Execution):
        raise InputTypeError(f"execution is a {type(execution).__name__}: allowed an Execution or None")
    if old_rules or old_exec:
        spell = ", ".join(
            f"{name}={cls}({', '.join(f'{k}=...' for k in old)})"
            for name, cls, old in (("rules", "StepRules", old_rules), ("execution", "Execution", old_exec))
            if old
        )
        warnings.warn(
            f"{function}({', '.join(f'{k}=' for k in (*old_rules, *old_exec))}) is deprecated: use {spell} "
            "(gear_rattle.mapimpl.engine.options; same meaning)",
            DeprecationWarning,
            stacklevel=stacklevel,
        )
    rules = StepRules(**old_rules) if old_rules else (rules or DEFAULT_RULES)
    execution = Execution(**old_exec) if old_exec else (execution or DEFAULT_EXECUTION)
    return rules, execution


__all__ = [
    "StepRules",
    "Execution",
    "DEFAULT_RULES",
    "DEFAULT_EXECUTION",
    "RULES_FIELDS",
    "EXECUTION_FIELDS",
    "MAX_LANES",
    "MAX_BLOCK",
    "MAX_CHUNK",
    "options_from_keywords",
]
