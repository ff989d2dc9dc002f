"""Descriptors by hand on tiny gaits: duty factors from the footfalls, turn and drift from the
poses."""

import math

import numpy as np
import pytest

from qdsega.adaptation.descriptor import (
    DRIFT_BOUND_M,
    TURN_BOUND_RAD,
    GaitDescriptor,
    duty_factors,
    turn_and_drift,
)
from qdsega.description import load_formation, resolve_formation


def test_duty_factors_are_each_legs_share_of_checks_on_the_ground():
    legs = ((0, 1), (2, 3), (4,))  # two legs of two units and one of one
    contacts = np.zeros((4, 6), dtype=bool)  # four checks; unit 5 is the trunk
    contacts[:, 1] = True  # the first leg's foot always down ...
    contacts[0, 0] = True  # ... and its upper unit once: still one contact a check
    contacts[2:, 3] = True  # the second leg down in the last two checks
    contacts[:, 5] = True  # the trunk's contacts count for no leg
    assert duty_factors(legs, contacts).tolist() == [1.0, 0.5, 0.0]
    assert duty_factors(legs, contacts[:0]).tolist() == [0.5, 0.5, 0.5]  # no check


def test_a_legged_bodys_descriptor_is_its_legs_and_a_snakes_its_steering():
    quadruped = load_formation(resolve_formation("quadruped"))
    descriptor = GaitDescriptor.of(quadruped)
    assert descriptor.names == tuple(leg.name for leg in quadruped.legs)
    units = [u.name for u in quadruped.units]
    assert [[units[i] for i in leg] for leg in descriptor.legs] == [
        list(leg.units) for leg in quadruped.legs
    ]
    snake = GaitDescriptor.of(load_formation(resolve_formation("snake5")))
    assert snake.names == ("turn", "drift") and snake.size == 2
    poses = np.array([[0, 0, 0], [0.1, 0, 0]])
    assert snake(np.zeros((3, 5), dtype=bool), poses, 1).tolist() == [0.5, 0.5]


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
