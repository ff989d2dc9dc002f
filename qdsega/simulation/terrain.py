"""A world (:class:`qdsega.description.world.World`) built in a PyBullet client: the ground, the
steps, the obstacles, the walls and the roof; and the ground's height under a point, so that a
body can be placed just above it.

Only PyBullet calls made through the client passed in: :mod:`qdsega.simulation.bullet` owns
the engine.
"""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import imageio.v3 as iio
import numpy as np

from qdsega.description.world import CELL_M, Box, Rough, World, corridor_walls, roof_box

GROUND_RGBA = (0.55, 0.5, 0.45, 1.0)
OBSTACLE_RGBA = (0.6, 0.6, 0.62, 1.0)
STEP_RGBA = (GROUND_RGBA, (0.7, 0.64, 0.56, 1.0))
"""Steps alternate these colours, so that each step shows in a picture."""
ROUGH_START_M = 1.0
"""Rough ground starts this far behind the start, so that a body begins on it."""
RELIEF_LOW_RGB = (0.42, 0.35, 0.27)
RELIEF_HIGH_RGB = (0.80, 0.72, 0.56)
"""Rough ground's colour in pictures at its lowest and its highest (-): height reads as tint."""
RELIEF_SUN_DEG = (135.0, 25.0)
"""Where the light that shades rough ground's picture comes from: azimuth counter-clockwise
from +x and elevation (deg); a low sun from the front left casts the bumps' slopes apart."""
RELIEF_GRID_M = 0.5
"""Lines on rough ground's picture every this many metres: they bend over the bumps, and give
a scale."""
RELIEF_TEXTURE_PX = 1024
"""The side of rough ground's picture (px): a power of two, as renderers take textures."""


@dataclass
class Terrain:
    """What a world put into a client: the bodies that are ground (a trunk on them has
    fallen) and the others (obstacles, walls, a roof)."""

    ground: list[int] = field(default_factory=list)
    obstacles: list[int] = field(default_factory=list)


def build_terrain(
    client: Any, pybullet: Any, world: World, plane_urdf: Path, *, pictures: bool = False
) -> Terrain:
    """Build ``world`` in ``client`` (a ``BulletClient``; ``pybullet`` the module, for its
    constants). The plain plane of a flat world is loaded exactly as it always was. With
    ``pictures``, rough ground also gets a shaded look that shows its relief
    (:func:`relief_texture`); the physics is the same either way."""
    terrain = Terrain()
    if world.rough is not None:
        terrain.ground += _heightfield(client, pybullet, world.rough, plane_urdf, pictures)
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
            colour = STEP_RGBA[k % len(STEP_RGBA)]
            terrain.ground.append(_box(client, pybullet, centre, size, 0.0, colour))
    for box in world.boxes:
        terrain.obstacles.append(_placed(client, pybullet, box, world))
    if world.corridor is not None:
        for wall in corridor_walls(world.corridor):
            terrain.obstacles.append(
                _box(client, pybullet, wall.xyz_m, wall.size_m, wall.yaw_rad, OBSTACLE_RGBA)
            )
    if world.ceiling is not None:
        roof = roof_box(world.ceiling)
        x, y, z = roof.xyz_m
        base = float(ground_height(world, np.array([x]), np.array([y]))[0])
        centre = (x, y, base + z)
        terrain.obstacles.append(_box(client, pybullet, centre, roof.size_m, 0.0, OBSTACLE_RGBA))
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


