"""Scipy reference track (Eq. 3 integrated with solve_ivp/DOP853): events, traps, dense output."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mapimpl.params import Params
from reference import scipy_track as S
from refhelpers import map_one


def test_first_impact_matches_map_paper_parameters():
    p = Params(3.0, 0.1, 0.1, 0.9)
    seq = S.orbit(p, 0.0, 0.5, 3)
    assert seq.track == "scipy" and seq.status == "active"
    m, _ = map_one(p, 0.0, 0.5)
    assert seq.wall[1] == int(m.wall)
    assert abs(seq.tau[1] - float(m.tau)) < 1e-10
    assert abs(seq.sdot[1] - float(m.sdot)) < 1e-10
