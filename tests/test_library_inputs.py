"""Bad input at the library's boundary (issue 29 items 4-5): a table of bad calls over every public
function -- the facade, the documented entry points and the documented low-level functions.

Every row calls one function with good arguments except one, and asserts that the call is refused at
once: a ``TypeError`` for a value of the wrong type (a str, None or a bool where a number is meant, a
nested list where a scalar or a 1-D list is meant) and a ``ValueError`` -- not a ``TypeError`` -- for a
value out of range (NaN, infinities, counts beyond their stated bound, tolerances below their floor or
above their ceiling), with a message that names the argument by its current name and says what is
allowed.  The checks are :mod:`gear_rattle.core.checks` (one helper per kind of value); the rows are
generated per kind from :data:`BAD` so that every argument of a kind meets the same bad values.

:func:`test_every_public_function_is_in_the_table` collects the public names -- the facade's
``__all__``, the entry points of ``tests/test_doctests.py``, the functions of ``docs/api/index.md`` and
the low-level functions the docs name (:data:`DOCUMENTED`) -- and fails on one the table does not
call, so a new public function cannot go in without its bad-input rows.

A refusal must come before any computation: every call runs under a 20 s alarm (``n_impacts=10**20``
ran on for minutes before the checks), and the whole table takes a few seconds.
"""

from __future__ import annotations

import contextlib
import importlib
import inspect
import math
import os
import re
import signal
from pathlib import Path

import numpy as np
import pytest
from flint import arb

import gear_rattle as gr
from gear_rattle.core.deprecation import UNSET
from gear_rattle.core.params import Params
from gear_rattle.core.paper import PAPER_BOX, PAPER_PARAMS

REPO = Path(__file__).resolve().parents[1]

T, V = TypeError, ValueError  # the two outcomes: the wrong type, a value out of range
NAN, INF = math.nan, math.inf

#: Bad values per kind of argument: ``(value, exception)``.  ``"none"`` rows are left out where None is
#: the argument's default (it means "not given" there).
BAD = {
    "real": [(NAN, V), (INF, V), (-INF, V), ("0.5", T), (None, T), (True, T), ([[0.5]], T), (1j, T)],
    "phase": [(NAN, V), (INF, V), (1e7, V), (-1e300, V), ("0.5", T), (None, T), (True, T), ([[0.0]], T)],
    "count": [(10**20, V), (-1, V), (NAN, V), (INF, V), (1.5, V), (True, T), ("3", T), (None, T)],
    "tol": [(INF, V), (NAN, V), (0.0, V), (-1.0, V), (1e-20, V), (1.0, V), ("1e-9", T), (True, T)],
    "wall": [(2, V), (0.5, V), (1, V), (True, T), (None, T), ("0", T)],
    "array": [([[0.9]], T), ("0.9", T), ([NAN], V), ([INF], V), ([], V), (None, T), ([True], T)],
    "choice": [("nope", V), (None, T), (3, T)],
    "params": [(None, T), ({"alpha": 3.0, "beta": 0.1, "gamma": 0.1, "r": 0.9}, T), (3.0, T)],
    "cparams": [(None, T), ("alpha", T), (3.0, T), ([3.0, 0.1, 0.1, 0.9], T)],  # a Params or a mapping
    "prec": [(10**6, V), (32, V), (True, T), ("320", T)],
}

#: Extra out-of-range values of an argument (beyond its kind's): ``"argument"`` or, for one function only,
#: ``"function.argument"`` -> values (each a ValueError).
RANGE = {
    "use_cpu_devices.n": [0, 1025],
    "lyapunov.n": [0],
    "lyapunov.n_impacts": [0, 5 * 10**7 + 1],
    "decide_stick.sdot": [],
    "decide_stick.theta": [1e7],
    "compute_tile.alpha": [[-1.0]],
    "compute_tile.r": [[0.0], [1.5]],
    "step_jacobian.tau": [1e7],
    "s0": [0.5, -1.5],
    "r": [0.0, 1.5],
    "alpha": [-1.0, 1e11],
    "beta": [0.0, -0.1],
    "gamma": [1e11],
    "sdot0": [0.0],
    "sdot": [0.0],
    "delta": [0.0, 11.0],
    "stick_time": [-1e-9, 0.1],
    "t_max": [0.0, 1e7],
    "radius_limit": [0.0, 2.0],
    "lanes": [0, 2**23],
    "block": [0],
    "chunk": [0],
    "cap": [0],
    "devices": [0, 10**6],
    "period": [0, 100_001],
    "impacts": [0],
    "turns": [0],
    "max_iter": [0, 10**5],
    "n_impacts": [10**7 + 1],
    "nx": [0, 10**5],
    "max_steps": [0],
    "max_evals": [0],
    "time_budget_s": [0.0],
    "workers": [0, 5000],
    "period_tol": [0.0, 1.0],
    "seed": [-1, 2**32],
    "tile": [0],
    "mu": [1.5],
    "values": [[1.5]],
    "deltas": [[0.0], [20.0]],
    "tau": [[1e7]],
    "theta": [[1e7]],
    "box": [[3.5, 3.0, 0.0, 0.5], [1.0, 2.0]],
    "guess": [[3.2]],
}

