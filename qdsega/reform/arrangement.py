"""A body's units and how they hang together: the material a robot has, and each arrangement
of it that moves reach.

A **move** detaches one unit with everything that hangs from it and attaches it at a free
connector, sets it aside, or takes a part from the spares. Units keep their names, types,
joint axes, locks and friction wherever they go. What the learner commands follows from where
a unit hangs (:meth:`Arrangement.formation`):

* a leg that hangs from a trunk unit (a unit of no leg) stays a leg; its side is where it points
  at rest, and a leg on the other side than before has its joints mirrored, as the templates
  mirror a right leg's swing levels. A leg on a back connector points neither way and keeps its
  side and levels;
* a leg's unit that hangs anywhere else becomes a plain joint of a chain, with levels centred on
  straight (``-A, 0, A``, ``2A`` the span of its leg levels), for a chain must rest straight.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from trimesh.transformations import euler_matrix, rotation_matrix

from qdsega.description import Formation, Leg, PlacedUnit
from qdsega.description.formation import Side
from qdsega.description.unit_type import Connector, UnitType

SIDE_COSINE = 0.5
"""A leg points left (right) when its trailing axis at rest is within 60 deg of the body's +y
(-y); otherwise (a leg on a back connector) it points neither way."""
_MIRROR = np.diag([1.0, -1.0, 1.0])


@dataclass(frozen=True)
class Place:
    """Where a unit hangs: its parent's connector."""

    parent: str
    connector: str

    def __str__(self) -> str:
        return f"{self.parent}.{self.connector}"


@dataclass(frozen=True)
class Move:
    """One step of re-forming: ``unit`` and everything that hangs from it leaves ``leaves``
    and takes ``takes`` (None: the spares, set aside)."""

    unit: str
    leaves: Place | None
    takes: Place | None

    def __str__(self) -> str:
        return f"{self.unit}: {_where(self.leaves)} -> {_where(self.takes)}"


def _where(place: Place | None) -> str:
    return "the spares" if place is None else str(place)


@dataclass(frozen=True)
class Material:
    """Every unit a robot has: its body's and its spares', with the body's legs.

    Attributes:
        source: the body as it is.
        units: every unit by name, the body's in its order and then the spares'; a spare part's
            top unit has no parent.
        legs: every leg instance, working or broken, with the side it has in ``source``
            (a spare leg: the side of the leg it copies).
    """

    source: Formation
    units: dict[str, PlacedUnit]
    legs: tuple[Leg, ...]

    @property
    def root(self) -> str:
        return self.source.root.name

    @cached_property
    def leg_of(self) -> dict[str, Leg]:
        """The leg each leg unit belongs to."""
        return {name: leg for leg in self.legs for name in leg.units}

    @cached_property
    def leg_tops(self) -> dict[str, Leg]:
        """Each leg by its top unit, the one that hangs from outside the leg."""
        return {
            name: leg
            for leg in self.legs
            for name in leg.units
            if self.units[name].parent not in leg.units
        }

    def is_trunk(self, unit: str) -> bool:
        """A unit of no leg: a legged body's trunk, or any unit of a snake."""
        return unit not in self.leg_of

    def counts(self) -> dict[str, int]:
        """Units of each type."""
        counts: dict[str, int] = {}
        for unit in self.units.values():
            counts[unit.unit_type.name] = counts.get(unit.unit_type.name, 0) + 1
        return counts

    def start(self) -> Arrangement:
        """The body as it is, the spares set aside."""
        places = tuple(
            # a unit's parent and connector are both set, or both None
            (
                u.name,
                None if u.parent is None or u.connector is None else Place(u.parent, u.connector),
            )
            for u in self.units.values()
            if u.name != self.root
        )
        return Arrangement(self, places)


