"""Where a formation is and where it heads, for every formation alike.

A snake's heading is not one link's yaw: the head swings with the wave. Every unit trails along
its own -x axis, so each unit's +x axis points toward the root (the head, or the front of a
trunk). The **heading** is the direction of the mass-weighted sum of the trunk units' +x axes
projected onto the ground, and the **position** is the trunk units' centre of mass. The trunk is
every unit that belongs to no leg (:attr:`Formation.trunk_units`): the whole body of a snake,
the rigid chain of hubs of a legged robot. On a straight body both reduce to the obvious.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from qdsega.description import Formation


@dataclass(frozen=True)
class BodyPose:
    """Planar pose of a formation.

    Attributes:
        x_m: trunk centre of mass, world x (m).
        y_m: trunk centre of mass, world y (m).
        heading_rad: direction of the trunk, counter-clockwise from world +x (rad).
        max_tilt_rad: largest angle between a trunk unit's up axis and the vertical (rad).
    """

    x_m: float
    y_m: float
    heading_rad: float
    max_tilt_rad: float


class BodyPoseEstimator:
    """Computes :class:`BodyPose` from unit states (the output of ``unit_states()``).

    Args:
        formation: the formation whose units the states list, in formation order.
    """

    def __init__(self, *, formation: Formation) -> None:
        trunk = {u.name for u in formation.trunk_units}
        self._rows = np.array([i for i, u in enumerate(formation.units) if u.name in trunk])
        masses = np.array([formation.units[i].unit_type.mass_kg for i in self._rows])
        self._weights = masses / masses.sum()

    def pose(self, positions_m: np.ndarray, quaternions: np.ndarray) -> BodyPose:
        """Pose from centres of mass (U, 3) (m) and orientations (U, 4) as (x, y, z, w)."""
        p = positions_m[self._rows]
        qx, qy, qz, qw = quaternions[self._rows].T
        # First and third columns of each rotation matrix: the unit's x and z axes in the world.
        forward_x = 1.0 - 2.0 * (qy * qy + qz * qz)
        forward_y = 2.0 * (qx * qy + qw * qz)
        up_z = 1.0 - 2.0 * (qx * qx + qy * qy)
        heading = math.atan2(float(self._weights @ forward_y), float(self._weights @ forward_x))
        centre = self._weights @ p
        tilt = float(np.arccos(np.clip(up_z, -1.0, 1.0)).max())
        return BodyPose(float(centre[0]), float(centre[1]), heading, tilt)