P = Params(3.0, 0.1, 0.1, 0.9)
FIG2 = Params(0.5, 0.1, 0.1, 0.9)
FOLD_THETA = [1.055, 2.017, 3.013, 4.172, 5.141, 6.102]
FOLD_SDOT = [-1.614, -1.343, -0.709, 1.734, 1.448, 0.829]


def _model():
    from gear_rattle.mapimpl.certified.model import Model

    return Model(P)


def _spec():
    from gear_rattle.validation.atlas.spec import AtlasSpec

    return AtlasSpec(n_alpha=2, n_r=2)


#: Bad values of a kind that are good for one argument: ``"function.argument"`` -> values (a tile's
#: points are 2-D, and an empty tile is answered empty).
SKIP = {"compute_tile.alpha": ([[0.9]], []), "compute_tile.r": ([[0.9]], [])}

#: Every public function: ``"module:name" -> (good keyword arguments, {argument: kind})``.  A good
#: argument given as a function is called to make it (objects that take an import to build).
FUNCTIONS: dict[str, tuple[dict, dict]] = {
    # the facade
    "gear_rattle:Params": (
        dict(alpha=3.0, beta=0.1, gamma=0.1, r=0.9),
        dict(alpha="real", beta="real", gamma="real", r="real"),
    ),
    "gear_rattle:orbit": (
        dict(params=P, tau0=0.0, sdot0=0.5, n_impacts=10, track="map"),
        dict(params="params", tau0="phase", sdot0="real", n_impacts="count", track="choice", s0="real?"),
    ),
    "gear_rattle:find_periodic": (
        dict(params=FIG2, tau0=2.034, sdot0=-0.7343, period=3),
        dict(params="params", tau0="phase", sdot0="real", period="count", turns="count", tol="tol", max_iter="count"),
    ),
    "gear_rattle:lyapunov": (
        dict(params=P, param="r", values=[0.9], n_impacts=100, transient=10),
        dict(
            params="params",
            param="choice",
            values="array?",
            n_impacts="count?",
            transient="count",
            tau0="phase",
            sdot0="real",
        ),
    ),
    # a result type refuses what no computation returns (issue 38 item 5); its other fields: EXTRA
    "gear_rattle:ImpactSequence": (
        dict(
            params=P,
            n=np.zeros(1, int),
            tau=np.zeros(1),
            theta=np.zeros(1),
            wall=np.zeros(1, int),
            sdot=np.ones(1),
            kind=np.array(["impact"]),
        ),
        dict(params="params"),
    ),
    "gear_rattle:transient_times": (
        dict(params=None, tau0=[3.2], sdot0=[0.3], cap=100, progress=False),
        dict(
            tau0="array",
            sdot0="array",
            params="params?",
            ic_mode="choice",
            delta="real?",
            deltas="array?",
            cap="count",
            sticking="choice",
            release="choice?",
            lanes="count?",
            stick_time="real?",
            devices="count?",
        ),
    ),
    "gear_rattle:use_cpu_devices": (dict(n=1), dict(n="count?")),
    # the documented entry points (tests/test_doctests.py, docs/api/index.md)
    "gear_rattle.mapimpl.finder:first_impact": (
        dict(tau0=0.0, s0=-0.5, v0=0.3, alpha=3.0, beta=0.1, gamma=0.1),
        dict(
            tau0="phase", s0="real", v0="real", alpha="real", beta="real", gamma="real", t_max="real", max_steps="count"
        ),
    ),
    "gear_rattle.mapimpl.orbit:map_orbit": (
        dict(params=P, tau0=0.0, sdot0=0.5, n_impacts=10),
        dict(params="params", tau0="phase", sdot0="real", n_impacts="count", s0="real?", chunk="count"),
    ),
    "gear_rattle.mapimpl.periodic:find_periodic": (
        dict(params=FIG2, tau0=2.034, sdot0=-0.7343, period=3),
        dict(params="params", tau0="phase", sdot0="real", period="count", turns="count", tol="tol", max_iter="count"),
    ),
    "gear_rattle.mapimpl.engine.driver:run": (
        dict(theta=[0.5], sdot=[1.0], wall=[0], params=P, cap=10, progress=False),
        dict(
            theta="array",
            sdot="array",
            wall="array",
            cap="count",
            lanes="count?",
            block="count",
            chunk="count?",
            stick_time="real",
            t_max="real",
            max_steps="count",
            devices="count?",
        ),
    ),
    "gear_rattle.mapimpl.engine.transients:transient_times": (
        dict(params=PAPER_PARAMS, tau0=[3.2], sdot0=[0.3], cap=100, progress=False),
        dict(
            tau0="array",
            sdot0="array",
            params="params?",
            ic_mode="choice",
            delta="real",
            deltas="array",
            cap="count",
            sticking="choice",
            release="choice?",
            lanes="count?",
            block="count",
            chunk="count?",
            stick_time="real",
            devices="count?",
        ),
    ),
    # the engine's settings as objects (issue 39): checked when made
    "gear_rattle.mapimpl.engine.options:StepRules": (
        dict(),
        dict(stick_time="real", t_max="real", max_steps="count"),
    ),
    "gear_rattle.mapimpl.engine.options:Execution": (
        dict(),
        dict(lanes="count?", block="count", chunk="count?", devices="count?"),
    ),
    "gear_rattle.mapimpl.engine.transients:TransientSettings": (
        dict(),
        dict(ic_mode="choice", delta="real", deltas="array", cap="count", sticking="choice", stick_time="real"),
    ),
    "gear_rattle.mapimpl.certified.contact:certified_flight": (
        dict(model=_model, tau0=arb(0), s0=-0.5, v0=arb(0.3)),
        dict(s0="real", prec="prec", t_max="real", max_evals="count"),
    ),
    "gear_rattle.mapimpl.certified.orbit:certify_orbit": (
        dict(params=P, tau0=0.0, sdot0=0.5, n_impacts=10),
        dict(
            params="cparams",
            tau0="phase",
            sdot0="real",
            n_impacts="count",
            s0="real?",
            prec="prec",
            stick_time="real",
            radius_limit="real?",
            t_max="real",
        ),
    ),
    "gear_rattle.mapimpl.certified.track:certified_orbit": (
        dict(params=P, tau0=0.0, sdot0=0.5, n_impacts=3, progress=False),
        dict(
            params="cparams",
            tau0="phase",
            sdot0="real",
            n_impacts="count",
            s0="real?",
            stick_time="real",
            prec="prec",
            max_prec="prec",
            t_max="real",
            time_budget_s="real?",
        ),
    ),
    "gear_rattle.mapimpl.certified.duration:certified_release_duration": (
        dict(wall=0, delta=1e-3),
        dict(
            wall="wall",
            delta="real",
            rounding="choice",
            max_impacts="count",
            stick_time="real",
            radius_limit="real",
            time_budget_s="real?",
        ),
    ),
    "gear_rattle.mapimpl.certified.periodic:certify_periodic_orbit": (
        dict(params=FIG2, theta=[2.034, 4.110, 6.087], sdot=[-0.7343, 0.6229, 0.4421]),
        dict(params="cparams", theta="array", sdot="array", turns="count", prec="prec"),
    ),
    "gear_rattle.mapimpl.certified.periodic:certify_bifurcation": (
        dict(kind="fold", params=Params(3.0, 0.1, 0.1, 0.8), name="r", theta=FOLD_THETA, sdot=FOLD_SDOT, mu=0.8214),
        dict(
            kind="choice",
            params="cparams",
            name="choice",
            theta="array",
            sdot="array",
            mu="real",
            turns="count",
            prec="prec",
        ),
    ),
    "gear_rattle.validation.dynamics.crises.r2:locate_r2": (dict(profile="quick"), dict(profile="choice")),
    "gear_rattle.validation.dynamics.crises.r1:locate_r1": (
        dict(profile="quick"),
        dict(profile="choice", seed="count"),
    ),
    "gear_rattle.validation.dynamics.crises.alpha1:locate_alpha1": (
        dict(profile="quick"),
        dict(profile="choice", seed="count"),
    ),
    "gear_rattle.validation.atlas.compute:compute_tile": (
        dict(alpha=np.array([0.5]), r=np.array([0.9]), spec=_spec),
        dict(alpha="array", r="array"),
    ),
    "gear_rattle.validation.atlas.run:run_atlas": (
        dict(spec=_spec, store="never-created.zarr", scheduler="serial"),
        dict(tile="count"),
    ),
    "gear_rattle.validation.atlas.spec:AtlasSpec": (
        dict(),
        dict(
            alpha_lo="real",
            r_lo="real",
            beta="real",
            gamma="real",
            tau0="phase",
            sdot0="real",
            n_alpha="count",
            transient="count",
            impacts="count",
            period_max="count",
            period_tol="real",
        ),
    ),
    # the documented low-level functions (docs/*.md, README.md)
    "gear_rattle.mapimpl.sticking:release_phase": (
        dict(wall=0, alpha=3.0, beta=0.1, gamma=0.1),
        dict(wall="wall", alpha="real", beta="real", gamma="real"),
    ),
    "gear_rattle.mapimpl.sticking:decide_stick": (
        dict(theta=1.0, wall=0, sdot=0.5, alpha=3.0, beta=0.1, gamma=0.1, r=0.9),
        dict(
            theta="phase",
            wall="wall",
            sdot="real",
            alpha="real",
            beta="real",
            gamma="real",
            r="real",
            stick_time="real",
        ),
    ),
    "gear_rattle.mapimpl.lyapunov:lyapunov": (
        dict(params=P, param="r", values=[0.9], n_impacts=100, transient=10),
        dict(
            params="params",
            param="choice",
            values="array?",
            n_impacts="count",
            transient="count",
            tau0="phase",
            sdot0="real",
        ),
    ),
    "gear_rattle.mapimpl.tracks:orbit": (
        dict(track="map", params=P, tau0=0.0, sdot0=0.5, n_impacts=10),
        dict(
            track="choice",
            params="params",
            tau0="phase",
            sdot0="real",
            n_impacts="count",
            s0="real?",
            stick_time="real",
        ),
    ),
    "gear_rattle.mapimpl.tracks:step_jacobian": (
        dict(track="map", params=P, tau=0.0, sdot=0.5),
        dict(track="choice", params="params", tau="phase", sdot="real", wall="wall?"),
    ),
    "gear_rattle.mapimpl.certified.duration:certified_release_durations": (
        dict(wall=0, deltas=(1e-3,)),
        dict(wall="wall", deltas="array", max_impacts="count"),
    ),
    "gear_rattle.mapimpl.engine.transients:periodic_target": (
        dict(params=PAPER_PARAMS),
        dict(params="params", impacts="count", guess="array", settle="count"),
    ),
    "gear_rattle.mapimpl.engine.transients:grid": (
        dict(box=PAPER_BOX, nx=4, ny=4),
        dict(box="array", nx="count", ny="count"),
    ),
}

