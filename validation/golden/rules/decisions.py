"""The sticking-decision rule of ``gear-rattle case`` (docs/reference/golden_commands.md, "Asking the oracle"): a case does not
ask a sticking decision that an output within its own tolerances could take the other way.

At every impact the policy of :mod:`mapimpl.sticking` decides between a bounce and sticking: where the force
presses into the wall (``f_in > 0``) the tooth sticks when ``t_acc = 2 r |sdot| / ((1 - r) f_in) <=
stick_time`` and the release delay is longer than ``t_acc``.  The scorer accepts an implementation whose
``tau`` and ``sdot`` at that impact are off by up to the case's tolerances; with those values its ``t_acc`` is
off by up to ``t_acc (tol_sdot / |sdot| + |f_in'| tol_tau / f_in)`` and its release delay by ``tol_tau``.  Where
that reaches the threshold (or the delay), such an implementation may take the other decision -- and then
fails the case on its events although every number it printed was within tolerance.  The case stops at that
impact instead (its decision is no longer asked), as the near-miss rule stops a case before a contact that
a correct implementation may take either way.  A pre-impact initial state is exact: its decision is asked.

Deep chatter makes it matter: the slowest bounces of a chatter stopped by a small ``stick_time`` (1e-7 and
below) land at ``|sdot| ~ 1e-7``, where the tolerance 1e-9 is 1 % of the speed (found by ``gear-rattle fuzz``:
our diffrax track, within 1.4 % of the speed there, bounced where the certified orbit stuck).
"""

from __future__ import annotations

import math

import numpy as np

from ....core.params import Params
from ....mapimpl import certified as cert
from ....mapimpl.sticking import release_delay
from ..formats.case_writer import certified_rows
from ..formats.spec import Spec


def forcing_in(params: Params, tau: float, wall: int) -> float:
    """The contact force pressing into ``wall`` at ``tau`` (float64): ``f`` on wall 0, ``-f`` on wall -1."""
    f = -params.alpha * math.sin(tau) + params.alpha * params.beta * math.cos(tau) + params.gamma
    return f if wall == 0 else -f


def _rate_in(p, tau: float) -> float:
    """``|d f_in / d tau|`` at ``tau`` (``f = gamma - alpha sin(tau) + alpha beta cos(tau)``)."""
    return abs(-p.alpha * math.cos(tau) - p.alpha * p.beta * math.sin(tau))


def doubtful_decision(spec: Spec, orb: cert.CertifiedOrbit, tol_tau, tol_sdot) -> tuple[int, str] | None:
    """``(impact, note)``: the first impact of the case whose sticking decision an output within the given
    tolerances could take the other way (module docstring), or ``None``.  ``tol_tau``, ``tol_sdot``: the
    absolute tolerance of each row (arrays over the rows of ``orb``, or one number for all).
    Only the decisions the case asks count: an impact followed by a row of the case (the last impact of an
    active case is not decided); a pre-impact initial state is exact."""
    p, st = spec.params, float(spec.stick_time)
    if not p.r < 1:
        return None
    rows = certified_rows(orb)
    size = len(rows.kind)
    tt = np.broadcast_to(tol_tau, (size,))
    tv = np.broadcast_to(tol_sdot, (size,))
    for i, kind in enumerate(rows.kind):
        n, wall = int(rows.n[i]), int(rows.wall[i])
        if kind != "impact" or (n == 0 and spec.s0 is None) or i == size - 1:
            continue
        tau, v = float(rows.tau[i]), float(rows.sdot[i])
        f_in = forcing_in(p, tau, wall)
        if not f_in > 0 or v == 0:
            continue
        t_acc = 2 * p.r * abs(v) / ((1 - p.r) * f_in)
        dt_acc = t_acc * (tv[i] / abs(v) + _rate_in(p, tau) * tt[i] / f_in)
        why = ""
        if abs(t_acc - st) <= dt_acc:
            why = f"t_acc = {t_acc:.4g} within {dt_acc:.2g} of stick_time = {st:g}"
        elif t_acc < st:
            delay = float(release_delay(float(rows.tau_mod_2pi[i]), wall, p.alpha, p.beta, p.gamma))
            if abs(delay - t_acc) <= dt_acc + tt[i]:
                why = f"the release delay {delay:.4g} within {dt_acc + tt[i]:.2g} of t_acc = {t_acc:.4g}"
        if why:
            return n, (
                f"the sticking decision at impact {n} (speed {abs(v):.3g}) is in doubt within the tolerances "
                f"of its row (tau {tt[i]:g}, sdot {tv[i]:g}): {why} (the sticking-decision rule)"
            )
    return None


__all__ = ["forcing_in", "doubtful_decision"]
