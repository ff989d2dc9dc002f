"""The task's rules: eq. (17) by hand, the exterior bins, pose integration and its inverse."""

import math

import numpy as np
import pytest

from qdsega.task import (
    Task,
    TaskConfig,
    edge_directions,
    exterior_state,
    exterior_state_ahead,
    move_pose,
    relative_move,
)


def test_eq17_by_hand():
    # Light 10 m ahead; a step from x = 0 to x = 0.3 m gains 0.3 m: 100 * 0.3 = 30 with
    # distances in metres, 100 * 30 = 3000 with distances in centimetres.
    metres = Task(config=TaskConfig(), light_xy=(10.0, 0.0))
    assert metres.reward((0.0, 0.0, 0.0), (0.3, 0.0, 0.0)) == pytest.approx(30.0)
    centimetres = Task(config=TaskConfig(distance_unit_m=0.01), light_xy=(10.0, 0.0))
    assert centimetres.reward((0.0, 0.0, 0.0), (0.3, 0.0, 0.0)) == pytest.approx(3000.0)
    # Sideways from (0, 0) to (0, 1): d goes from 10 to sqrt(101), a loss.
    expected = 100.0 * (10.0 - math.sqrt(101.0))
    assert metres.reward((0.0, 0.0, 0.0), (0.0, 1.0, 0.0)) == pytest.approx(expected)
    assert metres.covered((0.0, 0.0, 0.0), (0.0, 1.0, 0.0)) == pytest.approx(expected / 100)


def test_exterior_bins():
    task = Task(config=TaskConfig(), light_xy=(10.0, 0.0))
    assert task.n_exterior == 4
    cases = {0.0: 2, math.radians(30): 1, math.radians(-30): 3, math.radians(60): 0, math.pi: 0}
    for heading, state in cases.items():
        assert task.exterior((0.0, 0.0, heading)) == state
        assert exterior_state(0.0, 0.0, heading, 10.0, 0.0, task.edges) == state


@pytest.mark.parametrize(
    "edges_deg", [(-45.0, -15.0, 15.0, 45.0), (-80.0, 0.0, 89.0), (-120.0, 0.0, 120.0)]
)
def test_the_fast_exterior_state_is_the_exact_one(edges_deg):
    # Random poses, plus poses whose light lies on an edge, a hair beside it, on the side or
    # behind: the cross-product test gives exterior_state's bin wherever it is sure, and
    # defers to it elsewhere (always, for edges that are not all ahead).
    rng = np.random.default_rng(0)
    edges = np.radians(np.asarray(edges_deg))
    directions = edge_directions(edges)
    light = (50.0, 3.0)
    poses = [tuple(p) for p in rng.uniform([-5, -5, -40], [5, 5, 40], size=(3000, 3))]
    for x, y in rng.uniform(-5, 5, size=(40, 2)):
        bearing = math.atan2(light[1] - y, light[0] - x)
        for angle in (*edges, math.pi / 2, -math.pi / 2, math.pi):
            for hair in (0.0, 1e-15, -1e-15, 1e-9, -1e-9, 1e-7, -1e-7):
                poses.append((x, y, bearing - angle + hair))
    for x, y, theta in poses:
        fast = exterior_state_ahead(
            x, y, theta, math.cos(theta), math.sin(theta), *light, edges, directions
        )
        assert fast == exterior_state(x, y, theta, *light, edges), (x, y, theta)


def test_a_body_frame_move_and_its_inverse():
    start = (1.0, 2.0, math.radians(90))
    end = move_pose(*start, 0.5, 0.1, 0.2)  # forward is +y, left is -x at 90 deg
    assert end == pytest.approx((0.9, 2.5, math.radians(90) + 0.2))
    assert relative_move(start, end) == pytest.approx((0.5, 0.1, 0.2))


@pytest.mark.parametrize(
    "change",
    [
        {"trial_steps": 0},
        {"reward_scale": 0.0},
        {"distance_unit_m": -1.0},
        {"distance_unit_m": math.nan},
        {"penalty": math.inf},
        {"exterior_bin_edges_deg": (10.0, -10.0)},
    ],
)
def test_bad_rules_are_refused(change):
    with pytest.raises(ValueError):
        TaskConfig(**change)


def test_bad_light_is_refused():
    with pytest.raises(ValueError, match="light_xy"):
        Task(config=TaskConfig(), light_xy=(np.nan, 0.0))