#: Rows beyond the per-kind ones: ``(function, {argument: bad value}, exception, word in the message)``.
EXTRA = [
    ("gear_rattle:find_periodic", dict(impacts=0, period=UNSET), V, "period"),  # old name: named anew
    ("gear_rattle:find_periodic", dict(period=0), V, "period"),
    ("gear_rattle:lyapunov", dict(n=10**20, n_impacts=UNSET), V, "n_impacts"),
    ("gear_rattle:lyapunov", dict(tau0=NAN), V, "tau0"),
    ("gear_rattle:lyapunov", dict(values="0.9"), T, "values"),
    ("gear_rattle:transient_times", dict(tau0=[3.2, 3.3]), V, "same length"),
    ("gear_rattle:transient_times", dict(ic_mode="free", s0=None), V, "s0"),
    ("gear_rattle:transient_times", dict(ic_mode="free", s0=0.5), V, "s0"),
    ("gear_rattle:transient_times", dict(sdot0=[0.0]), V, "sdot0"),
    ("gear_rattle:transient_times", dict(cap=10**9), V, "cap"),
    ("gear_rattle.mapimpl.engine.transients:transient_times", dict(target="orbit"), T, "target"),
    ("gear_rattle.mapimpl.engine.driver:run", dict(params=None), T, "params"),
    ("gear_rattle.mapimpl.engine.driver:run", dict(observers=[3]), T, "observers"),
    ("gear_rattle.mapimpl.engine.driver:run", dict(wall=[2]), V, "wall"),
    ("gear_rattle.mapimpl.engine.driver:run", dict(sdot=[0.0]), V, "sdot"),
    ("gear_rattle.mapimpl.engine.driver:run", dict(cap=3 * 10**9), V, "cap"),
    ("gear_rattle.mapimpl.engine.driver:run", dict(devices=[]), V, "devices"),
    ("gear_rattle.mapimpl.engine.driver:run", dict(rules=dict(stick_time=1e-6)), T, "rules"),
    ("gear_rattle.mapimpl.engine.driver:run", dict(execution=3), T, "execution"),
    ("gear_rattle.mapimpl.engine.transients:transient_times", dict(settings=dict(cap=3)), T, "settings"),
    ("gear_rattle.mapimpl.engine.transients:TransientSettings", dict(ic_mode="free", s0=None), V, "s0"),
    ("gear_rattle.mapimpl.engine.transients:TransientSettings", dict(ic_mode="free", s0=0.5), V, "s0"),
    ("gear_rattle.mapimpl.engine.options:Execution", dict(devices=[]), V, "devices"),
    ("gear_rattle.mapimpl.certified.contact:certified_flight", dict(model=P), T, "model"),
    ("gear_rattle.mapimpl.certified.contact:certified_flight", dict(tau0=0.0), T, "tau0"),
    ("gear_rattle.mapimpl.certified.contact:certified_flight", dict(tau0=arb("nan")), V, "tau0"),
    ("gear_rattle.mapimpl.certified.contact:certified_flight", dict(v0=None), T, "v0"),
    ("gear_rattle.mapimpl.certified.contact:certified_flight", dict(release=1), T, "release"),
    (
        "gear_rattle.mapimpl.certified.orbit:certify_orbit",
        dict(params={"alpha": "x", "beta": "0.1", "gamma": "0.1", "r": "0.9"}),
        V,
        "alpha",
    ),
    ("gear_rattle.mapimpl.certified.orbit:certify_orbit", dict(params={"alpha": "3"}), V, "params"),
    (
        "gear_rattle.mapimpl.certified.duration:certified_release_duration",
        dict(params_decimal=None),
        T,
        "params_decimal",
    ),
    ("gear_rattle.mapimpl.certified.duration:certified_release_duration", dict(precisions=[512, 256]), V, "precisions"),
    ("gear_rattle.mapimpl.certified.duration:certified_release_duration", dict(precisions=[10**6]), V, "prec"),
    ("gear_rattle.mapimpl.certified.duration:certified_release_duration", dict(precisions="256"), T, "precisions"),
    ("gear_rattle.mapimpl.certified.duration:certified_release_duration", dict(confirm="yes"), T, "confirm"),
    ("gear_rattle.mapimpl.certified.duration:certified_release_duration", dict(target=3), T, "target"),
    # the certified track computes no float64 orbit: the caller passes the target (issue 32 item 3)
    ("gear_rattle.mapimpl.certified.duration:certified_release_duration", dict(target=None), T, "target"),
    ("gear_rattle.mapimpl.certified.duration:certified_release_durations", dict(target=None), T, "target"),
    (
        "gear_rattle.mapimpl.certified.periodic:certify_periodic_orbit",
        dict(sdot=[-0.7343, 0.6229]),
        V,
        "same length|equal length",
    ),
    ("gear_rattle.mapimpl.certified.periodic:certify_bifurcation", dict(mu="0.8"), T, "mu"),
    ("gear_rattle.validation.dynamics.crises.r2:locate_r2", dict(sizes={"cap": NAN}), V, "sizes"),
    ("gear_rattle.validation.dynamics.crises.r2:locate_r2", dict(sizes={"orbits": 10**20}), V, "sizes"),
    ("gear_rattle.validation.dynamics.crises.r2:locate_r2", dict(sizes={"dr": [[1e-4]]}), T, "sizes"),
    ("gear_rattle.validation.dynamics.crises.r2:locate_r2", dict(sizes={"orbits": "2"}), T, "sizes"),
    ("gear_rattle.validation.dynamics.crises.r2:locate_r2", dict(sizes={"nope": 1}), V, "sizes"),
    ("gear_rattle.validation.dynamics.crises.r2:locate_r2", dict(sizes=[("cap", 1)]), T, "sizes"),
    ("gear_rattle.validation.dynamics.crises.r1:locate_r1", dict(sizes={"r_ref": INF}), V, "sizes"),
    ("gear_rattle.validation.dynamics.crises.alpha1:locate_alpha1", dict(sizes={"probe_ics": 0}), V, "sizes"),
    ("gear_rattle.validation.atlas.compute:compute_tile", dict(spec=None), T, "spec"),
    ("gear_rattle.validation.atlas.compute:compute_tile", dict(r=np.array([1.5])), V, "r"),
    ("gear_rattle.validation.atlas.run:run_atlas", dict(spec=None), T, "spec"),
    ("gear_rattle.validation.atlas.run:run_atlas", dict(scheduler="nowhere"), V, "scheduler"),
    ("gear_rattle.validation.atlas.run:run_atlas", dict(scheduler="local", workers=True), T, "workers"),
    ("gear_rattle.validation.atlas.run:run_atlas", dict(scheduler="local", workers=0), V, "workers"),
    ("gear_rattle.validation.atlas.run:run_atlas", dict(tile=(4, 1.5)), V, "tile_alpha"),
    ("gear_rattle.validation.atlas.spec:AtlasSpec", dict(n_alpha=4.0), V, "n_alpha"),
    ("gear_rattle.validation.atlas.spec:AtlasSpec", dict(alpha_lo=2.0, alpha_hi=1.0), V, "alpha_lo"),
    ("gear_rattle.mapimpl.tracks:orbit", dict(track="scipy", rtol=NAN), V, "rtol"),
    ("gear_rattle.mapimpl.tracks:orbit", dict(track="scipy", tau0=NAN), V, "tau0"),
    ("gear_rattle.mapimpl.tracks:orbit", dict(track="diffrax", n_impacts=10**20), V, "n_impacts"),
    ("gear_rattle:orbit", dict(track="scipy", atol="1e-9"), T, "atol"),
    ("gear_rattle:orbit", dict(s0=-0.5, sdot0=NAN), V, "sdot0"),
    # issue 38 item 5: progress= checked (5 and "yes" were taken for False), a pre-impact start's s0 refused
    # (it was ignored), a result that makes no sense refused (it said ok=True)
    ("gear_rattle:orbit", dict(progress=5), T, "progress"),
    ("gear_rattle:orbit", dict(progress="yes"), T, "progress"),
    ("gear_rattle:transient_times", dict(progress=[1]), T, "progress"),
    ("gear_rattle:transient_times", dict(s0=-0.5), V, "s0"),
    ("gear_rattle:transient_times", dict(ic_mode="pre-impact", s0="x"), V, "s0"),
    ("gear_rattle:ImpactSequence", dict(status="banana"), V, "status"),
    ("gear_rattle:ImpactSequence", dict(status="converged"), V, "status"),
    ("gear_rattle:ImpactSequence", dict(tau=np.zeros(2)), V, "tau"),
    ("gear_rattle:ImpactSequence", dict(kind=np.array(["boom"])), V, "kind"),
    ("gear_rattle:ImpactSequence", dict(wall=np.array([3])), V, "wall"),
    ("gear_rattle:ImpactSequence", dict(n=np.zeros((1, 1))), V, "n"),
]