@dataclass(frozen=True)
class Arrangement:
    """Where each unit of a material hangs: its body, and the parts set aside.

    Attributes:
        material: the units.
        places: every unit but the root, in the material's order, and where it hangs (None: set
            aside).
    """

    material: Material
    places: tuple[tuple[str, Place | None], ...]
    _children: dict[str, dict[str, str]] = field(init=False, repr=False, compare=False)
    _places: dict[str, Place | None] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        children: dict[str, dict[str, str]] = {name: {} for name in self.material.units}
        for name, place in self.places:
            if place is not None:
                children[place.parent][place.connector] = name
        object.__setattr__(self, "_children", children)
        object.__setattr__(self, "_places", dict(self.places))

    def __hash__(self) -> int:
        return hash(self.places)

    def place(self, unit: str) -> Place | None:
        return self._places.get(unit)

    def children(self, unit: str) -> dict[str, str]:
        """The units hanging from ``unit``, by connector."""
        return self._children[unit]

    @cached_property
    def attached(self) -> tuple[str, ...]:
        """The body's units: the root first, each parent before its children, in the
        material's order where the tree leaves a choice."""
        order = list(self.material.units)
        reached = [self.material.root]
        frontier = [self.material.root]
        while frontier:
            found = [c for parent in frontier for c in self._children[parent].values()]
            found.sort(key=order.index)
            reached += found
            frontier = found
        return tuple(reached)

    def subtree(self, unit: str) -> tuple[str, ...]:
        """``unit`` and everything that hangs from it."""
        found = [unit]
        for name in found:
            found.extend(self._children[name].values())
        return tuple(found)

    def tops(self) -> tuple[str, ...]:
        """The top unit of each part set aside."""
        return tuple(name for name, place in self.places if place is None)

    def free(self) -> Iterator[Place]:
        """Every free connector of the body, in the body's order."""
        for name in self.attached:
            unit = self.material.units[name]
            for connector in unit.unit_type.connectors:
                if connector not in self._children[name]:
                    yield Place(name, connector)

    def can(self, move: Move) -> bool:
        """Whether ``move`` can be made here."""
        if move.unit == self.material.root or self.place(move.unit) != move.leaves:
            return False
        if move.takes is None:
            return move.leaves is not None
        target = move.takes  # on the body, or on a part set aside
        return (
            target.parent in self.material.units
            and target.parent not in self.subtree(move.unit)
            and target.connector in self.material.units[target.parent].unit_type.connectors
            and target.connector not in self._children[target.parent]
        )

    def moved(self, move: Move) -> Arrangement:
        """The arrangement after ``move``.

        Raises:
            ValueError: the move cannot be made here (:meth:`can`).
        """
        if not self.can(move):
            raise ValueError(f"cannot move {move}")
        places = tuple((n, move.takes if n == move.unit else p) for n, p in self.places)
        return Arrangement(self.material, places)

    def legs(self) -> tuple[Leg, ...]:
        """The legs of the body: every leg of the material that hangs from a trunk unit with
        nothing else hanging from it, with the side it points to (module docstring)."""
        frames = self.frames()
        legs = []
        for top, leg in self.material.leg_tops.items():
            place = self.place(top)
            if place is None or top not in frames or not self.material.is_trunk(place.parent):
                continue
            if any(c not in leg.units for n in leg.units for c in self._children[n].values()):
                continue  # something hangs from it: a link of a chain, not a limb
            side = pointing(frames[top]) or leg.side
            legs.append(Leg(leg.name, side, leg.swing_joint, leg.lift_joint, leg.units))
        order = list(self.attached)
        return tuple(sorted(legs, key=lambda leg: order.index(leg.units[0])))

    def frames(self) -> dict[str, np.ndarray]:
        """Each attached unit's frame at rest (4x4, in the root's frame): every joint at 0 rad,
        a locked one at its locked angle."""
        units = self.material.units
        frames = {self.material.root: np.eye(4)}
        for name in self.attached[1:]:
            unit, place = units[name], self.place(name)
            assert place is not None
            connector = units[place.parent].unit_type.connectors[place.connector]
            frames[name] = frames[place.parent] @ connector_matrix(connector)
            if unit.locked_rad is not None and unit.axis is not None:
                frames[name] = frames[name] @ rotation_matrix(unit.locked_rad, unit.axis)
        return frames

    def formation(self, name: str, description: str) -> Formation:
        """The body as a formation: its units where they hang, its legs, and its joints'
        levels as the module docstring says."""
        units = self.material.units
        legs = self.legs()
        in_legs = {n for leg in legs for n in leg.units}
        flipped = {n for leg in legs for n in leg.units if leg.side != self.material.leg_of[n].side}
        placed = []
        for unit_name in self.attached:
            unit = units[unit_name]
            place = self.place(unit_name)
            parent, connector = (None, None) if place is None else (place.parent, place.connector)
            axis, levels, locked = unit.axis, unit.levels_rad, unit.locked_rad
            if unit_name in flipped:
                axis, levels, locked = mirrored_joint(unit)
            elif unit_name in self.material.leg_of and unit_name not in in_legs:
                levels = chain_levels(unit)
            placed.append(
                PlacedUnit(
                    name=unit.name,
                    unit_type=unit.unit_type,
                    parent=parent,
                    connector=connector,
                    axis=axis,
                    levels_rad=levels,
                    friction=unit.friction,
                    locked_rad=locked,
                )
            )
        working = tuple(leg for leg in legs if not _broken(leg, units))
        broken = tuple(leg for leg in legs if _broken(leg, units))
        return Formation(
            name=name,
            description=description,
            file=self.material.source.file,
            units=tuple(placed),
            light=self.material.source.light,
            legs=working,
            broken_legs=broken,
        )

    def key(self, *, mirror: bool = False) -> str:
        """The body's shape with unit names left out (two arrangements with the same key are
        the same body): unit types, joints (levels as a set, about an axis pointing one way),
        locks, friction, which units make legs, and what hangs from which connector. With
        ``mirror`` the key of the body's mirror image, or "" when a unit type has a connector
        without a mirror partner."""
        body = self.formation("", "")
        units = body.units_by_name
        in_legs = {n for leg in body.legs + body.broken_legs for n in leg.units}

        def key_of(name: str) -> str:
            unit = units[name]
            axis, levels, locked = (
                mirrored_joint(unit) if mirror else (unit.axis, unit.levels_rad, unit.locked_rad)
            )
            parts = []
            for connector, child in self._children[name].items():
                label = mirror_connectors(unit.unit_type).get(connector) if mirror else connector
                if label is None:
                    raise _NoMirror
                parts.append(f"{label}:{key_of(child)}")
            leg = "L" if name in in_legs else ""
            friction = f"{unit.friction.lateral:g}/{unit.friction.anisotropic}"
            joint = _joint_key(axis, levels, locked)
            return f"{unit.unit_type.name}{leg}[{joint};{friction}]({','.join(sorted(parts))})"

        try:
            return key_of(self.material.root)
        except _NoMirror:
            return ""


