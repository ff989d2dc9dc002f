"""Where a body cannot go, and what it senses of that: the obstacle map.

Boxes and walls stand on the ground; a body must go around them (steps and rough ground it
climbs, so they are ground, not obstacles), and around a roof it is too tall to go under. Two
rules use the map, both through :class:`qdsega.task.Task`:

* **a move into an obstacle is lost**: the table's moves are measured on open ground, and a
  move that would bring one of the body's units (its outline: the units' centres at rest,
  turned with the body) within ``clearance_m`` of an obstacle leaves the body where it was
  (in exact physics the obstacle stops it there); the trial goes on;
* **the body senses what is ahead**: rays fan out from the body's centre at ``FAN_DEG`` from
  its heading, reaching ``RANGE_M`` beyond its nose, and meet the obstacles grown by the
  body's half-width (what its sides would brush); the sensed state is 0 where none meets one,
  1 where the nearest hit is on the left (or straight ahead) and 2 where it is on the right.
  Exterior states are then the light's bins times these (the paper bins the light alone; a
  world with nothing standing in it keeps exactly the paper's states).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from qdsega.description.world import Box, World, standing_boxes
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
    """A world's obstacles as a body of a given outline meets and senses them.

    Attributes:
        near: ``near[row, col]``: a unit centred there touches an obstacle (footprints grown
            by the clearance); row along y, col along x; shape (ny, nx).
        ahead: the footprints grown by the body's half-width, which the rays meet, same shape.
        origin_m: the centre of cell (0, 0), (x, y) (m).
        outline_m: the body's units' centres at rest in its own frame (forward, left), (K, 2)
            (m).
        nose_m: how far ahead of its centre the body reaches (m).
    """

    near: np.ndarray
    ahead: np.ndarray
    origin_m: tuple[float, float]
    outline_m: np.ndarray
    nose_m: float

    @classmethod
    def of(
        cls, world: World, *, outline_m: np.ndarray, clearance_m: float, roof: bool = False
    ) -> ObstacleMap | None:
        """The map of ``world``'s boxes and walls (and, with ``roof``, its roof: the body is too
        tall for it) for a body of ``outline_m`` (K, 2) whose units touch what comes within
        ``clearance_m`` of their centres; None where nothing stands in the way."""
        boxes = standing_boxes(world, roof=roof)
        if not boxes:
            return None
        outline = np.asarray(outline_m, dtype=np.float64).reshape(-1, 2)
        nose = float(outline[:, 0].max()) + clearance_m
        half_width = float(np.abs(outline[:, 1]).max()) + clearance_m
        corners = np.concatenate([_corners(box) for box in boxes])
        reach = half_width + MARGIN_M
        low = corners.min(axis=0) - reach
        count = np.ceil((corners.max(axis=0) + reach - low) / CELL_M).astype(int) + 1
        gx, gy = np.meshgrid(
            low[0] + CELL_M * np.arange(count[0]), low[1] + CELL_M * np.arange(count[1])
        )
        distance = np.full(gx.shape, np.inf)
        for box in boxes:
            distance = np.minimum(distance, _distance_to_box(gx, gy, box))
        return cls(
            near=distance <= clearance_m,
            ahead=distance <= half_width,
            origin_m=(float(low[0]), float(low[1])),
            outline_m=outline,
            nose_m=nose,
        )

    def geometry(self) -> np.ndarray:
        """The numbers the compiled rules take: origin x, y (m), cell (m), ray length (m)."""
        return np.array([*self.origin_m, CELL_M, self.nose_m + RANGE_M])

    def touches(self, x: float, y: float, theta: float) -> bool:
        """The body at pose (x m, y m, heading rad) touches an obstacle."""
        return touches(self.near, self.geometry(), self.outline_m, x, y, theta)

    def sensed(self, x: float, y: float, theta: float) -> int:
        """The sensed state at pose (x m, y m, heading rad)."""
        return sensed_state(self.ahead, self.geometry(), _FAN_RAD, x, y, theta)


_FAN_RAD = np.radians(np.array(FAN_DEG))


def fan_rad() -> np.ndarray:
    """The rays' directions from the heading (rad), for the compiled rules."""
    return _FAN_RAD.copy()


def _corners(box: Box) -> np.ndarray:
    """A box's footprint's corners (4, 2) (m)."""
    c, s = math.cos(box.yaw_rad), math.sin(box.yaw_rad)
    half = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]]) * np.array(box.size_m[:2]) / 2
    return half @ np.array([[c, s], [-s, c]]) + np.array(box.xyz_m[:2])


def _distance_to_box(x: np.ndarray, y: np.ndarray, box: Box) -> np.ndarray:
    """Horizontal distance (m) from points to a box's footprint (0 inside)."""
    c, s = math.cos(box.yaw_rad), math.sin(box.yaw_rad)
    ex, ey = x - box.xyz_m[0], y - box.xyz_m[1]
    along, across = c * ex + s * ey, -s * ex + c * ey
    out_x = np.maximum(np.abs(along) - box.size_m[0] / 2, 0.0)
    out_y = np.maximum(np.abs(across) - box.size_m[1] / 2, 0.0)
    return np.hypot(out_x, out_y)


@njit_no_refcount()
def in_grid(grid: np.ndarray, geometry: np.ndarray, x: float, y: float) -> bool:
    """The cell of ``grid`` under (x, y) (m) is set; off the grid it is not."""
    col = math.floor((x - geometry[0]) / geometry[2] + 0.5)
    row = math.floor((y - geometry[1]) / geometry[2] + 0.5)
    if row < 0 or col < 0 or row >= grid.shape[0] or col >= grid.shape[1]:
        return False
    return grid[row, col]


@njit_no_refcount()
def touches(
    near: np.ndarray, geometry: np.ndarray, outline: np.ndarray, x: float, y: float, theta: float
) -> bool:
    """One of the body's units, at pose (x m, y m, heading rad), touches an obstacle."""
    c, s = math.cos(theta), math.sin(theta)
    for k in range(outline.shape[0]):
        ux, uy = outline[k, 0], outline[k, 1]
        if in_grid(near, geometry, x + c * ux - s * uy, y + s * ux + c * uy):
            return True
    return False


@njit_no_refcount()
def sensed_state(
    ahead: np.ndarray, geometry: np.ndarray, fan: np.ndarray, x: float, y: float, theta: float
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
            if in_grid(ahead, geometry, x + r * c, y + r * s):
                if fan[k] >= 0.0:
                    left = min(left, r)
                if fan[k] <= 0.0:
                    right = min(right, r)
                break
    if left == math.inf and right == math.inf:
        return 0
    return 1 if left <= right else 2
