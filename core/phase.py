"""The phase of the driving: ``tau = 2 pi cycles + theta`` with ``theta`` in ``[0, 2 pi)``.

Every track keeps the elapsed time as a phase and a whole-turn counter, so long orbits keep the
phase's digits; :func:`reduce_phase` is the one reduction (three-term Cody-Waite 2 pi).
"""

from __future__ import annotations

from . import jax_config  # noqa: F401  (float64)
import jax.numpy as jnp

TWO_PI = 2.0 * jnp.pi
# Cody-Waite split of 2*pi in three terms: TWO_PI_HI and TWO_PI_MID carry 33 significant bits each, so
# m * TWO_PI_HI and m * TWO_PI_MID are exact for |m| < 2^20 (|tau| < 6.5e6, beyond TAU0_MAX), and
# TWO_PI_HI + TWO_PI_MID + TWO_PI_LO == 2*pi to 4e-37.
TWO_PI_HI = float.fromhex("0x1.921fb54400000p+2")  # 6.2831853069365025
TWO_PI_MID = float.fromhex("0x1.0b4611a600000p-32")  # 2.4308402025215864e-10
TWO_PI_LO = 8.089064995183803e-21


def reduce_phase(theta, cycles):
    """Reduce ``theta`` into [0, 2 pi), carrying whole turns into the integer ``cycles``.

    Three-term Cody-Waite reduction (``TWO_PI_HI``, ``TWO_PI_MID``, ``TWO_PI_LO``): for any float64
    ``|theta| < 6.5e6`` the phase is within ~1 ulp of ``theta - m 2 pi`` (exact), so long orbits and
    large initial times do not drift in phase.
    """
    m = jnp.floor(theta / TWO_PI)
    th = ((theta - m * TWO_PI_HI) - m * TWO_PI_MID) - m * TWO_PI_LO
    # guard the rare rounding to exactly 2*pi or just below 0
    adj = jnp.where(th >= TWO_PI, 1.0, jnp.where(th < 0.0, -1.0, 0.0))
    th = ((th - adj * TWO_PI_HI) - adj * TWO_PI_MID) - adj * TWO_PI_LO
    # (where, not clip: the derivative stays 1 at theta = 0 for autodiff)
    th = jnp.where(th < 0.0, 0.0, jnp.where(th >= TWO_PI, jnp.nextafter(TWO_PI, 0.0), th))
    return th, cycles + (m + adj).astype(cycles.dtype)


__all__ = [
    "TWO_PI",
    "TWO_PI_HI",
    "TWO_PI_MID",
    "TWO_PI_LO",
    "reduce_phase",
]