def _rows():
    rows = []
    for target, (_good, kinds) in FUNCTIONS.items():
        for arg, kind in kinds.items():
            optional = kind.endswith("?")
            kind = kind.rstrip("?")
            key = f"{target.split(':')[1]}.{arg}"
            bad = [(v, e) for v, e in BAD[kind] if not (optional and v is None) and v not in SKIP.get(key, ())]
            bad += [(v, V) for v in RANGE.get(key, RANGE.get(arg, []))]
            for value, exc in bad:
                rows.append((target, {arg: value}, exc, _names(arg)))
    for target, changes, exc, word in EXTRA:
        rows.append((target, changes, exc, _names(word) if word.isidentifier() else word))
    return rows


def _names(arg: str) -> str:
    """The pattern of a message that names ``arg`` as its subject: it starts with ``arg=``, ``arg[``,
    ``arg is``, ``arg:`` or ``parameter arg=`` (``"sdot0=0.5 is out of range ... (and finite tau0)"`` does
    not name tau0)."""
    return rf"^(?:parameter )?{re.escape(arg)}(?=[=\[ :])"


ROWS = _rows()


def _function(target: str):
    module, name = target.split(":")
    return getattr(importlib.import_module(module), name)


@contextlib.contextmanager
def _alarm(seconds: float):
    """Fail a call that is not refused within ``seconds`` (it computes instead of checking)."""

    def ring(signum, frame):
        raise AssertionError(f"not refused within {seconds} s: the call runs")

    old = signal.signal(signal.SIGALRM, ring)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _id(row) -> str:
    target, changes, exc, _ = row
    return f"{target.split(':')[1]}-" + ",".join(f"{k}={v!r}"[:40] for k, v in changes.items())


