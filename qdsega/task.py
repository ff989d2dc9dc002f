"""The light-seeking task (paper sections 4.1.1 and 4.1.3): the one home of its rules.

A trial starts with the robot at the origin, heading +x, in its start posture, and lasts
``trial_steps`` upper-agent steps unless the lower agent fails first. Every learning loop (the
compiled table loop, the Python loop over a step-by-step model), the Gymnasium environment,
evaluation and the reference search use these rules through :class:`Task` or its compiled
kernels:

* **reward** eq. (17): ``reward_scale * (d(t-1) - d(t)) / distance_unit_m``, with ``d`` the
  distance (m) from the body to the light; a step the lower agent fails earns ``penalty`` and
  ends the trial (eq. (1) without its future term);
* **exterior state**: the bin of the angle from the heading to the light. The paper's "four
  states from -45 to 45 deg each 30 deg" is read as edges -45, -15, 15, 45 deg: three 30-deg
  bins ahead (straight ahead, -15..15 deg, a bin of its own) and state 0 for "outside". In a
  world with obstacles, times what the body senses ahead (:mod:`qdsega.obstacle_map`):
  ``light_bin + n_light_bins * sensed``;
* **obstacles**: a table move that would carry the body into an obstacle is lost: the body
  stays where it was, in the posture it was sent to;
* **pose integration**: a step's move is measured in the body frame at its start (forward
  ``dx`` m, leftward ``dy`` m, turn ``dtheta`` rad) and applied to the world pose (eqs.
  (14)-(16), with ``dy`` added for bodies that also slip sideways).

Poses are ``(x m, y m, theta rad)`` tuples in the world frame.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit

from qdsega.jit import njit_no_refcount
from qdsega.obstacle_map import SENSED_STATES, ObstacleMap, fan_rad, sensed_state, touches

Pose = tuple[float, float, float]
"""A planar pose: x (m), y (m), heading (rad, counter-clockwise from +x)."""


@dataclass(frozen=True, kw_only=True)
class TaskConfig:
    """The task's rules.

    Attributes:
        trial_steps: upper-agent steps (postures commanded) per trial unless the lower agent
            fails first (-). 30 (open): ten cycles of the best MSM gait, so that a trial's
            distance is decided by the gait more than by how it starts (docs/algorithm.md).
        reward_scale: the 100 of eq. (17) (-).
        distance_unit_m: the unit ``d`` of eq. (17) is measured in (m). The paper leaves it
            open; it sets how hot eq. (18)'s temperature is against the rewards: metres for
            the legged presets, centimetres for the snake preset, whose 1000 trials cool the
            temperature too little for rewards in metres (docs/algorithm.md).
        penalty: reward of a step whose posture the lower agent failed to reach (-).
        exterior_bin_edges_deg: edges of the bins of the angle to the light, strictly
            increasing (deg); state 0 is "outside", so there are as many states as edges.
    """

    trial_steps: int = 30
    reward_scale: float = 100.0
    distance_unit_m: float = 1.0
    penalty: float = -100.0
    exterior_bin_edges_deg: tuple[float, ...] = (-45.0, -15.0, 15.0, 45.0)

    def __post_init__(self) -> None:
        if self.trial_steps < 1:
            raise ValueError(f"trial_steps must be at least 1, got {self.trial_steps}")
        if not (self.reward_scale > 0 and math.isfinite(self.reward_scale)):
            raise ValueError(f"reward_scale must be positive, got {self.reward_scale}")
        if not (self.distance_unit_m > 0 and math.isfinite(self.distance_unit_m)):
            raise ValueError(f"distance_unit_m must be positive, got {self.distance_unit_m}")
        if not math.isfinite(self.penalty):
            raise ValueError(f"penalty must be finite, got {self.penalty}")
        edges = self.exterior_bin_edges_deg
        if len(edges) < 2 or any(b <= a for a, b in itertools.pairwise(edges)):
            raise ValueError(f"exterior_bin_edges_deg: need 2+ increasing edges, got {edges}")

    @property
    def reward_per_m(self) -> float:
        """Reward of one metre gained toward the light (1/m)."""
        return self.reward_scale / self.distance_unit_m


class Task:
    """The task's rules for one light position.

    Args:
        config: the rules.
        light_xy: light position in the world frame (m).
        obstacles: what stands in the way, or None (nothing does).
    """

    def __init__(
        self,
        *,
        config: TaskConfig,
        light_xy: Sequence[float],
        obstacles: ObstacleMap | None = None,
    ) -> None:
        light = np.asarray(light_xy, dtype=np.float64)
        if light.shape != (2,) or not np.all(np.isfinite(light)):
            raise ValueError(f"light_xy must be two finite numbers, got {light_xy!r}")
        self.config = config
        self.light = light
        """Light position (x, y) (m), shape (2,)."""
        self.edges = np.radians(np.asarray(config.exterior_bin_edges_deg, dtype=np.float64))
        """The light's bin edges (rad), shape (n_light_bins,)."""
        self.obstacles = obstacles

    @property
    def n_exterior(self) -> int:
        """Exterior states: the light's bins, times the sensed states where obstacles are."""
        return len(self.edges) * (1 if self.obstacles is None else SENSED_STATES)

    def map_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The obstacles as the compiled rules take them (:class:`ObstacleMap`): ``near``,
        ``ahead``, the geometry, the rays' directions and the body's outline; empty grids
        where nothing stands."""
        obstacles = self.obstacles
        if obstacles is None:
            empty = np.zeros((0, 0), dtype=np.bool_)
            return empty, empty, np.zeros(4), fan_rad(), np.zeros((0, 2))
        return obstacles.near, obstacles.ahead, obstacles.geometry(), fan_rad(), obstacles.outline_m

    @property
    def trial_steps(self) -> int:
        return self.config.trial_steps

    @property
    def penalty(self) -> float:
        return self.config.penalty

    def distance(self, pose: Pose) -> float:
        """Distance from the pose's position to the light (m)."""
        return math.hypot(self.light[0] - pose[0], self.light[1] - pose[1])

    def reward(self, before: Pose, after: Pose) -> float:
        """Eq. (17) for a successful step from ``before`` to ``after`` (-)."""
        return step_reward(self.distance(before), self.distance(after), self.config.reward_per_m)

    def move(
        self, pose: Pose, dx: float, dy: float, dtheta: float, failed: bool
    ) -> tuple[Pose, float, bool]:
        """One table step: a body-frame move from ``pose``, or a failure (the pose stays); a
        move into an obstacle is lost (the pose stays, the trial goes on). The new pose, the
        step's reward (eq. 17, or the penalty) and whether it failed."""
        if failed:
            return pose, self.penalty, True
        after = move_pose(*pose, dx, dy, dtheta)
        if self.obstacles is not None and self.obstacles.touches(*after):
            after = pose
        return after, self.reward(pose, after), False

    def bearing(self, pose: Pose) -> float:
        """Angle from the pose's heading to the light, counter-clockwise, in [-pi, pi] (rad):
        what the exterior state bins."""
        return angle_to_light(pose[0], pose[1], pose[2], self.light[0], self.light[1])

    def exterior(self, pose: Pose) -> int:
        """Exterior state of a pose."""
        light = exterior_state(pose[0], pose[1], pose[2], self.light[0], self.light[1], self.edges)
        if self.obstacles is None:
            return light
        return light + len(self.edges) * self.obstacles.sensed(*pose)

    def covered(self, start: Pose, pose: Pose) -> float:
        """Distance toward the light gained from ``start`` to ``pose`` (m)."""
        return self.distance(start) - self.distance(pose)


