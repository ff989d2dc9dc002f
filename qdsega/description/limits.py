"""Bounds on everything a unit or formation file may hold, checked as each value is read.

They keep a hostile or mistaken file from exhausting time or memory (a billion levels, a
million units, nested YAML aliases) and keep bodies within what PyBullet simulates sensibly.
docs/formations.md lists them (Limits).
"""

from __future__ import annotations

import math

from qdsega.yaml_reader import Interval

MAX_UNITS = 128
"""Units in one formation, counted after repeats and templates are expanded."""

MAX_LEVELS = 64
"""Levels of one joint (the paper's snake has 9, a leg joint 2)."""

REPEAT_INDEX = Interval(-1_000_000, 1_000_000)
"""First and last index of a ``repeat`` entry."""

ANGLE_DEG = Interval(-360.0, 360.0)
"""Angles in degrees: levels, bearings, connector rotations (deg)."""

JOINT_LIMIT_DEG = Interval(-180.0, 180.0)
"""A revolute joint's lower and upper limit (deg)."""

LEVEL_STEP_DEG = Interval(0.0, 360.0, open_low=True)
"""``step`` of a ``levels_deg: {min, max, step}`` range (deg)."""

AXIS_COMPONENT = Interval(-1000.0, 1000.0)
"""Each component of an ``axis: [x, y, z]`` vector (-); only its direction counts."""

FRICTION = Interval(0.0, 10.0, open_low=True)
"""Friction coefficient ``lateral`` and each ``anisotropic`` scale (-)."""

LIGHT_DISTANCE_M = Interval(0.0, 10_000.0, open_low=True)
"""Distance from the start to the light (m)."""

MASS_KG = Interval(0.0, 100.0, open_low=True)
"""A unit's mass (kg)."""

EFFORT_NM = Interval(0.0, 1000.0, open_low=True)
"""A joint's torque limit (N m)."""

SPEED_RAD_S = Interval(0.0, 100.0, open_low=True)
"""A joint's speed limit (rad/s)."""

POSITION_M = Interval(-10.0, 10.0)
"""Positions in a unit's frame: connectors, collision-shape origins (m)."""

SIZE_M = Interval(0.0, 10.0, open_low=True)
"""Collision-shape sizes: box edges, radii, cylinder lengths (m)."""

ROTATION_RAD = Interval(-2.0 * math.pi, 2.0 * math.pi)
"""Roll, pitch and yaw of a collision shape's origin in a link template (rad)."""