def test_the_table_is_large():
    """The issue tried 183 bad calls; the table holds more, over every public function."""
    assert len(ROWS) > 300, len(ROWS)
    assert {r[0] for r in ROWS} == set(FUNCTIONS)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """An empty working directory for the table's calls: nothing may be written (and nothing lands in the
    repository if something is)."""
    path, old = tmp_path_factory.mktemp("refused"), os.getcwd()
    os.chdir(path)
    yield path
    os.chdir(old)


@pytest.mark.parametrize("row", ROWS, ids=[_id(r) for r in ROWS])
def test_bad_input_is_refused_naming_the_argument(row, workdir):
    target, changes, exc, word = row
    good = FUNCTIONS[target][0]
    kwargs = {k: (v() if callable(v) else v) for k, v in good.items()}
    kwargs.update(changes)
    with _alarm(20.0), pytest.raises(Exception) as info:
        _function(target)(**kwargs)
    e = info.value
    msg = str(e)
    assert isinstance(e, exc), f"{type(e).__name__} ({msg}), expected {exc.__name__}"
    if exc is ValueError:
        assert not isinstance(e, TypeError), f"a value out of range is a ValueError: {type(e).__name__}: {msg}"
    assert re.search(word, msg), f"the message does not name the argument ({word!r}): {msg}"
    assert "allowed" in msg or "same length" in msg or "equal length" in msg, f"no allowed range in: {msg}"
    assert not list(workdir.iterdir()), "a refused call wrote files"