def relief_texture(rough: Rough) -> np.ndarray:
    """The picture of ``rough`` seen from above, (px, px, 3) uint8, rows along +x and columns
    along +y: tinted by height, shaded by a low sun (``RELIEF_SUN_DEG``) and lined every
    ``RELIEF_GRID_M``, so that bumps a few centimetres high show in any light."""
    heights = _resampled(rough_heights(rough), RELIEF_TEXTURE_PX)
    texel_m = rough.size_m / (RELIEF_TEXTURE_PX - 1)
    slope_x, slope_y = np.gradient(heights, texel_m)
    normal = np.stack([-slope_x, -slope_y, np.ones_like(heights)], axis=-1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    azimuth, elevation = (math.radians(a) for a in RELIEF_SUN_DEG)
    sun = np.array(
        [math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
         math.sin(elevation)]
    )  # fmt: skip
    light = np.clip(normal @ sun, 0.0, 1.0) / sun[2]  # 1 on level ground
    level = heights / max(rough.amplitude_m, 1e-12)
    low, high = np.array(RELIEF_LOW_RGB), np.array(RELIEF_HIGH_RGB)
    rgb = (low + level[..., None] * (high - low)) * np.clip(light, 0.3, 1.6)[..., None]
    x0, y0 = _rough_origin(rough)
    x = x0 + texel_m * np.arange(len(heights))
    y = y0 + texel_m * np.arange(len(heights))
    on_x = np.abs((x + RELIEF_GRID_M / 2) % RELIEF_GRID_M - RELIEF_GRID_M / 2) < texel_m
    on_y = np.abs((y + RELIEF_GRID_M / 2) % RELIEF_GRID_M - RELIEF_GRID_M / 2) < texel_m
    rgb[on_x, :] *= 0.75
    rgb[:, on_y] *= 0.75
    return np.round(255 * np.clip(rgb, 0.0, 1.0)).astype(np.uint8)


def _resampled(grid: np.ndarray, size: int) -> np.ndarray:
    """``grid`` (n, n) interpolated linearly to (size, size), corners kept."""
    n = len(grid)
    fine = np.linspace(0.0, n - 1.0, size)
    along_x = np.array([np.interp(fine, np.arange(n), grid[:, j]) for j in range(n)]).T
    return np.array([np.interp(fine, np.arange(n), row) for row in along_x])


def _heightfield(
    client: Any, pybullet: Any, rough: Rough, plane_urdf: Path, pictures: bool
) -> list[int]:
    """The rough square and, beyond it, plain ground; with ``pictures``, the square is shown as
    a mesh of its heights carrying :func:`relief_texture`, and the plain ground as a flat
    world's plane."""
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
    plane = client.createCollisionShape(pybullet.GEOM_PLANE)
    if not pictures:
        body = client.createMultiBody(
            baseMass=0.0, baseCollisionShapeIndex=shape, basePosition=centre
        )
        client.changeVisualShape(body, -1, rgbaColor=GROUND_RGBA)
        return [body, client.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=plane)]
    # The EGL renderer takes meshes from files only: the relief is written as an OBJ file with
    # its texture, read as the bodies are made.
    with tempfile.TemporaryDirectory(prefix="qdsega-relief-") as folder:
        mesh = _write_relief(rough, Path(folder), centre)
        visual = client.createVisualShape(pybullet.GEOM_MESH, fileName=str(mesh))
        body = client.createMultiBody(
            baseMass=0.0,
            baseCollisionShapeIndex=shape,
            baseVisualShapeIndex=visual,
            basePosition=centre,
        )
        texture = client.loadTexture(str(mesh.with_suffix(".png")))
        client.changeVisualShape(body, -1, textureUniqueId=texture)
    plain = client.createVisualShape(
        pybullet.GEOM_MESH, fileName=str(plane_urdf.with_name("plane100.obj"))
    )
    return [
        body,
        client.createMultiBody(
            baseMass=0.0, baseCollisionShapeIndex=plane, baseVisualShapeIndex=plain
        ),
    ]


def _write_relief(rough: Rough, folder: Path, centre: tuple[float, float, float]) -> Path:
    """Write ``rough``'s heights as a mesh around ``centre`` (``relief.obj``: smooth normals,
    texture coordinates spanning the square) and its picture (``relief.png``) into
    ``folder``; returns the mesh's file."""
    heights = rough_heights(rough)
    n = len(heights)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    x0, y0 = _rough_origin(rough)
    vertices = np.stack(
        [x0 + CELL_M * i - centre[0], y0 + CELL_M * j - centre[1], heights - centre[2]], axis=-1
    ).reshape(-1, 3)
    slope_x, slope_y = np.gradient(heights, CELL_M)
    normals = np.stack([-slope_x, -slope_y, np.ones_like(heights)], axis=-1).reshape(-1, 3)
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    uvs = np.stack([j / (n - 1), 1.0 - i / (n - 1)], axis=-1).reshape(-1, 2)  # row 0: v = 1
    corner = (i[:-1, :-1] * n + j[:-1, :-1]).ravel() + 1  # OBJ counts from 1
    faces = np.stack(
        [corner, corner + n, corner + n + 1, corner, corner + n + 1, corner + 1], axis=-1
    ).reshape(-1, 3)
    corners = np.repeat(faces, 3, axis=1)  # each corner's vertex, texture and normal: one index
    text = "".join(
        (line * len(rows)) % tuple(rows.ravel())
        for line, rows in (
            ("v %.4f %.4f %.5f\n", vertices),
            ("vn %.4f %.4f %.4f\n", normals),
            ("vt %.5f %.5f\n", uvs),
            ("f %d/%d/%d %d/%d/%d %d/%d/%d\n", corners),
        )
    )
    mesh = folder / "relief.obj"
    mesh.write_text(text, encoding="utf-8")
    iio.imwrite(mesh.with_suffix(".png"), relief_texture(rough), compress_level=1)
    return mesh


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
