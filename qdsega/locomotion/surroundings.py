"""A body's task in a world: the light's rules, and the obstacles sized to the body.

The obstacle map (:mod:`qdsega.obstacle_map`) needs the body's outline: its units' centres at
rest, measured once here, so that the table (training) and exact physics (replays, evaluation)
meet and sense the same world; and whether the body can stand somewhere (a roof it cannot stand
under is in its way).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from qdsega.assembly import assemble
from qdsega.description import Formation, World
from qdsega.description.world import roof_box, standing_boxes
from qdsega.errors import WorldError
from qdsega.locomotion.body_pose import BodyPoseEstimator
from qdsega.obstacle_map import ObstacleMap
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation
from qdsega.simulation.camera import UNIT_SIZE_M
from qdsega.task import Task, TaskConfig

CLEARANCE_M = UNIT_SIZE_M / 2
"""How close a unit's centre comes to an obstacle before the unit touches it (m)."""


def body_outline_m(formation: Formation, physics: PhysicsSettings) -> np.ndarray:
    """The centres of ``formation``'s units at rest on flat ground, in the body's own frame
    (forward, left) (m), shape (U, 2)."""
    with BulletSimulation(robot=assemble(formation), settings=physics) as sim:
        sim.reset(formation.posture_rad(formation.rest_levels()))
        centres, quaternions = sim.unit_states()
    pose = BodyPoseEstimator(formation=formation).pose(centres, quaternions)
    c, s = math.cos(pose.heading_rad), math.sin(pose.heading_rad)
    ex, ey = centres[:, 0] - pose.x_m, centres[:, 1] - pose.y_m
    return np.column_stack([c * ex + s * ey, -s * ex + c * ey])


def blocked_spots(
    formation: Formation,
    *,
    physics: PhysicsSettings,
    world: World,
    spots: tuple[tuple[float, float], ...],
) -> list[tuple[float, float]]:
    """The spots where the body cannot stand at rest, heading +x: it would be inside an
    obstacle."""
    blocked = []
    with BulletSimulation(robot=assemble(formation), settings=physics, world=world) as sim:
        rest = formation.posture_rad(formation.rest_levels())
        for spot in spots:
            try:
                sim.reset(rest, xy_m=spot)
            except WorldError:
                blocked.append(spot)
    return blocked


def too_tall(formation: Formation, world: World, physics: PhysicsSettings) -> bool:
    """``formation`` cannot stand at rest under ``world``'s roof (False: no roof)."""
    if world.ceiling is None:
        return False
    under = replace(world, boxes=(), corridor=None)
    middle = roof_box(world.ceiling).xyz_m
    return bool(blocked_spots(formation, physics=physics, world=under, spots=(middle[:2],)))


def obstacle_map(
    formation: Formation, world: World, physics: PhysicsSettings
) -> ObstacleMap | None:
    """``world``'s obstacles as ``formation`` meets them (a roof too low for it among them);
    None where nothing stands in its way."""
    roof = too_tall(formation, world, physics)
    if not standing_boxes(world, roof=roof):
        return None
    outline = body_outline_m(formation, physics)
    return ObstacleMap.of(world, outline_m=outline, clearance_m=CLEARANCE_M, roof=roof)


def world_task(
    formation: Formation, config: TaskConfig, world: World, physics: PhysicsSettings
) -> Task:
    """The task of ``formation`` (lit as it is) in ``world``."""
    return Task(
        config=config,
        light_xy=formation.light.position_m,
        obstacles=obstacle_map(formation, world, physics),
    )