@njit(cache=True)
def step_reward(d_before_m: float, d_after_m: float, reward_per_m: float) -> float:
    """Eq. (17): ``reward_per_m * (d(t-1) - d(t))`` for distances to the light (m)."""
    return reward_per_m * (d_before_m - d_after_m)


@njit(cache=True)
def angle_to_light(x: float, y: float, theta: float, light_x: float, light_y: float) -> float:
    """Angle from the heading ``theta`` to the light, counter-clockwise, in [-pi, pi] (rad)."""
    angle = math.atan2(light_y - y, light_x - x) - theta
    return math.atan2(math.sin(angle), math.cos(angle))


@njit_no_refcount()
def exterior_state(
    x: float, y: float, theta: float, light_x: float, light_y: float, edges: np.ndarray
) -> int:
    """Exterior state of a pose: 0 outside ``[edges[0], edges[-1])``, else 1 + its bin."""
    angle = angle_to_light(x, y, theta, light_x, light_y)
    if angle < edges[0] or angle >= edges[-1]:
        return 0
    state = 0
    for edge in edges:
        if angle >= edge:
            state += 1
    return state


_EDGE_TOLERANCE = 1e-9
"""How close (rad, about) to an edge, or to the side, :func:`exterior_state_ahead` lets a pose
come before it defers to :func:`exterior_state`: far above both formulas' rounding (below
1e-13 rad for headings under 1000 rad)."""


