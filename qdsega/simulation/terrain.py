"""A world (:class:`qdsega.description.world.World`) built in a PyBullet client: the ground, the
steps, the obstacles, the walls and the roof; and the ground's height under a point, so that a
body can be placed just above it.

Only PyBullet calls made through the client passed in: :mod:`qdsega.simulation.bullet` owns
the engine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.description.world import CELL_M, Box, Rough, World

GROUND_RGBA = (0.55, 0.5, 0.45, 1.0)
OBSTACLE_RGBA = (0.6, 0.6, 0.62, 1.0)
ROUGH_START_M = 1.0
"""Rough ground starts this far behind the start, so that a body begins on it."""


@dataclass
class Terrain:
    """What a world put into a client: the bodies that are ground (a trunk on them has
    fallen) and the others (obstacles, walls, a roof)."""

    ground: list[int] = field(default_factory=list)
    obstacles: list[int] = field(default_factory=list)


def build_terrain(client: Any, pybullet: Any, world: World, plane_urdf: Path) -> Terrain:
    """Build ``world`` in ``client`` (a ``BulletClient``; ``pybullet`` the module, for its
    constants). The plain plane of a flat world is loaded exactly as it always was."""
    terrain = Terrain()
    if world.rough is not None:
        terrain.ground += _heightfield(client, pybullet, world.rough)
    elif world.slope_rad == 0.0:
        terrain.ground.append(client.loadURDF(str(plane_urdf), useFixedBase=True))
    else:
        axis = (-math.sin(world.slope_toward_rad), math.cos(world.slope_toward_rad), 0.0)
        tilt = client.getQuaternionFromAxisAngle(axis, -world.slope_rad)
        terrain.ground.append(
            client.loadURDF(str(plane_urdf), useFixedBase=True, baseOrientation=tilt)
        )
    if world.stairs is not None:
        stairs = world.stairs
        for k in range(stairs.count):
            height = stairs.rise_m * (k + 1)
            centre = (stairs.from_m + (k + 0.5) * stairs.run_m, 0.0, height / 2)
            size = (stairs.run_m, stairs.width_m, height)
            terrain.ground.append(_box(client, pybullet, centre, size, 0.0, GROUND_RGBA))
    for box in world.boxes:
        terrain.obstacles.append(_placed(client, pybullet, box, world))
    if world.corridor is not None:
        wall = world.corridor
        length = wall.length_m + 1.0
        for side in (-1.0, 1.0):
            y = side * (wall.width_m / 2 + 0.025)
            centre = (wall.length_m - length / 2, y, wall.height_m / 2)
            size = (length, 0.05, wall.height_m)
            terrain.obstacles.append(_box(client, pybullet, centre, size, 0.0, OBSTACLE_RGBA))
    if world.ceiling is not None:
        roof = world.ceiling
        length = roof.to_m - roof.from_m
        x = (roof.from_m + roof.to_m) / 2
        base = float(ground_height(world, np.array([x]), np.array([0.0]))[0])
        centre = (x, 0.0, base + roof.height_m + 0.025)
        size = (length, roof.width_m, 0.05)
        terrain.obstacles.append(_box(client, pybullet, centre, size, 0.0, OBSTACLE_RGBA))
    return terrain


def ground_height(world: World, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The top of the ground (plane, slope, rough ground, steps) at points (x, y) (m); where
    rough ground is, the highest corner of the cell, so that a body placed above it clears
    it."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    toward = x * math.cos(world.slope_toward_rad) + y * math.sin(world.slope_toward_rad)
    height = math.tan(world.slope_rad) * toward
    if world.rough is not None:
        height = height + _rough_height(world.rough, x, y)
    if world.stairs is not None:
        stairs = world.stairs
        k = np.floor((x - stairs.from_m) / stairs.run_m)
        on = (k >= 0) & (k < stairs.count) & (np.abs(y) <= stairs.width_m / 2)
        height = np.where(on, height + stairs.rise_m * (k + 1), height)
    return height


def rough_heights(rough: Rough) -> np.ndarray:
    """The heightfield of ``rough``, shape (n, n), rows along +x and columns along +y, from 0
    to ``amplitude_m``: random heights every ``feature_m``, interpolated linearly between."""
    n = round(rough.size_m / CELL_M) + 1
    coarse = max(2, math.ceil(rough.size_m / rough.feature_m) + 1)
    rng = np.random.default_rng(rough.seed)
    knots = rng.random((coarse, coarse))
    fine = np.linspace(0.0, coarse - 1.0, n)
    along_x = np.array([np.interp(fine, np.arange(coarse), knots[:, j]) for j in range(coarse)])
    grid = np.array([np.interp(fine, np.arange(coarse), along_x[:, i]) for i in range(n)])
    grid -= grid.min()
    return rough.amplitude_m * grid / max(grid.max(), 1e-12)


def _rough_origin(rough: Rough) -> tuple[float, float]:
    """Where the heightfield's first cell corner lies (x, y) (m)."""
    return -ROUGH_START_M, -rough.size_m / 2


