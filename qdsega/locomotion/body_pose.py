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
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from qdsega.description import Formation
from qdsega.task import Pose


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

    @property
    def planar(self) -> Pose:
        """(x m, y m, heading rad), the task's view of the pose."""
        return (self.x_m, self.y_m, self.heading_rad)


class BodyPoseEstimator:
    """Computes :class:`BodyPose` from unit states (the output of ``unit_states()``).

    Args:
        formation: the formation whose units the states list, in formation order.
    """

    def __init__(self, *, formation: Formation) -> None:
        trunk = {u.name for u in formation.trunk_units}
        self.trunk_rows = tuple(i for i, u in enumerate(formation.units) if u.name in trunk)
        """Indices of the trunk units in formation order."""
        masses = [formation.units[i].unit_type.mass_kg for i in self.trunk_rows]
        self._weights = tuple(m / sum(masses) for m in masses)

    def pose(self, positions_m: np.ndarray, quaternions: np.ndarray) -> BodyPose:
        """Pose from every unit's centre of mass (U, 3) (m) and orientation (U, 4) as
        (x, y, z, w)."""
        rows = list(self.trunk_rows)
        return self.trunk_pose(positions_m[rows], quaternions[rows])

    def trunk_pose(
        self,
        positions_m: Sequence[Sequence[float]] | np.ndarray,
        quaternions: Sequence[Sequence[float]] | np.ndarray,
    ) -> BodyPose:
        """Pose from the trunk units' states only, rows in :attr:`trunk_rows` order.

        Plain Python: for the few trunk units, checked every few physics steps, it runs several
        times faster than numpy's per-call overhead."""
        x = y = forward_x = forward_y = 0.0
        ups = []
        for weight, (px, py, _), (qx, qy, qz, qw) in zip(
            self._weights, positions_m, quaternions, strict=True
        ):
            x += weight * px
            y += weight * py
            # First and third columns of the rotation matrix: the unit's x and z axes.
            forward_x += weight * (1.0 - 2.0 * (qy * qy + qz * qz))
            forward_y += weight * 2.0 * (qx * qy + qw * qz)
            ups.append(1.0 - 2.0 * (qx * qx + qy * qy))
        finite = all(map(math.isfinite, ups))
        tilt = math.acos(max(-1.0, min(1.0, min(ups)))) if finite else math.nan
        return BodyPose(x, y, math.atan2(forward_y, forward_x), tilt)
