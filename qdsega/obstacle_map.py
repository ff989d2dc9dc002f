"""Where a body cannot go, and what it senses of that: the obstacle map.

Boxes and walls stand on the ground; a body must go around them (steps and rough ground it
climbs, so they are ground, not obstacles). The map is a grid of the places the body's centre
cannot reach without touching one: every obstacle's footprint grown by the body's radius. Two
rules use it, both through :class:`qdsega.task.Task`:

* **a move into an obstacle fails**: the table's moves are measured on open ground, and a move
  that would carry the body's centre into the grown footprint ends the trial as the lower
  agent's failure does (in exact physics the body is stopped there);
* **the body senses what is ahead**: rays fan out from the body's centre at ``FAN_DEG`` from
  its heading, reaching ``RANGE_M`` beyond its nose; the sensed state is 0 where none meets
  an obstacle, 1 where the nearest hit is on the left (or straight ahead) and 2 where it is
  on the right. Exterior states are then the light's bins times these (the paper bins the light
  alone; a world with nothing standing in it keeps exactly the paper's states).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from qdsega.description.world import World, standing_boxes
from qdsega.jit import njit_no_refcount

SENSED_STATES = 3
"""Sensed states where a world has obstacles: clear, obstacle nearer on the left, on the right."""
CELL_M = 0.025
"""The map's cell (m)."""
RANGE_M = 0.3
"""How far beyond the body's nose the rays reach (m)."""
FAN_DEG = (-30.0, -15.0, 0.0, 15.0, 30.0)
"""The rays' directions from the heading (deg)."""
MARGIN_M = 0.5
"""Open ground kept around the grown obstacles in the grid (m)."""


@dataclass(frozen=True)
class ObstacleMap:
    """The grown footprints of a world's obstacles for a body ``radius_m`` wide each side.

    Attributes:
        blocked: ``blocked[row, col]``: the body's centre there touches an obstacle; row along
            y, col along x; shape (ny, nx).
        origin_m: the centre of cell (0, 0), (x, y) (m).
        radius_m: how far the footprints are grown: the body's half-width (m).
        nose_m: how far ahead of its centre the body reaches: its half-length (m).
    """

    blocked: np.ndarray
    origin_m: tuple[float, float]
    radius_m: float
    nose_m: float

    @classmethod
    def of(cls, world: World, *, radius_m: float, nose_m: float) -> ObstacleMap | None:
        """The map of ``world``'s boxes and walls for a body ``radius_m`` wide each side and
        ``nose_m`` long ahead of its centre; None where nothing stands on the ground."""
        boxes = standing_boxes(world)
        if not boxes:
            return None
        corners = np.concatenate([_corners(box.xyz_m, box.size_m, box.yaw_rad) for box in boxes])
        reach = max(radius_m, nose_m) + RANGE_M + MARGIN_M
        low = corners.min(axis=0) - reach
        count = np.ceil((corners.max(axis=0) + reach - low) / CELL_M).astype(int) + 1
        xs = low[0] + CELL_M * np.arange(count[0])
        ys = low[1] + CELL_M * np.arange(count[1])
        gx, gy = np.meshgrid(xs, ys)
        blocked = np.zeros(gx.shape, dtype=bool)
        for box in boxes:
            blocked |= _distance_to_box(gx, gy, box.xyz_m, box.size_m, box.yaw_rad) <= radius_m
        origin = (float(low[0]), float(low[1]))
        return cls(blocked=blocked, origin_m=origin, radius_m=radius_m, nose_m=nose_m)

    def geometry(self) -> np.ndarray:
        """The numbers the compiled rules take: origin x, y (m), cell (m), ray length (m)."""
        return np.array([*self.origin_m, CELL_M, self.nose_m + RANGE_M])

    def touches(self, x: float, y: float) -> bool:
        """The body's centre at (x, y) (m) touches an obstacle."""
        return touches(self.blocked, self.geometry(), x, y)

    def sensed(self, x: float, y: float, theta: float) -> int:
        """The sensed state at pose (x m, y m, heading rad)."""
        return sensed_state(self.blocked, self.geometry(), _FAN_RAD, x, y, theta)


_FAN_RAD = np.radians(np.array(FAN_DEG))


def fan_rad() -> np.ndarray:
    """The rays' directions from the heading (rad), for the compiled rules."""
    return _FAN_RAD.copy()


def _corners(
    centre: tuple[float, float, float], size: tuple[float, float, float], yaw: float
) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    half = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]]) * np.array(size[:2]) / 2
    rotated = half @ np.array([[c, s], [-s, c]])
    return rotated + np.array(centre[:2])


def _distance_to_box(
    x: np.ndarray,
    y: np.ndarray,
    centre: tuple[float, float, float],
    size: tuple[float, float, float],
    yaw: float,
) -> np.ndarray:
    """Horizontal distance (m) from points to a box's footprint (0 inside)."""
    c, s = math.cos(yaw), math.sin(yaw)
    ex, ey = x - centre[0], y - centre[1]
    along, across = c * ex + s * ey, -s * ex + c * ey
    out_x = np.maximum(np.abs(along) - size[0] / 2, 0.0)
    out_y = np.maximum(np.abs(across) - size[1] / 2, 0.0)
    return np.hypot(out_x, out_y)


@njit_no_refcount()
def touches(blocked: np.ndarray, geometry: np.ndarray, x: float, y: float) -> bool:
    """The body's centre at (x, y) (m) is in a grown footprint; outside the grid it is not."""
    col = math.floor((x - geometry[0]) / geometry[2] + 0.5)
    row = math.floor((y - geometry[1]) / geometry[2] + 0.5)
    if row < 0 or col < 0 or row >= blocked.shape[0] or col >= blocked.shape[1]:
        return False
    return blocked[row, col]


@njit_no_refcount()
def sensed_state(
    blocked: np.ndarray, geometry: np.ndarray, fan: np.ndarray, x: float, y: float, theta: float
) -> int:
    """The sensed state (module docstring) at pose (x m, y m, heading rad); ties between the
    two sides go to the left."""
    cell, length = geometry[2], geometry[3]
    samples = math.ceil(length / (0.5 * cell))
    left, right = math.inf, math.inf
    for k in range(fan.shape[0]):
        c, s = math.cos(theta + fan[k]), math.sin(theta + fan[k])
        for n in range(1, samples + 1):
            r = length * n / samples
            if touches(blocked, geometry, x + r * c, y + r * s):
                if fan[k] >= 0.0:
                    left = min(left, r)
                if fan[k] <= 0.0:
                    right = min(right, r)
                break
    if left == math.inf and right == math.inf:
        return 0
    return 1 if left <= right else 2