@njit(cache=True)
def edge_directions(edges: np.ndarray) -> np.ndarray:
    """``(cos, sin)`` of each exterior bin edge (rad), shape (n_exterior, 2)."""
    directions = np.empty((edges.shape[0], 2))
    for k in range(edges.shape[0]):
        directions[k, 0], directions[k, 1] = math.cos(edges[k]), math.sin(edges[k])
    return directions


@njit_no_refcount()
def exterior_state_ahead(
    x: float,
    y: float,
    theta: float,
    cos_theta: float,
    sin_theta: float,
    light_x: float,
    light_y: float,
    edges: np.ndarray,
    edge_directions: np.ndarray,
) -> int:
    """:func:`exterior_state`, the same state for every pose, without its four
    trigonometric calls where every edge lies ahead (within +-90 deg).

    The light's direction in the body frame is compared with each edge's direction by the
    sign of their cross product; a pose whose light lies within about
    :data:`_EDGE_TOLERANCE` rad of an edge or of the side gets :func:`exterior_state`.

    Args:
        cos_theta, sin_theta: of the heading ``theta``.
        edge_directions: ``(cos, sin)`` of each edge, shape (n_exterior, 2).
    """
    n = edges.shape[0]
    if edges[0] <= -0.5 * math.pi or edges[n - 1] >= 0.5 * math.pi:
        return exterior_state(x, y, theta, light_x, light_y, edges)
    ex, ey = light_x - x, light_y - y
    ahead = cos_theta * ex + sin_theta * ey
    left = cos_theta * ey - sin_theta * ex
    tolerance = _EDGE_TOLERANCE * (abs(ahead) + abs(left))
    if ahead < -tolerance:
        return 0
    if ahead <= tolerance:
        return exterior_state(x, y, theta, light_x, light_y, edges)
    passed = 0
    for k in range(n):
        cross = edge_directions[k, 0] * left - edge_directions[k, 1] * ahead
        if abs(cross) <= tolerance:
            return exterior_state(x, y, theta, light_x, light_y, edges)
        if cross > 0.0:
            passed += 1
    return 0 if passed == n else passed


@njit_no_refcount()
def sensed_exterior(
    light_state: int,
    n_light: int,
    ahead: np.ndarray,
    geometry: np.ndarray,
    fan: np.ndarray,
    x: float,
    y: float,
    theta: float,
) -> int:
    """The exterior state from the light's bin and what the body senses ahead (an empty
    ``ahead`` grid: nothing stands in the world, the light's bin alone)."""
    if ahead.shape[0] == 0:
        return light_state
    return light_state + n_light * sensed_state(ahead, geometry, fan, x, y, theta)


@njit_no_refcount()
def stopped(
    near: np.ndarray, geometry: np.ndarray, outline: np.ndarray, x: float, y: float, theta: float
) -> bool:
    """A move that ends at pose (x m, y m, heading rad) runs into an obstacle, and so is lost
    (never without a map)."""
    return near.shape[0] > 0 and touches(near, geometry, outline, x, y, theta)


@njit(cache=True)
def move_position(
    x: float, y: float, cos_theta: float, sin_theta: float, dx: float, dy: float
) -> tuple[float, float]:
    """The position (m) after a body-frame move (``dx`` forward, ``dy`` leftward, m) from a
    pose heading ``theta``, given its cosine and sine."""
    return x + dx * cos_theta - dy * sin_theta, y + dx * sin_theta + dy * cos_theta


@njit(cache=True)
def move_pose(
    x: float, y: float, theta: float, dx: float, dy: float, dtheta: float
) -> tuple[float, float, float]:
    """Apply a body-frame move (m, m, rad) to a world pose; eqs. (14)-(16) for ``dy = 0``."""
    x, y = move_position(x, y, math.cos(theta), math.sin(theta), dx, dy)
    return x, y, theta + dtheta


def relative_move(start: Pose, end: Pose) -> tuple[float, float, float]:
    """The body-frame move from ``start`` to ``end``: forward (m), leftward (m) in the frame
    at ``start``, and the turn wrapped to [-pi, pi] (rad); :func:`move_pose` inverts it."""
    c, s = math.cos(start[2]), math.sin(start[2])
    ex, ey = end[0] - start[0], end[1] - start[1]
    turn = math.atan2(math.sin(end[2] - start[2]), math.cos(end[2] - start[2]))
    return (c * ex + s * ey, -s * ex + c * ey, turn)