class _NoMirror(Exception):
    """A connector without a mirror partner: the body has no mirror image among bodies."""


def _broken(leg: Leg, units: dict[str, PlacedUnit]) -> bool:
    return any(units[name].locked_rad is not None for name in leg.units)


def _joint_key(
    axis: tuple[float, float, float] | None, levels: tuple[float, ...], locked: float | None
) -> str:
    if axis is None:
        return "-"
    axis, levels, locked = _pointing_one_way(axis, levels, locked)
    angles = sorted(round(math.degrees(a), 6) + 0.0 for a in levels)  # + 0.0: no -0.0
    lock = "" if locked is None else f"@{round(math.degrees(locked), 6) + 0.0}"
    return f"{tuple(round(a, 6) + 0.0 for a in axis)}{angles}{lock}"


def _pointing_one_way(
    axis: tuple[float, float, float], levels: tuple[float, ...], locked: float | None
) -> tuple[tuple[float, float, float], tuple[float, ...], float | None]:
    """The same joint about the axis whose first nonzero component is positive (a turn by
    ``a`` about ``-n`` is a turn by ``-a`` about ``n``)."""
    first = next((c for c in axis if abs(c) > 1e-12), 1.0)
    if first > 0:
        return axis, levels, locked
    flipped = (-axis[0], -axis[1], -axis[2])
    return flipped, tuple(-a for a in levels), None if locked is None else -locked


