"""Where the camera stands and what it films."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

WIDTH_PX = 640
HEIGHT_PX = 480
"""The size of a picture unless asked otherwise (px): videos, ``match``'s stills, the gallery."""
LIGHT_RADIUS_FRACTION = 0.02
"""The light's sphere has this fraction of its distance as radius (at least 0.1 m), so that it
shows on the horizon."""

FRAMING = 1.2
"""Without a distance given, the camera stands this many times the body's largest horizontal
extent (:func:`body_extent_m`) from it (-): a hexapod at rest, seen from behind, fills about
half the picture's width with the default 60 deg vertical field of view at 4:3, which leaves
room for its legs' swing and its turns."""

UNIT_SIZE_M = 0.1
"""What :func:`body_extent_m` adds to the span of the units' centres: one unit's size (m)."""

MIN_DISTANCE_M = 0.3
"""The closest a framing camera comes (m), for bodies of one or two units."""


@dataclass(frozen=True, kw_only=True)
class CameraConfig:
    """A camera that follows the robot from behind, looking toward the light.

    Attributes:
        width: image width (px).
        height: image height (px).
        fps: frames per second of simulated time (1/s).
        distance_m: distance from the robot's centre of mass (m); None frames the body:
            ``FRAMING`` times its largest horizontal extent at rest (:meth:`distance_for`).
        pitch_deg: how far the camera looks down (deg).
        fov_deg: vertical field of view (deg).
    """

    width: int = WIDTH_PX
    height: int = HEIGHT_PX
    fps: int = 20
    distance_m: float | None = None
    pitch_deg: float = 25.0
    fov_deg: float = 60.0

    def __post_init__(self) -> None:
        if self.width < 16 or self.height < 16:
            raise ValueError(f"image must be at least 16x16 px, got {self.width}x{self.height}")
        if not 1 <= self.fps <= 240:
            raise ValueError(f"fps must be in 1..240, got {self.fps}")
        if self.distance_m is not None and not self.distance_m > 0:
            raise ValueError(f"distance_m must be positive, got {self.distance_m}")
        if not 0 < self.fov_deg < 180:
            raise ValueError(f"fov_deg must be in (0, 180), got {self.fov_deg}")
        if not -90 < self.pitch_deg < 90:
            raise ValueError(f"pitch_deg must be in (-90, 90), got {self.pitch_deg}")

    @property
    def pitch_rad(self) -> float:
        return math.radians(self.pitch_deg)

    def distance_for(self, extent_m: float) -> float:
        """The camera's distance (m) for a body ``extent_m`` across: ``distance_m`` if given,
        else one that frames the body (``FRAMING`` times its extent, at least
        ``MIN_DISTANCE_M``)."""
        if self.distance_m is not None:
            return self.distance_m
        return max(MIN_DISTANCE_M, FRAMING * extent_m)


def body_extent_m(centres_m: np.ndarray) -> float:
    """A body's largest horizontal extent (m): the largest horizontal distance between two of
    its units' centres of mass ``centres_m`` (U, 3), plus one unit's size (``UNIT_SIZE_M``)."""
    xy = np.asarray(centres_m, dtype=float).reshape(-1, 3)[:, :2]
    span = float(np.max(np.linalg.norm(xy[:, None, :] - xy[None, :, :], axis=-1)))
    return span + UNIT_SIZE_M
