"""What a robot can be re-formed from: its body's units and the spares a user names.

A spare unit copies a unit of its type in the body (its axis, levels and friction), and spares
that make up a leg of the body's shape become a spare leg, so that a body that lost a leg can
take a new one. A unit type that the body lacks is taken as it is: a passive unit bare, an
active one about the yaw axis with levels -20, 0 and 20 deg (inside its limits).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from qdsega.description import Formation, Leg, PlacedUnit
from qdsega.description.formation import joint_name_of
from qdsega.description.formation_reader import AXES
from qdsega.description.shipped import UNITS_DIR
from qdsega.description.unit_type import find_unit_type, load_unit_type
from qdsega.errors import ConfigError, FormationError
from qdsega.reform.arrangement import Material, chain_levels

MAX_SPARES = 64
"""Spare units of one type at most (a formation has at most 128 units)."""
NEW_LEVELS_DEG = (-20.0, 0.0, 20.0)
"""Levels of a spare active unit whose type the body lacks (deg)."""


def parse_units(given: Sequence[str], *, what: str = "--spare") -> dict[str, int]:
    """``["servo=2", "hub=1"]`` -> ``{"servo": 2, "hub": 1}``; ``what`` names the argument in
    an error.

    Raises:
        ConfigError: not ``TYPE=N`` with N from 1 to :data:`MAX_SPARES`, or a type named twice.
    """
    units: dict[str, int] = {}
    for text in given:
        name, _, count = text.partition("=")
        if not name or not count.isdigit() or not 1 <= int(count) <= MAX_SPARES:
            raise ConfigError(f"{what} {text!r}: expected TYPE=N with N from 1 to {MAX_SPARES}")
        if name in units:
            raise ConfigError(f"{what} {name} given twice")
        units[name] = int(count)
    return units


def material_of(formation: Formation, spares: dict[str, int]) -> Material:
    """The units of ``formation`` and the ``spares`` (unit type -> count).

    Raises:
        FormationError: a spare type that no unit folder defines.
    """
    units = {u.name: u for u in formation.units}
    legs = list(formation.legs + formation.broken_legs)
    loose = _spare_units(formation, spares)
    model = formation.legs[0] if formation.legs else None
    number = 1
    while model is not None and _take(loose, [units[n].unit_type.name for n in model.units]):
        name = _free_name(f"S{number}", units)
        copies = {n: f"{name}_{n.removeprefix(model.name + '_')}" for n in model.units}
        for unit_name, copy in copies.items():
            unit = units[unit_name]
            parent = copies.get(unit.parent) if unit.parent is not None else None
            units[copy] = replace(
                unit,
                name=copy,
                parent=parent,
                connector=unit.connector if parent is not None else None,
                line=None,
            )
        swing = next(u for u in model.units if units[u].joint_name == model.swing_joint)
        lift = next(u for u in model.units if units[u].joint_name == model.lift_joint)
        leg_units = tuple(copies[u] for u in model.units)
        # the joints the copies have once attached (a spare leg's top hangs from nothing yet)
        joints = joint_name_of(copies[swing]), joint_name_of(copies[lift])
        legs.append(Leg(name, model.side, *joints, leg_units))
        number += 1
    for unit in loose:
        name = _free_name(f"spare_{unit.unit_type.name}", units)
        units[name] = replace(unit, name=name)
    return Material(source=formation, units=units, legs=tuple(legs))


def _spare_units(formation: Formation, spares: dict[str, int]) -> list[PlacedUnit]:
    """One loose unit (no parent) per spare, each a copy of the first unit of its type in the
    body (a trunk unit before a leg's), else new."""
    folders = [UNITS_DIR, *{u.unit_type.folder.parent for u in formation.units}]
    leg_units = {n for leg in formation.legs + formation.broken_legs for n in leg.units}
    loose = []
    for type_name, count in spares.items():
        same = [u for u in formation.units if u.unit_type.name == type_name]
        same.sort(key=lambda u: (u.name in leg_units, u.parent is None))
        if same and same[0].parent is not None:
            model = replace(same[0], parent=None, connector=None, locked_rad=None, line=None)
            if not model.levels_rad and model.axis is not None:  # a locked model: levels anew
                model = replace(model, levels_rad=_new_levels(model))
        else:
            model = _new_unit(formation, type_name, folders)
        loose += [replace(model, name=f"{type_name}{k}") for k in range(count)]
    return loose


def _new_unit(formation: Formation, type_name: str, folders: list[Path]) -> PlacedUnit:
    try:
        unit_type = load_unit_type(find_unit_type(folders, type_name), type_name)
    except FormationError as exc:
        raise FormationError(f"--spare {type_name}: {exc.message}") from None
    unit = PlacedUnit(
        name=type_name,
        unit_type=unit_type,
        parent=None,
        connector=None,
        axis=AXES["yaw"] if unit_type.is_active else None,
        levels_rad=(),
        friction=formation.root.friction,
    )
    return replace(unit, levels_rad=_new_levels(unit)) if unit_type.is_active else unit


def _new_levels(unit: PlacedUnit) -> tuple[float, ...]:
    spread = replace(unit, levels_rad=tuple(math.radians(a) for a in NEW_LEVELS_DEG))
    return chain_levels(spread)


def _take(loose: list[PlacedUnit], types: list[str]) -> bool:
    """Take loose units of ``types`` (one each) out of ``loose``; False (and nothing taken)
    when they are not all there."""
    kinds = [u.unit_type.name for u in loose]
    for kind in set(types):
        if kinds.count(kind) < types.count(kind):
            return False
    for kind in types:
        loose.pop(next(i for i, u in enumerate(loose) if u.unit_type.name == kind))
    return True


def _free_name(stem: str, taken: dict[str, PlacedUnit]) -> str:
    """``stem``, or ``stem2``, ``stem3``, ... where a unit (or a unit's prefix) has it."""
    name, k = stem, 1
    while any(n == name or n.startswith(name + "_") for n in taken):
        k += 1
        name = f"{stem}{k}"
    return name