def mirrored_joint(
    unit: PlacedUnit,
) -> tuple[tuple[float, float, float] | None, tuple[float, ...], float | None]:
    """``unit``'s joint as its mirror image across the body's vertical plane of symmetry:
    about ``(-x, y, -z)`` by the same angles, written about the axis pointing one way (a
    yaw joint's levels change sign, a pitch joint's stay)."""
    if unit.axis is None:
        return None, unit.levels_rad, unit.locked_rad
    x, y, z = unit.axis
    return _pointing_one_way((-x, y, -z), unit.levels_rad, unit.locked_rad)


def chain_levels(unit: PlacedUnit) -> tuple[float, ...]:
    """A leg unit's levels in a chain: ``-A, 0, A`` with ``2A`` the span of its levels, inside
    its joint's limits (a locked unit has none)."""
    if not unit.levels_rad or unit.unit_type.joint is None:
        return unit.levels_rad
    spec = unit.unit_type.joint
    half = (max(unit.levels_rad) - min(unit.levels_rad)) / 2.0
    half = min(half, -spec.lower_rad, spec.upper_rad)
    half = round(math.degrees(half), 3)
    return (0.0,) if half <= 0 else tuple(math.radians(a) for a in (-half, 0.0, half))


@functools.lru_cache(maxsize=1024)
def connector_matrix(connector: Connector) -> np.ndarray:
    """The connector's frame in its unit's frame (4x4; read only, it is shared)."""
    matrix = euler_matrix(*connector.rpy_rad, axes="sxyz")
    matrix[:3, 3] = connector.xyz_m
    matrix.setflags(write=False)
    return matrix


def pointing(frame: np.ndarray) -> Side | None:
    """The side a unit trails toward from its ``frame`` in the root's (+x ahead, +y left):
    ``left``, ``right``, or None (ahead or behind)."""
    trailing_y = -frame[1, 0]
    if trailing_y > SIDE_COSINE:
        return "left"
    if trailing_y < -SIDE_COSINE:
        return "right"
    return None


def side_connectors(unit_type: UnitType, frame: np.ndarray) -> dict[Side, str]:
    """The connectors of a unit at ``frame`` (in the root's) whose child would trail to the
    left and to the right, by side."""
    sides: dict[Side, str] = {}
    for name, connector in unit_type.connectors.items():
        side = pointing(frame @ connector_matrix(connector))
        if side is not None:
            sides[side] = name
    return sides


def straight_connector(unit_type: UnitType) -> str | None:
    """The connector that continues a unit straight behind (``back`` of the shipped units):
    no turn, on the unit's x axis, behind its origin."""
    for name, connector in unit_type.connectors.items():
        matrix = connector_matrix(connector)
        x, y, z = matrix[:3, 3]
        if np.allclose(matrix[:3, :3], np.eye(3), atol=1e-9) and x < 0 and abs(y) + abs(z) < 1e-9:
            return name
    return None


def mirror_connectors(unit_type: UnitType) -> dict[str, str]:
    """Each connector's mirror partner across the unit's x-z plane (``left`` and ``right``
    of the shipped units; ``back`` is its own); a connector with none is left out."""
    partners = {}
    for name, connector in unit_type.connectors.items():
        image = _MIRROR @ connector_matrix(connector)[:3, :3] @ _MIRROR
        position = _MIRROR @ np.asarray(connector.xyz_m)
        for other_name, other in unit_type.connectors.items():
            matrix = connector_matrix(other)
            if np.allclose(matrix[:3, 3], position, atol=1e-9) and np.allclose(
                matrix[:3, :3], image, atol=1e-9
            ):
                partners[name] = other_name
    return partners
