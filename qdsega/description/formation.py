"""Formations: a robot as a tree of units, the validated data model.

``formation_reader.load_formation`` reads one from YAML; see ``assemblies/*.yaml`` for worked
examples and docs/formations.md for every key.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Literal

import numpy as np

from qdsega.description.unit_type import JointSpec, UnitType

Side = Literal["left", "right"]


def joint_name_of(unit: str) -> str:
    """URDF name of the joint that attaches the unit named ``unit`` to its parent."""
    return f"{unit}_joint"


ISOTROPIC = (1.0, 1.0, 1.0)
"""Anisotropic friction scales of a link that slides alike every way (the default)."""


@dataclass(frozen=True)
class Friction:
    """Contact friction of a unit's link.

    Attributes:
        lateral: Coulomb friction coefficient against the ground (-).
        anisotropic: per-axis scale of ``lateral`` in the link frame (x, y, z) (-); units trail
            along their -x axis, so ``[0.01, 1, 0.01]`` slides easily along the body only.
    """

    lateral: float
    anisotropic: tuple[float, float, float]

    @property
    def is_isotropic(self) -> bool:
        """The link slides alike every way: its anisotropic scales are all 1."""
        return self.anisotropic == ISOTROPIC


@dataclass(frozen=True)
class Light:
    """The light source the robot walks toward (the paper's task, section 4.1.1).

    Attributes:
        distance_m: distance from the robot's start (m).
        bearing_rad: direction from the start, counter-clockwise from the robot's initial
            heading (+x of the world) (rad).
    """

    distance_m: float
    bearing_rad: float

    @property
    def position_m(self) -> tuple[float, float]:
        """Light position (x, y) in the world frame (m)."""
        return (
            self.distance_m * math.cos(self.bearing_rad),
            self.distance_m * math.sin(self.bearing_rad),
        )


@dataclass(frozen=True)
class PlacedUnit:
    """One unit of a formation: its type, where it attaches and how its joint is commanded.

    Attributes:
        name: unique unit name; also the URDF link name.
        unit_type: the unit's type.
        parent: parent unit name, or None for the root unit.
        connector: the parent's connector this unit attaches to (None for the root).
        axis: joint axis in the joint frame, unit vector, shape (3,); None when the unit has no
            joint (root or passive unit).
        levels_rad: discrete target angles the learner may command (rad); empty unless the
            unit's joint is actuated (a locked joint has none).
        friction: friction of this unit's link.
        line: line of the formation file that declared it.
        locked_rad: a broken joint, locked at this angle about ``axis`` (rad): it becomes a
            fixed joint and no longer an action dimension; None for a working joint.
    """

    name: str
    unit_type: UnitType
    parent: str | None
    connector: str | None
    axis: tuple[float, float, float] | None
    levels_rad: tuple[float, ...]
    friction: Friction
    line: int | None = None
    locked_rad: float | None = None

    @property
    def joint_name(self) -> str | None:
        """URDF name of the joint to the parent (active or fixed), None for the root."""
        return None if self.parent is None else joint_name_of(self.name)

    @property
    def is_actuated(self) -> bool:
        """The unit has a working joint (not locked) that the learner commands."""
        return self.axis is not None and self.locked_rad is None


@dataclass(frozen=True)
class ActuatedJoint:
    """An actuated joint as the learner sees it.

    Attributes:
        name: URDF joint name.
        unit: name of the unit it moves (its child link).
        levels_rad: commandable target angles (rad), in the formation's order.
        spec: the actuator's limits.
    """

    name: str
    unit: str
    levels_rad: tuple[float, ...]
    spec: JointSpec


@dataclass(frozen=True)
class Leg:
    """A two-joint leg, for gait models (the MSM, section 4.1.2) and gait references.

    A leg instance with a locked joint is a broken leg (:attr:`Formation.broken_legs`): its
    units still belong to no trunk, but no gait model moves it.

    Convention: the swing joint's levels are ``[forward, back]`` and the lift joint's levels are
    ``[down, up]``, so the paper's leg states are 1 = (forward, down), 2 = (back, down),
    3 = (forward, up), 4 = (back, up).

    Attributes:
        name: leg name (the template instance name).
        side: ``left`` or ``right`` of the robot's heading.
        swing_joint: URDF name of the swing joint (moves the leg forward/back).
        lift_joint: URDF name of the lift joint (puts the leg down/up).
        units: names of every unit of the leg (the template instance's units).
    """

    name: str
    side: Side
    swing_joint: str
    lift_joint: str
    units: tuple[str, ...] = ()


@dataclass(frozen=True)
class Formation:
    """A validated formation.

    Attributes:
        name: formation name.
        description: one line for humans.
        file: the YAML file it was read from.
        units: every unit, root first, parents before children.
        light: the light-source task.
        legs: the working legs in declaration order (front to back per side); empty for a
            snake.
        broken_legs: leg instances with a locked joint, in declaration order.
    """

    name: str
    description: str
    file: Path
    units: tuple[PlacedUnit, ...]
    light: Light
    legs: tuple[Leg, ...] = field(default=())
    broken_legs: tuple[Leg, ...] = field(default=())

    @property
    def root(self) -> PlacedUnit:
        return self.units[0]

    @cached_property
    def joints(self) -> tuple[ActuatedJoint, ...]:
        """Actuated joints in formation order: the learner's action dimensions (computed
        once: a formation is immutable)."""
        joints = []
        for u in self.units:
            if u.is_actuated:
                # an actuated unit has a parent (so a joint name) and an active unit type
                assert u.joint_name is not None and u.unit_type.joint is not None
                joints.append(ActuatedJoint(u.joint_name, u.name, u.levels_rad, u.unit_type.joint))
        return tuple(joints)

    @cached_property
    def unit_index(self) -> dict[str, int]:
        """Each unit's position in :attr:`units`, by name: the columns of a contact record."""
        return {u.name: i for i, u in enumerate(self.units)}

    @cached_property
    def units_by_name(self) -> dict[str, PlacedUnit]:
        """Every unit by its name."""
        return {u.name: u for u in self.units}

    def joint_index(self, joint_name: str) -> int:
        """Position of ``joint_name`` in :attr:`joints`."""
        names = [j.name for j in self.joints]
        if joint_name not in names:
            raise KeyError(f"{self.name} has no actuated joint {joint_name!r}")
        return names.index(joint_name)

    def rest_levels(self) -> tuple[int, ...]:
        """A standing start posture, as one level index per joint in :attr:`joints` order.

        Legs stand: swing forward (level 0) and lift down (level 0), also the working joint of
        a broken leg. Every other joint takes the level nearest to 0 rad (the first of equally
        near ones).
        """
        legs = self.legs + self.broken_legs
        leg_joints = {leg.swing_joint for leg in legs} | {leg.lift_joint for leg in legs}
        return tuple(
            0
            if joint.name in leg_joints
            else min(range(len(joint.levels_rad)), key=lambda k: abs(joint.levels_rad[k]))
            for joint in self.joints
        )

    def posture_rad(self, levels: Sequence[int] | np.ndarray) -> tuple[float, ...]:
        """Joint angles (rad), shape (J,), of a posture given as level indices, shape (J,)."""
        if len(levels) != len(self.joints):
            raise ValueError(f"{self.name} has {len(self.joints)} joints, got {len(levels)} levels")
        return tuple(j.levels_rad[k] for j, k in zip(self.joints, levels, strict=True))

    @property
    def trunk_units(self) -> tuple[PlacedUnit, ...]:
        """Units that belong to no leg, working or broken: a legged robot's trunk, or every
        unit of a snake."""
        leg_units = {name for leg in self.legs + self.broken_legs for name in leg.units}
        return tuple(u for u in self.units if u.name not in leg_units)

    def legs_on(self, side: Side) -> tuple[Leg, ...]:
        return tuple(leg for leg in self.legs if leg.side == side)

    def with_light(self, light: Light) -> Formation:
        """The same formation with the light elsewhere."""
        return replace(self, light=light)
