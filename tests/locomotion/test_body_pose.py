import math

import numpy as np
import pytest

from qdsega.description import load_formation
from qdsega.locomotion.body_pose import BodyPoseEstimator


def _yaw_quaternion(yaw: float) -> list[float]:
    return [0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)]


def test_snake_heading_is_the_mean_direction_not_the_heads_yaw():
    snake = load_formation("assemblies/snake5.yaml")
    estimator = BodyPoseEstimator(formation=snake)
    # A wave: units yawed +30, -30, +30, -30, +30 deg around a body heading of 0.
    yaws = [math.radians(30 * (-1) ** i) for i in range(5)]
    positions = np.array([[-0.1 * i, 0.0, 0.025] for i in range(5)])
    quaternions = np.array([_yaw_quaternion(y) for y in yaws])
    pose = estimator.pose(positions, quaternions)
    assert pose.heading_rad == pytest.approx(math.atan2(math.sin(yaws[0]) / 5, math.cos(yaws[0])))
    assert abs(pose.heading_rad) < math.radians(7)  # the head alone would say 30 deg
    assert pose.x_m == pytest.approx(-0.2)
    assert pose.max_tilt_rad == pytest.approx(0.0, abs=1e-9)


def test_legged_pose_uses_the_trunk_only():
    legged = load_formation("assemblies/legged12.yaml")
    estimator = BodyPoseEstimator(formation=legged)
    count = len(legged.units)
    positions = np.zeros((count, 3))
    quaternions = np.tile(_yaw_quaternion(math.radians(90)), (count, 1))
    for i, unit in enumerate(legged.units):
        if unit.name.startswith(("L", "R")):  # legs point elsewhere and sit far away
            quaternions[i] = _yaw_quaternion(math.radians(-45))
            positions[i] = [5.0, 5.0, 0.0]
    pose = estimator.pose(positions, quaternions)
    assert pose.heading_rad == pytest.approx(math.radians(90))
    assert (pose.x_m, pose.y_m) == pytest.approx((0.0, 0.0))


def test_tilt_of_a_rolled_unit():
    snake = load_formation("assemblies/snake5.yaml")
    estimator = BodyPoseEstimator(formation=snake)
    quaternions = np.tile([0.0, 0.0, 0.0, 1.0], (5, 1))
    roll = math.radians(80)
    quaternions[2] = [math.sin(roll / 2), 0.0, 0.0, math.cos(roll / 2)]
    pose = estimator.pose(np.zeros((5, 3)), quaternions)
    assert pose.max_tilt_rad == pytest.approx(roll)


def test_a_non_finite_state_gives_a_non_finite_pose():
    snake = load_formation("assemblies/snake5.yaml")
    estimator = BodyPoseEstimator(formation=snake)
    quaternions = np.tile([0.0, 0.0, 0.0, 1.0], (5, 1))
    quaternions[1] = [math.nan, 0.0, 0.0, 1.0]
    pose = estimator.pose(np.zeros((5, 3)), quaternions)
    assert math.isnan(pose.max_tilt_rad) and math.isnan(pose.heading_rad)