# ------------------------------------------------------------------------------------------------------
# every public function is in the table


#: Low-level functions the docs (docs/*.md, README.md) name for users, besides the entry points.
DOCUMENTED = (
    "gear_rattle.mapimpl.sticking:release_phase",
    "gear_rattle.mapimpl.sticking:decide_stick",
    "gear_rattle.mapimpl.lyapunov:lyapunov",
    "gear_rattle.mapimpl.tracks:orbit",
    "gear_rattle.mapimpl.tracks:step_jacobian",
    "gear_rattle.mapimpl.certified.duration:certified_release_durations",
    "gear_rattle.mapimpl.engine.transients:periodic_target",
)


def _public() -> set[str]:
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    try:
        from test_doctests import ENTRY_POINTS
    finally:
        sys.path.pop(0)
    names = {f"gear_rattle:{n}" for n in gr.__all__ if inspect.isfunction(getattr(gr, n)) or n == "Params"}
    names |= {f"{m}:{n}" for m, n in ENTRY_POINTS}
    api = (REPO / "docs" / "api" / "index.md").read_text()
    for ref in re.findall(r"\{(?:func|class)\}`~?(gear_rattle\.[\w.]+)`", api):
        module, _, name = ref.rpartition(".")
        names.add(f"{module}:{name}")
    return names | set(DOCUMENTED)


def test_every_public_function_is_in_the_table():
    public = _public()
    assert len(public) >= 25, sorted(public)
    missing = sorted(public - set(FUNCTIONS))
    assert not missing, f"public functions without bad-input rows: {missing}"
    for target in public:
        _function(target)  # each name resolves


def test_documented_low_level_names_are_in_the_docs():
    """Each of :data:`DOCUMENTED` is named in README.md or docs/*.md (the list follows the docs)."""
    text = (REPO / "README.md").read_text() + "".join(p.read_text() for p in (REPO / "docs").glob("*.md"))
    for target in DOCUMENTED:
        module, name = target.split(":")
        short = module.removeprefix("gear_rattle.").split(".")[-1] + "." + name
        assert name in text and (short in text or f"`{name}`" in text or f"{name}(" in text), target
