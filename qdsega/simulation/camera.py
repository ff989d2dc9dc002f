"""Where the camera stands and what it films."""

from __future__ import annotations

import math
from dataclasses import dataclass

LIGHT_RADIUS_FRACTION = 0.02
"""The light's sphere has this fraction of its distance as radius (at least 0.1 m), so that it
shows on the horizon."""


@dataclass(frozen=True, kw_only=True)
class CameraConfig:
    """A camera that follows the robot from behind, looking toward the light.

    Attributes:
        width: image width (px).
        height: image height (px).
        fps: frames per second of simulated time (1/s).
        distance_m: distance from the robot's centre of mass (m).
        pitch_deg: how far the camera looks down (deg).
        fov_deg: vertical field of view (deg).
    """

    width: int = 320
    height: int = 240
    fps: int = 20
    distance_m: float = 1.0
    pitch_deg: float = 25.0
    fov_deg: float = 60.0

    def __post_init__(self) -> None:
        if self.width < 16 or self.height < 16:
            raise ValueError(f"image must be at least 16x16 px, got {self.width}x{self.height}")
        if not 1 <= self.fps <= 240:
            raise ValueError(f"fps must be in 1..240, got {self.fps}")
        if not self.distance_m > 0 or not 0 < self.fov_deg < 180:
            raise ValueError("distance_m must be positive and fov_deg in (0, 180)")
        if not -90 < self.pitch_deg < 90:
            raise ValueError(f"pitch_deg must be in (-90, 90), got {self.pitch_deg}")

    @property
    def pitch_rad(self) -> float:
        return math.radians(self.pitch_deg)