def _rough_height(rough: Rough, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    heights = rough_heights(rough)
    n = len(heights)
    x0, y0 = _rough_origin(rough)
    i = np.clip((x - x0) / CELL_M, 0, n - 1)
    j = np.clip((y - y0) / CELL_M, 0, n - 1)
    i0, j0 = np.floor(i).astype(int), np.floor(j).astype(int)
    i1, j1 = np.minimum(i0 + 1, n - 1), np.minimum(j0 + 1, n - 1)
    corners = np.stack([heights[i0, j0], heights[i1, j0], heights[i0, j1], heights[i1, j1]])
    inside = (x >= x0) & (x <= x0 + rough.size_m) & (y >= y0) & (y <= y0 + rough.size_m)
    return np.where(inside, corners.max(axis=0), 0.0)


def _heightfield(client: Any, pybullet: Any, rough: Rough) -> list[int]:
    """The rough square and, beyond it, plain ground."""
    heights = rough_heights(rough)
    n = len(heights)
    shape = client.createCollisionShape(
        pybullet.GEOM_HEIGHTFIELD,
        meshScale=[CELL_M, CELL_M, 1.0],
        heightfieldData=heights.flatten(order="F").tolist(),  # index i + j * n: i along x
        numHeightfieldRows=n,
        numHeightfieldColumns=n,
    )
    x0, y0 = _rough_origin(rough)
    centre = (x0 + rough.size_m / 2, y0 + rough.size_m / 2, rough.amplitude_m / 2)
    body = client.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=shape, basePosition=centre)
    client.changeVisualShape(body, -1, rgbaColor=GROUND_RGBA)
    plane = client.createCollisionShape(pybullet.GEOM_PLANE)
    return [body, client.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=plane)]


def _placed(client: Any, pybullet: Any, box: Box, world: World) -> int:
    base = float(ground_height(world, np.array([box.xyz_m[0]]), np.array([box.xyz_m[1]]))[0])
    centre = (box.xyz_m[0], box.xyz_m[1], base + box.xyz_m[2])
    return _box(client, pybullet, centre, box.size_m, box.yaw_rad, OBSTACLE_RGBA)


def _box(
    client: Any,
    pybullet: Any,
    centre: tuple[float, float, float],
    size: tuple[float, float, float],
    yaw_rad: float,
    rgba: tuple[float, float, float, float],
) -> int:
    half = [s / 2 for s in size]
    shape = client.createCollisionShape(pybullet.GEOM_BOX, halfExtents=half)
    visual = client.createVisualShape(pybullet.GEOM_BOX, halfExtents=half, rgbaColor=rgba)
    orientation = client.getQuaternionFromEuler((0.0, 0.0, yaw_rad))
    return client.createMultiBody(
        baseMass=0.0,
        baseCollisionShapeIndex=shape,
        baseVisualShapeIndex=visual,
        basePosition=centre,
        baseOrientation=orientation,
    )
