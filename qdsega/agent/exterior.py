"""Exterior state (section 4.1.3): the bin of the angle from the robot's heading to the light.

The paper divides the angle into "four states (from -45 deg to 45 deg each 30 deg)". Read
here as edges at -45, -15, 15 and 45 deg: three 30-deg bins in the field ahead, with
straight-ahead (-15..15 deg) a bin of its own, plus one state for a light outside +-45 deg.
Exterior state 0 is "outside"; state ``k`` is the bin ``[edges[k-1], edges[k])``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit


def bin_edges_rad(edges_deg: Sequence[float]) -> np.ndarray:
    """Bin edges (deg), at least 2 and strictly increasing, as an array (rad)."""
    edges = np.radians(np.asarray(edges_deg, dtype=np.float64))
    if edges.ndim != 1 or len(edges) < 2 or np.any(np.diff(edges) <= 0):
        raise ValueError(f"need at least 2 strictly increasing edges, got {list(edges_deg)}")
    return edges


@njit(cache=True)
def angle_to_light(x: float, y: float, theta: float, light_x: float, light_y: float) -> float:
    """Angle from the heading ``theta`` to the light, counter-clockwise, in [-pi, pi] (rad)."""
    angle = math.atan2(light_y - y, light_x - x) - theta
    return math.atan2(math.sin(angle), math.cos(angle))


@njit(cache=True)
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
