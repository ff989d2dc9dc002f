"""A body's task in a world: the light's rules, and the obstacles sized to the body.

The obstacle map (:mod:`qdsega.obstacle_map`) grows each obstacle by the body's half-width and
casts its rays from the body's nose: both come from the body at rest, measured once here, so
that the table (training) and exact physics (replays, evaluation) sense the same world.
"""

from __future__ import annotations

import math

import numpy as np

from qdsega.assembly import assemble
from qdsega.description import Formation, World
from qdsega.description.world import standing_boxes
from qdsega.locomotion.body_pose import BodyPoseEstimator
from qdsega.obstacle_map import ObstacleMap
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation
from qdsega.simulation.camera import UNIT_SIZE_M
from qdsega.task import Task, TaskConfig


def body_half_size_m(formation: Formation, physics: PhysicsSettings) -> tuple[float, float]:
    """Half the body's length along its heading and half its width across it at rest (m):
    from its pose to the farthest unit centre each way, plus half a unit."""
    with BulletSimulation(robot=assemble(formation), settings=physics) as sim:
        sim.reset(formation.posture_rad(formation.rest_levels()))
        centres, quaternions = sim.unit_states()
    pose = BodyPoseEstimator(formation=formation).pose(centres, quaternions)
    c, s = math.cos(pose.heading_rad), math.sin(pose.heading_rad)
    ex, ey = centres[:, 0] - pose.x_m, centres[:, 1] - pose.y_m
    along, across = np.abs(c * ex + s * ey), np.abs(-s * ex + c * ey)
    return float(along.max()) + UNIT_SIZE_M / 2, float(across.max()) + UNIT_SIZE_M / 2


def obstacle_map(
    formation: Formation, world: World, physics: PhysicsSettings
) -> ObstacleMap | None:
    """``world``'s obstacles grown by ``formation``'s half-width; None where nothing stands."""
    if not standing_boxes(world):
        return None
    half_length, half_width = body_half_size_m(formation, physics)
    return ObstacleMap.of(world, radius_m=half_width, nose_m=half_length)


def world_task(
    formation: Formation, config: TaskConfig, world: World, physics: PhysicsSettings
) -> Task:
    """The task of ``formation`` (lit as it is) in ``world``."""
    return Task(
        config=config,
        light_xy=formation.light.position_m,
        obstacles=obstacle_map(formation, world, physics),
    )
