"""The post-release orbit in the Figs. 9-11 durations (issue 10 item 3): certified ``T_post`` and the
durations of the orbits that stick.

Every orbit that sticks to a wall is released at that wall's canonical phase with sdot = 0
(:func:`mapimpl.sticking.release_phase`), so all of them continue on ONE post-release orbit, and an
initial condition that first sticks at its impact ``n_s`` has duration ``n_s + T_post`` (the capture
rule :func:`mapimpl.engine.transients.compose_release`).  The float64 engine's ``T_post`` is a sample
(the orbit is chaotic and float64 loses it after ~60 impacts); the value used here is certified in
ball arithmetic (:mod:`mapimpl.certified`, docs/release.md).
"""

from __future__ import annotations

import numpy as np

from ...core.paper import DELTA
from ...core.params import Params
from ...mapimpl.engine.transients import TransientResult
from ...mapimpl.sticking import STICK_TIME

#: Where the durations of the orbits that stick come from: ``certified`` (T_post in ball arithmetic
#: for the decimal parameters as printed) or ``float64`` (the engine's own post-release orbit, a sample).
RELEASE_SOURCES = ("certified", "float64")
#: The walls an orbit can stick to, as the keys of the per-wall entries (``"0"``: s = 0, ``"-1"``: s = -1).
WALLS = (0, -1)


def decimal_params(params: Params) -> dict:
    """The parameters as printed: the shortest decimal of each float64 (``repr``), e.g. ``"1.245"``;
    the certified ``T_post`` is computed for these exact decimals."""
    return {k: repr(float(v)) for k, v in params.as_dict().items()}


#: The certifications done in this process (the report asks for the same orbit in several experiments).
_CACHE: dict = {}


def _certified(pdec: tuple, wall: int, deltas: tuple, rounding: str, stick_time: float, confirm: bool,
               progress=None) -> dict:
    from ...core.progress import Bar, wanted
    from ...mapimpl.certified import certified_release_durations

    key = (pdec, wall, deltas, rounding, stick_time, confirm)
    if key in _CACHE:
        return _CACHE[key]
    with Bar(f"certified T_post (wall {wall}, {rounding} parameters)", enabled=wanted(progress),
             phase="ball arithmetic") as bar:
        def prog(prec, n, radius):
            bar.postfix(f"{prec} bits, radius {radius}")
            bar.update(n)

        rs = certified_release_durations(dict(pdec), wall, deltas, rounding=rounding, confirm=confirm,
                                         stick_time=stick_time, progress=prog)
    out = {}
    for d, r in rs.items():
        dd = r.to_dict()
        out[d] = {k: dd[k] for k in ("params", "rounding", "wall", "delta", "status", "value", "precision",
                                     "confirmed", "lower_bound", "release_phase", "seconds")}
    _CACHE[key] = out
    return out


def certified_t_post(params: Params, wall: int, delta: float = DELTA, *, deltas=None, rounding: str = "decimal",
                     stick_time: float = STICK_TIME, confirm: bool = True, progress=None) -> dict:
    """The certified post-release duration of ``wall``'s canonical release orbit at capture distance
    ``delta`` (:func:`mapimpl.certified.certified_release_durations` for :func:`decimal_params`),
    as a dict (``value``, ``status``, ``precision``, ``confirmed``, ``lower_bound``, ``seconds``, ...).

    ``deltas``: all the capture distances the caller will ask for (containing ``delta``): one schedule
    of certified runs decides them all (one orbit serves every distance; ``seconds`` is that schedule's
    time).  Cached per process: the report asks for the same orbit in several experiments.  ``progress``:
    a bar of the certified run's impacts (:mod:`gear_rattle.core.progress`)."""
    ds = tuple(sorted({float(d) for d in (deltas if deltas is not None else ())} | {float(delta)}, reverse=True))
    out = _certified(tuple(sorted(decimal_params(params).items())), int(wall), ds, rounding, float(stick_time),
                     bool(confirm), progress)
    return dict(out[float(delta)])


def t_post_value(c: dict) -> tuple[int | None, bool]:
    """``(T_post for TransientResult.duration, usable)`` of a certification dict
    (:func:`certified_t_post`): the certified value, ``None`` for a certified 'never captured' outcome,
    or ``(None, False)`` when the certification was undecided."""
    if c["status"] == "captured":
        return int(c["value"]), True
    if c["status"] in ("periodic", "stuck_forever", "no_capture"):
        return None, True
    return None, False


def release_durations(res: TransientResult, delta: float, *, source: str = "certified", confirm: bool = True,
                      stick_time: float = STICK_TIME, progress=None):
    """``(durations, censored, info)`` of a :class:`TransientResult` at ``delta``, the orbits that stick
    composed with the ``source`` post-release duration of their wall (``first_stick + T_post``).

    ``info``: per wall stuck to (``"0"``, ``"-1"``): ``certified`` (the certification dict),
    ``float64_sample`` (the engine's T_post, -1 beyond the cap), ``used`` (the T_post used; ``None``:
    never captured), ``source`` (``certified``, or ``float64 sample`` when the certification was
    undecided: then the text must say so)."""
    if source not in RELEASE_SOURCES:
        raise ValueError(f"source={source!r} is out of range: allowed one of {', '.join(RELEASE_SOURCES)}")
    j = res.column(delta)
    info = {}
    t_post = {}
    for rel in res.release:
        w = int(rel["wall"])
        sample = int(np.asarray(rel["T_post"])[j])
        entry = {"float64_sample": sample}
        if source == "certified":
            c = certified_t_post(res.params, w, float(res.deltas[j]), deltas=tuple(float(x) for x in res.deltas),
                                 stick_time=stick_time, confirm=confirm, progress=progress)
            v, ok = t_post_value(c)
            entry["certified"] = c
            entry["used"], entry["source"] = (v, "certified") if ok else (sample if sample >= 0 else None,
                                                                          "float64 sample (certification undecided)")
        else:
            entry["used"], entry["source"] = (sample if sample >= 0 else None), "float64 sample"
        t_post[w] = entry["used"]
        info[str(w)] = entry
    if source == "float64":
        dur, cens = res.duration(delta)
    else:
        dur, cens = res.duration(delta, t_post=t_post) if t_post else res.duration(delta)
    return dur, cens, info


def composed_mask(res: TransientResult, delta: float | None = None) -> np.ndarray:
    """Orbits whose duration comes from the release: they stuck before coming within ``delta``."""
    j = res.column(delta)
    raw = res.meta.get("hit_before_stick")
    m = res.first_stick >= 0
    return m & (raw[:, j] < 0) if raw is not None else m


def stick_counts(res: TransientResult, delta: float | None = None) -> dict:
    """Orbits that stick (before capture) per wall of their first sticking episode (``stick_wall``)."""
    m = composed_mask(res, delta)
    return {str(w): int(np.sum(m & (res.stick_wall == w))) for w in WALLS}
