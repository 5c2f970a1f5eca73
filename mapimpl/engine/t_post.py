"""The post-release duration ``T_post`` from the source asked for: the float64 engine's own
post-release orbit (a sample) or certified in ball arithmetic (:mod:`mapimpl.certified`, docs/release.md).

:func:`float64_target` is the capture target the certified runs are given: the engine's float64
periodic orbit (the certified track itself imports nothing of the float64 kernels).
:func:`release_for` gives the :class:`~.release.TPost` of a transient run at one capture distance
from a :class:`~.release.ReleaseSource`; :func:`certified_t_post` runs (once per setting in a process)
the schedule of certified runs that decides ``T_post`` of one wall at every capture distance asked for.
The composition itself is :func:`.release.compose_durations`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from ...core.paper import DELTA
from ...core.params import Params
from ...core.progress import Bar, wanted
from ..certified.capture import Target
from ..certified.duration import ReleaseDuration, certified_release_durations, model_params
from ..sticking import STICK_TIME
from .release import TPost, ReleaseSource, WallTPost, float64_t_post

#: The certified outcomes that decide ``T_post``: a capture (its value), or never captured.
NEVER_CAPTURED = ("periodic", "stuck_forever", "no_capture")


def decimal_params(params: Params) -> dict:
    """The parameters as printed: the shortest decimal of each float64 (``repr``), e.g. ``"1.245"``;
    the certified ``T_post`` is computed for these exact decimals."""
    return {k: repr(float(v)) for k, v in params.as_dict().items()}


def float64_target(params: Params) -> Target:
    """The capture target of a certified ``T_post``: the engine's float64 4-impact period-1 orbit
    (:func:`.transients.periodic_target` of ``params``), its pre-impact points taken as exact numbers
    (a :class:`mapimpl.certified.capture.Target`, the ``target`` of
    :func:`mapimpl.certified.certified_release_durations`).  (The engine is imported on first use: this
    module's readers -- plots, results -- need no JAX.)"""
    from .transients import periodic_target

    t = periodic_target(params)
    return Target(tuple(float(x) for x in t.theta), tuple(float(x) for x in t.sdot), tuple(int(w) for w in t.wall))


@dataclass(frozen=True)
class CertifiedKey:
    """Every argument that decides a schedule of certified runs (:func:`certified_t_post`)."""

    params_decimal: tuple[tuple[str, str], ...]
    wall: int
    deltas: tuple[float, ...]
    rounding: str
    stick_time: float
    confirm: bool


def certified_t_post(
    params: Params,
    wall: int,
    deltas=(DELTA,),
    *,
    rounding: str = "decimal",
    stick_time: float = STICK_TIME,
    confirm: bool = True,
    progress=None,
) -> Mapping[float, ReleaseDuration]:
    """``{delta: ReleaseDuration}``: the certified post-release duration of ``wall``'s canonical release
    orbit at every capture distance of ``deltas``, for :func:`decimal_params` of ``params``
    (``rounding="decimal"``) or their float64 roundings (``"float64"``):
    :func:`mapimpl.certified.certified_release_durations`, one schedule for all the distances (its
    ``seconds`` is that schedule's time).  Computed once per setting in a process (the report asks for
    the same orbit in several experiments): the typed results are kept under a :class:`CertifiedKey`
    of every argument that decides them.  ``progress``: a bar of the certified run's impacts
    (:mod:`gear_rattle.core.progress`)."""
    ds = tuple(sorted({float(d) for d in deltas}, reverse=True))
    key = CertifiedKey(
        tuple(sorted(decimal_params(params).items())), int(wall), ds, rounding, float(stick_time), bool(confirm)
    )
    if key not in _SCHEDULES:
        _SCHEDULES[key] = _certify(key, progress)
    return _SCHEDULES[key]


#: The schedules certified in this process (typed, read-only), under every argument that decides them.
_SCHEDULES: dict[CertifiedKey, Mapping[float, ReleaseDuration]] = {}


def _certify(key: CertifiedKey, progress) -> Mapping[float, ReleaseDuration]:
    """The schedule of certified runs of one :class:`CertifiedKey`, with a progress bar."""
    with Bar(
        f"certified T_post (wall {key.wall}, {key.rounding} parameters)",
        enabled=wanted(progress),
        phase="ball arithmetic",
    ) as bar:

        def prog(prec, n, radius):
            bar.postfix(f"{prec} bits, radius {radius}")
            bar.update(n)

        params_decimal = dict(key.params_decimal)
        out = certified_release_durations(
            params_decimal,
            key.wall,
            key.deltas,
            rounding=key.rounding,
            confirm=key.confirm,
            target=float64_target(model_params(params_decimal, "float64")),
            stick_time=key.stick_time,
            progress=prog,
        )
    return MappingProxyType(out)


def certified_value(c: ReleaseDuration) -> tuple[int | None, bool]:
    """``(T_post, decided)`` of a certification: the certified value, ``None`` for a certified 'never
    captured' outcome, or ``(None, False)`` when the certification was undecided."""
    if c.status == "captured":
        return c.value, True
    return None, c.status in NEVER_CAPTURED


def release_for(
    res,
    delta: float | None = None,
    source: ReleaseSource | str = ReleaseSource.FLOAT64,
    *,
    deltas=None,
    confirm: bool = True,
    stick_time: float = STICK_TIME,
    progress=None,
) -> TPost:
    """The :class:`~.release.TPost` of the transient run ``res`` (a
    :class:`~.transients.TransientResult`) at ``delta`` (default its main one) from ``source``: the
    engine's own post-release orbit of every wall stuck to, or its certified ``T_post``
    (:func:`certified_t_post` in one schedule for ``deltas``, default all the run's capture distances,
    with ``stick_time`` and ``confirm`` as given) -- the float64 sample where a certification was undecided (``WallTPost.undecided``: then the
    text must say so)."""
    source = ReleaseSource.of(source)
    j = res.column(delta)
    sample = float64_t_post(res.post_release, res.deltas, delta=float(res.deltas[j]), column=j)
    if source is ReleaseSource.FLOAT64:
        return sample
    d = float(res.deltas[j])
    together = tuple({d, *(float(x) for x in (res.deltas if deltas is None else deltas))})
    walls = {}
    for w, s in sample.walls.items():
        c = certified_t_post(
            res.params,
            w,
            together,
            rounding=str(source.rounding),
            stick_time=stick_time,
            confirm=confirm,
            progress=progress,
        )[d]
        v, decided = certified_value(c)
        walls[w] = (
            WallTPost(w, v, source, s.float64_sample, c)
            if decided
            else WallTPost(w, s.value, ReleaseSource.FLOAT64, s.float64_sample, c, undecided=True)
        )
    return TPost(source, d, walls)


__all__ = [
    "NEVER_CAPTURED",
    "decimal_params",
    "float64_target",
    "CertifiedKey",
    "certified_t_post",
    "certified_value",
    "release_for",
]
