import itertools
import math

import numpy as np
import pytest

from qdsega.baselines import classic_gaits
from qdsega.description import load_formation


@pytest.fixture(scope="module")
def legged12():
    return load_formation("assemblies/legged12.yaml")


def _leg_states(formation, postures):
    """Paper leg state (1..4) of every leg at every step, shape (steps, legs)."""
    return np.array(
        [
            [
                1
                + row[formation.joint_index(leg.swing_joint)]
                + 2 * row[formation.joint_index(leg.lift_joint)]
                for leg in formation.legs
            ]
            for row in postures
        ]
    )


@pytest.mark.parametrize("gait", classic_gaits.LEG_GAITS)
def test_every_leg_follows_the_stroke_cycle(legged12, gait):
    states = _leg_states(legged12, classic_gaits.leg_gait(legged12, gait=gait, steps=8))
    for column in states.T:
        start = classic_gaits.LEG_CYCLE.index(column[0])
        expected = [classic_gaits.LEG_CYCLE[(start + k) % 4] for k in range(8)]
        assert list(column) == expected


def test_alternating_gait_keeps_half_the_legs_down(legged12):
    states = _leg_states(legged12, classic_gaits.leg_gait(legged12, gait="alternating", steps=4))
    down = (states <= 2).sum(axis=1)
    assert list(down) == [6, 6, 6, 6]
    # neighbours along a side are half a cycle apart
    left = [legged12.legs.index(leg) for leg in legged12.legs_on("left")]
    assert all(states[0, a] != states[0, b] for a, b in itertools.pairwise(left))


def test_serpenoid_is_snapped_to_levels_and_travels_head_to_tail():
    snake = load_formation("assemblies/snake5.yaml")
    postures = classic_gaits.serpenoid(
        snake, amplitude_rad=math.radians(20), phase_lag_rad=math.pi / 2, steps_per_cycle=4, steps=4
    )
    angles = np.degrees([snake.posture_rad(row) for row in postures]).round()
    # Joint i+1 repeats joint i one step later: a wave running from head to tail.
    assert np.array_equal(angles[1:, 1:], angles[:-1, :-1])
    assert set(angles.flatten()) <= {-20.0, 0.0, 20.0}


def test_unknown_gait_and_legless_bodies_are_refused(legged12):
    with pytest.raises(ValueError, match="unknown gait"):
        classic_gaits.leg_gait(legged12, gait="gallop", steps=4)
    with pytest.raises(ValueError, match="has no legs"):
        classic_gaits.leg_gait(load_formation("assemblies/snake5.yaml"), gait="wave", steps=4)
