"""The certified post-release duration ``T_post``: a schedule of increasing precisions.

:func:`certified_release_durations` runs the certified release orbit (:mod:`.release`) at each
precision of a schedule until one decides every step up to the outcome, and confirms the outcome
at the next precision (docs/release.md).  The parameters are balls around the *decimal* values as
printed (``arb("1.245")``) or their exact float64 roundings (``rounding="float64"``).
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass
from functools import partial

from collections.abc import Callable, Mapping, Sequence

from ...core.checks import (
    MAX_IMPACTS as MAX_ORBIT_IMPACTS,
    InputTypeError,
    check_choice,
    check_int,
    check_real,
    check_wall,
)
from ...core.paper import DELTA, MAX_DELTA, PAPER_DECIMAL
from ...core.params import Params
from ..sticking import MAX_STICK_TIME, STICK_TIME
from .balls import MAX_PREC, CertificationError, check_prec, precision
from .capture import Target
from .model import PARAM_NAMES, Model
from .release import MAX_IMPACTS, RADIUS_LIMIT, Attempt, check_deltas, certify_post_release_deltas
from .sticking import release_phase

#: Precision schedule (bits) of :func:`certified_release_duration`.
PRECISIONS = (256, 512, 1024, 2048, 4096, 8192)
#: How the printed decimals enter the model: as exact decimals (balls) or as their float64 roundings (exact).
ROUNDINGS = ("decimal", "float64")


@dataclass
class ReleaseDuration:
    """The certified post-release duration of one wall's canonical release orbit.

    ``value``: ``T_post`` (``None`` unless ``status == "captured"``); ``status``: the certified
    outcome (``captured``, ``periodic``, ``stuck_forever``, ``no_capture`` within ``max_impacts``) or
    ``undecided`` (no precision decided it; ``lower_bound`` still holds); ``precision``: the first
    precision (bits) that decided it; ``confirmed``: the next precision gave the same outcome;
    ``lower_bound``: certified ``T_post > lower_bound`` (impacts certified not captured);
    ``attempts``: every run; ``seconds``: total wall time.
    """

    params: dict
    rounding: str
    wall: int
    delta: float
    max_impacts: int
    target: dict
    release_phase: str
    status: str
    value: int | None
    precision: int | None
    confirmed: bool
    lower_bound: int
    attempts: list
    seconds: float

    def to_dict(self) -> dict:
        d = asdict(self)
        d["attempts"] = [asdict(a) for a in self.attempts]
        return d

    def summary(self) -> str:
        what = {
            "captured": f"T_post = {self.value}",
            "periodic": "never captured (periodic)",
            "stuck_forever": "stuck forever",
            "no_capture": f"T_post > {self.max_impacts}",
            "undecided": f"undecided (T_post > {self.lower_bound} certified)",
        }[self.status]
        conf = "confirmed" if self.confirmed else "NOT confirmed"
        at = f" at {self.precision} bits, {conf} at the next precision" if self.precision else ""
        kind = "exact decimal" if self.rounding == "decimal" else "float64-rounded"
        return (
            f"wall {self.wall}, {kind} parameters "
            f"(alpha={self.params['alpha']}, beta={self.params['beta']}, gamma={self.params['gamma']}, "
            f"r={self.params['r']}): {what}{at} ({self.seconds:.1f} s)"
        )


def model_params(params_decimal: dict, rounding: str):
    """The parameters for :class:`.model.Model`: the decimal strings themselves (``"decimal"``) or
    the float64 numbers they round to (``"float64"``, exact binary values)."""
    check_choice("rounding", rounding, ROUNDINGS)
    missing = [k for k in PARAM_NAMES if k not in params_decimal]
    if missing or len(params_decimal) != len(PARAM_NAMES):
        raise ValueError(f"params_decimal={params_decimal!r}: allowed exactly the keys {', '.join(PARAM_NAMES)}")
    from ...core.params import check_value

    text = {k: str(params_decimal[k]).strip() for k in PARAM_NAMES}
    floats = Params(**{k: check_value(k, v) for k, v in text.items()})  # ValueError names the parameter
    return dict(text) if rounding == "decimal" else floats


def certified_release_duration(
    params_decimal: dict = PAPER_DECIMAL,
    wall: int = 0,
    delta: float = DELTA,
    *,
    rounding: str = "decimal",
    max_impacts: int = MAX_IMPACTS,
    precisions=PRECISIONS,
    confirm: bool = True,
    target: Target | None = None,
    stick_time: float = STICK_TIME,
    radius_limit: float = RADIUS_LIMIT,
    time_budget_s: float | None = None,
    progress=None,
) -> ReleaseDuration:
    """``T_post`` of ``wall``'s canonical release orbit for one capture distance ``delta``, certified
    (see module docstring): :func:`certified_release_durations` for ``(delta,)``.

    Parameters
    ----------
    params_decimal : dict, optional
        The parameters as decimal strings (default the paper's Figs. 9-11, alpha = 1.245).
    wall : {0, -1}, optional
        The wall released from.
    delta : float, optional
        The capture distance.
    rounding : {"decimal", "float64"}, optional
        Exact decimal parameters, or their float64 roundings (:data:`ROUNDINGS`).
    max_impacts : int, optional
        Most post-release impacts certified.
    precisions : sequence of int, optional
        Working precisions tried in turn until one decides (:data:`PRECISIONS`).
    confirm : bool, optional
        Rerun at the next precision and require the same outcome.
    target : Target
        The capturing orbit's points, taken as exact (required: :func:`mapimpl.engine.t_post.float64_target`
        gives the engine's stable 4-impact orbit; the certified track does not compute a float64 orbit).
    stick_time, radius_limit, time_budget_s, progress : optional
        The sticking threshold, the largest radius accepted, a time budget and a progress callback.

    Returns
    -------
    ReleaseDuration
        ``status`` (``captured``, ``periodic``, ``stuck_forever``, ``no_capture`` or ``undecided``),
        ``value`` (``T_post`` when captured), the precision that decided it and a certified lower bound.

    Examples
    --------
    The upper wall's release orbit at the paper's printed parameters is captured by the stable 4-impact
    orbit at post-release impact 824 (``delta = 1e-3``; docs/release.md):

    >>> from gear_rattle.core.paper import PAPER_PARAMS
    >>> from gear_rattle.mapimpl.certified.duration import certified_release_duration
    >>> from gear_rattle.mapimpl.engine.t_post import float64_target
    >>> target = float64_target(PAPER_PARAMS)
    >>> d = certified_release_duration(wall=0, delta=1e-3, max_impacts=2000, target=target)
    >>> d.status, d.value, d.confirmed
    ('captured', 824, True)
    """
    delta = check_real("delta", delta, 0.0, MAX_DELTA, lo_open=True)
    return certified_release_durations(
        params_decimal,
        wall,
        (delta,),
        rounding=rounding,
        max_impacts=max_impacts,
        precisions=precisions,
        confirm=confirm,
        target=target,
        stick_time=stick_time,
        radius_limit=radius_limit,
        time_budget_s=time_budget_s,
        progress=progress,
    )[float(delta)]


def certified_release_durations(
    params_decimal: dict = PAPER_DECIMAL,
    wall: int = 0,
    deltas=(DELTA,),
    *,
    rounding: str = "decimal",
    max_impacts: int = MAX_IMPACTS,
    precisions=PRECISIONS,
    confirm: bool = True,
    target: Target | None = None,
    stick_time: float = STICK_TIME,
    radius_limit: float = RADIUS_LIMIT,
    time_budget_s: float | None = None,
    progress=None,
) -> dict[float, ReleaseDuration]:
    """``T_post`` of ``wall``'s canonical release orbit for every capture distance of ``deltas``,
    certified (see module docstring): ``{delta: ReleaseDuration}``.

    Runs the orbit at each precision of ``precisions`` (increasing), every run deciding all the
    distances still open (:func:`.release.certify_post_release_deltas`: one orbit serves them all); a distance
    is decided by the first precision that decides every step up to its outcome, and with ``confirm``
    the next precision of the list (or twice the last one) must give it the same outcome, else
    :class:`.balls.CertificationError` (a bug).  Each distance gets exactly the attempts, value,
    precision and confirmation that a schedule for it alone would give; their runs are shared
    (``seconds``: the whole schedule).  ``params_decimal``: decimal strings ``{"alpha": "1.245", ...}``;
    ``rounding``: ``"decimal"`` (exact decimals, balls) or ``"float64"`` (their float64 roundings, exact).
    ``target``: the capture target, required (the engine's float64 4-impact orbit:
    :func:`mapimpl.engine.t_post.float64_target` of the float64 parameters; ``None`` is refused, naming it).
    ``time_budget_s``: wall-time budget of the whole schedule (an attempt past it fails, later ones are
    skipped).  ``progress(prec, n, radius)``: see :func:`.release.certify_post_release`.
    """
    check_choice("rounding", rounding, ROUNDINGS)
    if not isinstance(params_decimal, Mapping):
        raise InputTypeError(
            f"params_decimal is a {type(params_decimal).__name__}: allowed a mapping of alpha, beta, "
            "gamma, r to decimal strings"
        )
    pm = model_params(params_decimal, rounding)
    wall = check_wall("wall", wall)
    ds = check_deltas(deltas)
    max_impacts = check_int("max_impacts", max_impacts, 1, MAX_ORBIT_IMPACTS)
    precs = _check_precisions(precisions)
    if not isinstance(confirm, bool):
        raise InputTypeError(f"confirm={confirm!r} is a {type(confirm).__name__}: allowed True or False")
    if target is not None and not isinstance(target, Target):
        raise InputTypeError(f"target is a {type(target).__name__}: allowed None or a certified capture Target")
    stick_time = check_real("stick_time", stick_time, 0.0, MAX_STICK_TIME)
    radius_limit = check_real("radius_limit", radius_limit, 0.0, 1.0, lo_open=True)
    if time_budget_s is not None:
        time_budget_s = check_real("time_budget_s", time_budget_s, 0.0, lo_open=True)
    if target is None:
        raise InputTypeError(
            "target=None: allowed a certified capture Target (the certified track computes no float64 orbit: "
            "pass mapimpl.engine.t_post.float64_target(params), the engine's 4-impact periodic orbit)"
        )
    t0 = time.monotonic()
    deadline = None if time_budget_s is None else t0 + float(time_budget_s)
    with precision(128):
        ph = release_phase(Model(pm), wall)
    phase_text = "never" if ph is None else ph.str(30, radius=False)
    run_at = partial(
        certify_post_release_deltas,
        pm,
        wall,
        target=target,
        max_impacts=max_impacts,
        stick_time=stick_time,
        radius_limit=radius_limit,
        deadline=deadline,
        progress=progress,
    )
    attempts, decided, confirmed = _schedule(run_at, ds, precs, confirm, deadline)
    seconds = time.monotonic() - t0
    common = dict(
        params={k: str(params_decimal[k]).strip() for k in PARAM_NAMES},
        rounding=rounding,
        wall=wall,
        max_impacts=int(max_impacts),
        target=target.as_dict(),
        release_phase=phase_text,
        seconds=seconds,
    )
    return {d: _release_duration(d, decided[d], confirmed[d], attempts[d], common) for d in ds}


def _schedule(
    run_at: Callable[..., dict[float, Attempt]], ds: tuple, precs: list[int], confirm: bool, deadline: float | None
) -> tuple[dict[float, list[Attempt]], dict[float, Attempt | None], dict[float, bool]]:
    """The precision schedule of :func:`certified_release_durations` for the distances ``ds``:
    ``run_at(prec=, deltas=)`` is one run of the orbit.  Per distance: its attempts, the attempt that
    decided it (None: undecided) and whether the next precision confirmed it (a different definite outcome
    there raises :class:`.balls.CertificationError`: a bug)."""
    attempts: dict[float, list[Attempt]] = {d: [] for d in ds}
    decided: dict[float, Attempt | None] = {d: None for d in ds}
    confirmed = {d: False for d in ds}

    def confirm_with(d: float, b: Attempt) -> None:
        a = decided[d]
        assert a is not None, "only a decided distance is confirmed"
        if b.definite:
            if (b.status, b.impacts) != (a.status, a.impacts):
                raise CertificationError(
                    f"precisions {a.prec} and {b.prec} certify different outcomes at delta={d:g}: "
                    f"{a.status} at {a.impacts} vs {b.status} at {b.impacts} (a bug)"
                )
            confirmed[d] = True

    to_confirm: list[float] = []  # decided by the last run: confirmed (or not) by the next one
    for prec in precs:
        open_ = [d for d in ds if decided[d] is None]
        if not (open_ or to_confirm) or (deadline is not None and time.monotonic() > deadline):
            break
        run = run_at(prec=prec, deltas=open_ + to_confirm)
        for d in to_confirm:
            attempts[d].append(run[d])
            confirm_with(d, run[d])
        to_confirm = []
        for d in open_:
            attempts[d].append(run[d])
            if run[d].definite:
                decided[d] = run[d]
                if confirm:
                    to_confirm.append(d)
    # decided at the last precision of the list: confirmed at twice it
    nxt = min(2 * precs[-1], MAX_PREC)
    if to_confirm and nxt > precs[-1] and (deadline is None or time.monotonic() <= deadline):
        run = run_at(prec=nxt, deltas=to_confirm)
        for d in to_confirm:
            attempts[d].append(run[d])
            confirm_with(d, run[d])
    return attempts, decided, confirmed


def _check_precisions(precisions) -> list[int]:
    """The precision schedule ``precisions`` checked: a non-empty increasing sequence of bits (``check_prec``)."""
    if isinstance(precisions, (str, bytes)) or not isinstance(precisions, Sequence):
        raise InputTypeError(
            f"precisions={precisions!r} is a {type(precisions).__name__}: allowed a non-empty "
            f"increasing list of bits, 64 <= prec <= {MAX_PREC}"
        )
    precs = [check_prec(p) for p in precisions]
    if not precs or any(b <= a for a, b in zip(precs, precs[1:])):
        raise ValueError(f"precisions={precisions!r} is out of range: allowed a non-empty increasing list of bits")
    return precs


def _release_duration(
    delta: float, decided: Attempt | None, confirmed: bool, attempts: list[Attempt], common: dict
) -> ReleaseDuration:
    """The :class:`ReleaseDuration` of the distance ``delta`` from its schedule: the attempt that decided it
    (None: undecided), whether the next precision confirmed it, every attempt; ``common``: the fields shared
    by every distance.  ``lower_bound``: the most impacts an attempt certified not captured."""
    lower = max([b.impacts - (1 if b.status == "captured" else 0) for b in attempts] or [0])
    status = decided.status if decided is not None else "undecided"
    return ReleaseDuration(
        delta=delta,
        status=status,
        value=decided.impacts if decided is not None and status == "captured" else None,
        precision=decided.prec if decided is not None else None,
        confirmed=confirmed,
        lower_bound=lower,
        attempts=attempts,
        **common,
    )


__all__ = [
    "PRECISIONS",
    "ROUNDINGS",
    "ReleaseDuration",
    "model_params",
    "certified_release_duration",
    "certified_release_durations",
]
