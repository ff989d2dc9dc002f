"""A body from a bag of units (``qdsega design hub=2 servo=8 --world W``): a first body is
put together by a fixed rule, and ``qdsega reform`` re-forms it for the world, its chain and
its one-move variants included.

The first body: the passive units in a trunk, one behind the other; the active units in
two-unit legs (a yaw swing of -15 and 15 deg, a pitch lift of -35 and 5 deg, within the unit's
limits), left-right pairs from the front along the trunk units that have both sides; any
active units left over hang behind the trunk in a chain (yaw and pitch in turn, levels -20, 0
and 20 deg). With no passive unit, every unit is in the chain. Friction is isotropic, the
ground's coefficient 1.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np

from qdsega.description import Formation, Friction, Leg, Light, PlacedUnit, UnitType
from qdsega.description.formation_reader import AXES
from qdsega.description.shipped import UNITS_DIR
from qdsega.description.unit_type import find_unit_type, load_unit_type
from qdsega.errors import ConfigError, FormationError
from qdsega.reform.arrangement import side_connectors, straight_connector

SWING_DEG = (-15.0, 15.0)
LIFT_DEG = (-35.0, 5.0)
CHAIN_DEG = (-20.0, 0.0, 20.0)
FRICTION = Friction(lateral=1.0, anisotropic=(1.0, 1.0, 1.0))
LIGHT = Light(distance_m=50.0, bearing_rad=0.0)


def first_body(bag: dict[str, int], *, name: str = "design") -> Formation:
    """The first body made of ``bag`` (unit type -> count), by the module's rule.

    Raises:
        FormationError: a unit type no unit folder defines.
        ConfigError: no active unit in the bag (nothing could move).
    """
    types = {}
    for type_name in bag:
        try:
            types[type_name] = load_unit_type(find_unit_type([UNITS_DIR], type_name), type_name)
        except FormationError as exc:
            raise FormationError(f"{type_name}: {exc.message}") from None
    passive = [t for name_, t in types.items() for _ in range(bag[name_]) if not t.is_active]
    active = [t for name_, t in types.items() for _ in range(bag[name_]) if t.is_active]
    if not active:
        raise ConfigError("the units have no joint: nothing could move")
    units: list[PlacedUnit] = []
    legs: list[Leg] = []
    trunk = passive or [active.pop(0)]
    for k, unit_type in enumerate(trunk, start=1):
        parent = None if k == 1 else units[-1]
        units.append(_placed(f"body{k}", unit_type, parent, None, ()))
    slots = [(u, side_connectors(u.unit_type, np.eye(4))) for u in units] if passive else []
    pairs = [(unit, sides) for unit, sides in slots if len(sides) == 2]
    for number, (parent, sides) in enumerate(pairs, start=1):
        for side, connector in sides.items():
            if len(active) < 2:
                break
            swing_type, lift_type = active.pop(0), active.pop(0)
            leg = f"{side[0].upper()}{number}"
            swing_deg = SWING_DEG if side == "left" else tuple(-a for a in SWING_DEG)
            swing = _placed(f"{leg}_swing", swing_type, parent, connector, swing_deg, "yaw")
            lift = _placed(f"{leg}_lift", lift_type, swing, None, LIFT_DEG, "pitch")
            units += [swing, lift]
            assert swing.joint_name is not None and lift.joint_name is not None  # both have parents
            legs.append(Leg(leg, side, swing.joint_name, lift.joint_name, (swing.name, lift.name)))
    tail = units[len(trunk) - 1]
    for k, (unit_type, axis) in enumerate(zip(active, itertools.cycle(("yaw", "pitch"))), start=1):
        tail = _placed(f"tail{k}", unit_type, tail, None, CHAIN_DEG, axis)
        units.append(tail)
    return Formation(
        name=name,
        description=f"a first body of {', '.join(f'{n} {t}' for t, n in bag.items())}",
        file=Path(f"{name}.yaml"),
        units=tuple(units),
        light=LIGHT,
        legs=tuple(legs),
    )


def _placed(
    name: str,
    unit_type: UnitType,
    parent: PlacedUnit | None,
    connector: str | None,
    levels_deg: tuple[float, ...],
    axis: str | None = None,
) -> PlacedUnit:
    """A unit hanging from ``parent`` at ``connector`` (None: its straight connector), a
    working joint about ``axis`` at ``levels_deg`` (inside the joint's limits)."""
    if parent is not None and connector is None:
        connector = straight_connector(parent.unit_type)
        if connector is None:
            raise ConfigError(f"unit type {parent.unit_type.name} has no connector behind it")
    joint = unit_type.joint if parent is not None else None
    levels: tuple[float, ...] = ()
    if joint is not None:
        inside = [min(max(math.radians(a), joint.lower_rad), joint.upper_rad) for a in levels_deg]
        levels = tuple(dict.fromkeys(inside))
    return PlacedUnit(
        name=name,
        unit_type=unit_type,
        parent=None if parent is None else parent.name,
        connector=connector if parent is not None else None,
        axis=AXES[axis] if joint is not None and axis is not None else None,
        levels_rad=levels,
        friction=FRICTION,
    )
