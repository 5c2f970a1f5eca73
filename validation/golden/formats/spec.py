"""A case before it is certified (:class:`Spec`): what its ``settings.json`` will say -- parameters, start,
impacts, sticking threshold, level, bug classes, tags and notes -- and how it is certified (precision,
ending, extras).  The catalogue (:mod:`..catalog.specs`) lists the shipped cases as specs, the oracle
(:mod:`..oracle.ondemand`) makes one of an input; :func:`spec_from_settings` reads one back from a committed
``settings.json`` (to re-certify it without the searches), :func:`.case_writer.settings_json` writes it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from ....core.params import Params
from ....mapimpl.certified import PREC
from ....mapimpl.sticking import STICK_TIME

__all__ = ["Spec", "spec_from_settings"]


@dataclass
class Spec:
    """A case to certify (module docstring); the fields are those of its ``settings.json``, then how it is
    certified."""

    id: str
    description: str
    params: Params
    tau0: float
    sdot0: float
    n_impacts: int
    s0: float | None = None
    tags: tuple = ()
    notes: dict = field(default_factory=dict)
    prec: int = PREC
    #: computes the settings that are expensive to find (run only when the case is built)
    finish: Callable | None = field(default=None, repr=False, compare=False)
    #: 1 impact map, 2 sticking policy, 3 hard contacts and endings (:data:`.index.LEVELS`)
    level: int = 1
    #: bug classes the case exists to catch (:data:`.index.BUG_CLASSES`)
    catches: tuple = ()
    #: how the orbit ends: ``"active"`` or ``"stuck_forever"`` (:func:`mapimpl.certified.certify_orbit`), or
    #: ``"no_impact"`` (:func:`mapimpl.certified.certify_no_impact_orbit`)
    ending: str = "active"
    #: certified extras recorded in the notes before the settings are written: ``"excursion"`` (a
    #: graze), ``"policy"`` (the sticking decision at impact 0)
    extras: tuple = ()
    #: the sticking policy's threshold (``stick_time`` of the settings; the shipped cases: STICK_TIME)
    stick_time: float = STICK_TIME


def spec_from_settings(settings: dict, prec: int = PREC) -> Spec:
    """The :class:`Spec` of a committed ``settings.json`` (to re-certify a case without the searches)."""
    ini = settings["initial_state"]
    return Spec(
        settings["id"],
        settings["description"],
        Params(**settings["params"]),
        ini["tau0"],
        ini["sdot0"],
        int(settings["n_impacts"]),
        s0=ini.get("s0"),
        tags=tuple(settings.get("tags", ())),
        notes=dict(settings.get("notes", {})),
        prec=prec,
        level=int(settings.get("level", 1)),
        catches=tuple(settings.get("catches", ())),
        ending="no_impact" if settings["expected_status"] == "no_impact" else "active",
        stick_time=float(settings.get("stick_time", STICK_TIME)),
    )
