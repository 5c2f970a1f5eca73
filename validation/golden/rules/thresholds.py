"""The states at a sticking threshold or just before a release, found by rule (docs/golden.md, "Cases"): the
pre-impact velocity whose impact has a given accumulation time (:func:`stick_ratio_sdot0`), and the
pre-impact state a given lead before the canonical release phase (:func:`release_lead_state`).  The shipped
catalogue (:mod:`..catalog.specs`) and the fuzzer's scenarios (:mod:`..fuzzing.scenarios`) find their
inputs with the same rules.
"""

from __future__ import annotations

from ....core.params import Params
from ....mapimpl import certified as cert
from ....mapimpl.sticking import STICK_TIME
from .decisions import forcing_in

__all__ = ["stick_ratio_sdot0", "release_lead_state"]


def stick_ratio_sdot0(params: Params, tau0: float, wall: int, ratio: float) -> float:
    """Pre-impact velocity on ``wall`` (6 significant digits) whose impact has t_acc = ratio * STICK_TIME:
    ``|sdot0| = ratio STICK_TIME (1 - r) f_in(tau0) / (2 r)``."""
    v = ratio * STICK_TIME * (1 - params.r) * forcing_in(params, tau0, wall) / (2 * params.r)
    if not v > 0:
        raise RuntimeError(f"the forcing does not press into wall {wall} at tau0={tau0}")
    v = float(f"{v:.6g}")
    return v if wall == 0 else -v


def release_lead_state(params: Params, wall: int, lead: float, t_acc: float) -> tuple[float, float]:
    """``(tau0, sdot0)``: a pre-impact state on ``wall`` ``lead`` before the canonical release phase
    (float64 nearest to the certified phase minus ``lead``) whose impact has accumulation time
    ``t_acc`` (``sdot0`` to 3 significant digits)."""
    with cert.precision(cert.PREC):
        phase = cert.release_phase(cert.Model(params), wall)
        if phase is None:
            raise ValueError(
                f"params={params!r} is out of range for wall={wall}: the contact force never stops "
                "pressing (|gamma| >= alpha sqrt(1 + beta^2) or alpha = 0): allowed parameters "
                "with a release phase"
            )
        tau0 = cert.nearest_float(phase - cert.exact(lead))
    v = t_acc * (1 - params.r) * forcing_in(params, tau0, wall) / (2 * params.r)
    v = float(f"{v:.3g}")
    return tau0, (v if wall == 0 else -v)
