"""Descriptors by hand on tiny gaits: duty factors from the commands, turn and drift from the
poses."""

import math

import numpy as np
import pytest

from qdsega.adaptation.descriptor import (
    DRIFT_BOUND_M,
    TURN_BOUND_RAD,
    duty_factors,
    turn_and_drift,
)
from qdsega.description import load_formation, resolve_formation
from qdsega.msm import LegLayout


def test_duty_factors_count_the_postures_with_each_leg_down():
    quadruped = load_formation(resolve_formation("quadruped"))
    layout = LegLayout.from_formation(quadruped)
    cycle = np.zeros((4, len(quadruped.joints)), dtype=np.int64)  # every leg down ...
    cycle[1, layout.lift[0]] = 1  # ... but the first leg up in one posture of four
    cycle[2:, layout.lift[2]] = 1  # and the third in two
    assert duty_factors(layout, cycle).tolist() == [0.75, 1.0, 0.5, 1.0]


def test_turn_and_drift_per_cycle_map_their_bounds_to_the_cube():
    # Two cycles of two steps: a quarter of the bound's turn and a drift of the bound per cycle.
    turn = TURN_BOUND_RAD / 2
    poses = np.array([[0, 0, 0], [0.1, 0, 0], [0.2, DRIFT_BOUND_M, turn / 2], [0.3, 0, turn],
                      [0.4, 2 * DRIFT_BOUND_M, turn]])  # fmt: skip
    assert turn_and_drift(poses, 2) == pytest.approx([0.625, 1.0])  # 0.5 + (1/4) / 2
    straight = np.array([[0, 0, 0], [0.1, 0, 0]])
    assert turn_and_drift(straight, 1).tolist() == [0.5, 0.5]
    assert turn_and_drift(straight[:1], 1).tolist() == [0.5, 0.5]  # no step completed
    spin = np.array([[0, 0, 0], [0, 0, 3.0], [0, 0, -3.0 + 2 * math.pi]])  # unwrapped: +3.28
    assert turn_and_drift(spin, 2)[0] == 1.0  # far past the bound, at the edge
