"""Can every joint reach its levels? A kinematic self-collision check of an assembled body.

A body whose units hit each other on the way to a level fails every command that asks for it
(the lower agent's "joint ... missed its level"), so it learns nothing and no one says why.
This finds such levels before training, in PyBullet with the simulation's collision shapes
and self-collision rules (parent-child pairs never collide).

What is checked, with no ground and no physics: for each actuated joint alone, the other joints
at their rest levels (:meth:`Formation.rest_levels`), the angles from its rest angle to each of
its levels every ``step_deg``, the level itself included. A level is blocked when, at one of
those angles, a unit that the joint moves overlaps a unit that it does not move by more than
``depth_m``: so a level reached only by passing through the hub is blocked too, and a body that
overlaps already at rest is blocked at every level of each joint between the two units. Not
checked: joints moving together (neighbouring legs swinging toward each other), the ground, an
overlap at rest between units joined by fixed joints only.

Cost: about 0.1 ms a checked angle; 20 to 40 ms for a shipped formation, 0.3 s for a snake of
128 units with 9 levels a joint, and at most 360 / ``step_deg`` + 64 angles a joint.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from qdsega.assembly import AssembledRobot
from qdsega.errors import FormationError, QdsegaWarning
from qdsega.simulation.bullet import BulletSimulation
from qdsega.simulation.settings import PhysicsSettings

DEPTH_M = 0.003
"""Overlap (m) that counts as a hit. A graze costs a joint 0.1 m from it under 2 deg, within
the lower agent's 4 deg tolerance; a leg connector turned into the hub overlaps by centimetres
(the shipped bodies overlap nowhere)."""

STEP_DEG = 5.0
"""Largest angle (deg) between checked angles on the way to a level: 5 deg moves a point
0.2 m from the joint by 17 mm, less than any shipped unit is thick."""


@dataclass(frozen=True)
class Blocked:
    """A level a joint cannot reach without the body hitting itself.

    Attributes:
        joint: URDF name of the joint.
        level: index of the level in the joint's levels.
        level_deg: the level (deg).
        at_deg: the first angle on the way from rest where the body hits itself (deg).
        unit: a unit the joint moves.
        other: the unit it hits, which the joint does not move.
        depth_m: how far they overlap (m).
    """

    joint: str
    level: int
    level_deg: float
    at_deg: float
    unit: str
    other: str
    depth_m: float

    def __str__(self) -> str:
        level_deg, at_deg = round(self.level_deg, 1) + 0.0, round(self.at_deg, 1) + 0.0
        where = "" if at_deg == level_deg else f" at {at_deg:g} deg"
        return (
            f"joint {self.joint} cannot reach level {self.level} ({level_deg:g} deg): "
            f"unit {self.unit} hits unit {self.other}{where}"
        )


def unreachable_levels(
    robot: AssembledRobot,
    settings: PhysicsSettings | None = None,
    *,
    depth_m: float = DEPTH_M,
    step_deg: float = STEP_DEG,
) -> list[Blocked]:
    """Every level of every actuated joint that the body cannot reach without hitting itself,
    in joint then level order (see the module's docstring for what is checked); [] when all
    are reachable, or when ``settings`` turn self-collision off."""
    formation = robot.formation
    joints = formation.joints
    if not joints:
        return []
    rest = formation.posture_rad(formation.rest_levels())
    step_rad = math.radians(step_deg)
    children: dict[str, list[str]] = {}
    for unit in formation.units:
        if unit.parent is not None:
            children.setdefault(unit.parent, []).append(unit.name)
    blocked = []
    with BulletSimulation(robot=robot, settings=settings) as sim:
        sim.place_joints(sim.joint_ids, rest)
        for joint_id, joint, rest_rad in zip(sim.joint_ids, joints, rest, strict=True):
            moved = _subtree(joint.unit, children)
            seen: dict[float, tuple[float, str, str] | None] = {}
            for level, level_rad in enumerate(joint.levels_rad):
                for angle in _path(rest_rad, level_rad, step_rad):
                    if angle not in seen:
                        sim.place_joints([joint_id], [angle])
                        seen[angle] = _deepest_overlap(sim, moved, depth_m)
                    overlap = seen[angle]
                    if overlap is not None:
                        depth, mover, other = overlap
                        level_deg, at_deg = math.degrees(level_rad), math.degrees(angle)
                        blocked.append(
                            Blocked(joint.name, level, level_deg, at_deg, mover, other, depth)
                        )
                        break
            sim.place_joints([joint_id], [rest_rad])
    return blocked


def check_reach(robot: AssembledRobot, *, allow_blocked: bool = False) -> None:
    """Refuse a body with a level that a joint cannot reach (:func:`unreachable_levels`); with
    ``allow_blocked``, say the same in a :class:`QdsegaWarning` and let the body go on (the
    user knows: say, legs that touch at one swing level).

    Raises:
        FormationError: the first blocked level, at the line of the unit whose joint it is,
            and how many more are blocked.
    """
    blocked = unreachable_levels(robot)
    if not blocked:
        return
    formation = robot.formation
    unit = next(u for u in formation.units if u.joint_name == blocked[0].joint)
    others = len(blocked) - 1
    more = f" ({others} more level{'s' * (others > 1)} blocked)" if others else ""
    error = FormationError(f"{blocked[0]}{more}", file=formation.file, line=unit.line)
    if not allow_blocked:
        raise FormationError(
            f"{blocked[0]}{more} (--allow-blocked goes on regardless)",
            file=formation.file,
            line=unit.line,
        )
    warnings.warn(
        f"{error}; going on (--allow-blocked): a command the units stop fails as a missed level",
        QdsegaWarning,
        stacklevel=2,
    )


def _deepest_overlap(
    sim: BulletSimulation, moved: set[str], depth_m: float
) -> tuple[float, str, str] | None:
    """(depth (m), moved unit, unmoved unit) of the deepest overlap deeper than ``depth_m``
    between a unit in ``moved`` and one outside it, or None."""
    overlaps = [
        (-distance, a, b) if a in moved else (-distance, b, a)
        for a, b, distance in sim.self_contacts()
        if -distance > depth_m and (a in moved) != (b in moved)
    ]
    return max(overlaps, default=None)


def _subtree(unit: str, children: dict[str, list[str]]) -> set[str]:
    """``unit`` and every unit attached below it."""
    found, stack = set(), [unit]
    while stack:
        name = stack.pop()
        found.add(name)
        stack.extend(children.get(name, ()))
    return found


def _path(start: float, end: float, step: float) -> list[float]:
    """Angles from ``start`` toward ``end`` every ``step``, then ``end`` (rad); on a grid from
    ``start``, so the levels on one side share their angles."""
    direction = 1.0 if end >= start else -1.0
    count = math.ceil(abs(end - start) / step - 1e-9)
    return [start + direction * step * k for k in range(count)] + [end]
