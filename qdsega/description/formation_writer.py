"""A :class:`Formation` written back as YAML that ``load_formation`` reads into the same
formation: units, joints, levels, locks, friction, legs and light.

Bodies made by the toolkit itself (``qdsega reform``'s candidates) are written this way. Legs
are written as template instances, one template per leg shape, since the format declares legs
only through templates; everything else is one plain entry per unit.
"""

from __future__ import annotations

import math
from collections import Counter
from os.path import relpath
from pathlib import Path
from typing import Any

import yaml

from qdsega.description.formation import Formation, Friction, Leg, PlacedUnit
from qdsega.description.formation_reader import AXES
from qdsega.description.shipped import UNITS_DIR
from qdsega.errors import FormationError

_DECIMALS = 9
"""Angles are written in degrees to this many decimals: a shipped level reads back exactly."""


def formation_yaml(formation: Formation, file: Path, *, comment: str = "") -> str:
    """The YAML text of ``formation``, to be saved as ``file`` (a folder of the user's own unit
    types is written relative to it); ``comment`` heads it, one ``#`` line per line.

    Raises:
        FormationError: its unit types come from more than one folder besides the shipped one.
    """
    default = Counter(u.friction for u in formation.units).most_common(1)[0][0]
    data: dict[str, Any] = {"name": formation.name}
    if formation.description != formation.name:
        data["description"] = formation.description
    data["friction"] = _friction(default)
    light = {"distance_m": formation.light.distance_m}
    light["bearing_deg"] = _degrees(formation.light.bearing_rad)
    data["light"] = light
    own = _units_dir(formation, file)
    if own is not None:
        data["units_dir"] = own
    legs = formation.legs + formation.broken_legs
    leg_of = {name: leg for leg in legs for name in leg.units}
    templates: dict[str, dict[str, Any]] = {}
    shape_of: dict[tuple[Any, ...], str] = {}
    units: list[dict[str, Any]] = []
    for unit in formation.units:
        leg = leg_of.get(unit.name)
        if leg is None:
            units.append(_unit_entry(unit, default))
        elif unit.name == _leg_root(formation, leg).name:
            units.append(_instance(formation, leg, default, templates, shape_of))
    text = "".join(f"# {line}\n" for line in comment.splitlines())
    text += yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=100)
    if templates:
        text += "templates:\n"
        for name, template in templates.items():
            text += f"  {name}:\n    leg: {_flow(template['leg'])}\n    units:\n"
            text += "".join(f"      - {_flow(entry)}\n" for entry in template["units"])
    return text + "units:\n" + "".join(f"  - {_flow(entry)}\n" for entry in units)


def _flow(value: dict[str, Any]) -> str:
    """One YAML mapping on one line."""
    return yaml.safe_dump(value, sort_keys=False, default_flow_style=True, width=10**6).strip()


def _units_dir(formation: Formation, file: Path) -> str | None:
    folders = {u.unit_type.folder.parent.resolve() for u in formation.units}
    folders.discard(UNITS_DIR.resolve())
    if len(folders) > 1:
        names = ", ".join(str(f) for f in sorted(folders))
        raise FormationError(f"unit types from more than one folder ({names})", file=file)
    if not folders:
        return None
    return relpath(folders.pop(), Path(file).resolve().parent)


def _leg_root(formation: Formation, leg: Leg) -> PlacedUnit:
    """The leg's unit that hangs from outside the leg (where the instance attaches)."""
    units = formation.units_by_name
    return next(units[n] for n in leg.units if units[n].parent not in leg.units)


def _local(leg: Leg, name: str) -> str:
    return name.removeprefix(f"{leg.name}_")


def _instance(
    formation: Formation,
    leg: Leg,
    default: Friction,
    templates: dict[str, dict[str, Any]],
    shape_of: dict[tuple[Any, ...], str],
) -> dict[str, Any]:
    """A leg's instance entry; its template is added to ``templates`` where no earlier leg
    has the same shape (units, their frames and axes, swing and lift)."""
    units = formation.units_by_name
    members = [units[n] for n in leg.units]
    root = _leg_root(formation, leg)
    local_entries = []
    for unit in members:
        entry = _unit_entry(unit, default, with_joint=False)
        entry["name"] = _local(leg, unit.name)
        if unit is root:
            entry.pop("parent", None)
            entry.pop("connector", None)
        else:
            entry["parent"] = _local(leg, entry["parent"])
        local_entries.append(entry)
    locked = tuple(unit.locked_rad is not None for unit in members)
    unit_of = {unit.joint_name: unit.name for unit in members}
    roles = {
        "swing": _local(leg, unit_of[leg.swing_joint]),
        "lift": _local(leg, unit_of[leg.lift_joint]),
    }
    shape = (repr(local_entries), repr(roles), locked)
    if shape not in shape_of:
        name = "leg" if not templates else f"leg{len(templates) + 1}"
        shape_of[shape] = name
        template_units = [
            entry | _joint(unit) for entry, unit in zip(local_entries, members, strict=True)
        ]
        templates[name] = {"leg": roles, "units": template_units}
    template = templates[shape_of[shape]]
    instance: dict[str, Any] = {"name": leg.name, "template": shape_of[shape]}
    instance |= {"parent": root.parent, "connector": root.connector, "side": leg.side}
    overrides = {}
    for written, unit in zip(template["units"], members, strict=True):
        changed = {k: v for k, v in _joint(unit).items() if written.get(k) != v}
        friction = _friction(unit.friction) if unit.friction != default else None
        if friction is not None and written.get("friction") != friction:
            changed["friction"] = friction
        if changed:
            overrides[written["name"]] = changed
    if overrides:
        instance["overrides"] = overrides
    return instance


def _unit_entry(unit: PlacedUnit, default: Friction, *, with_joint: bool = True) -> dict[str, Any]:
    entry: dict[str, Any] = {"name": unit.name, "unit": unit.unit_type.name}
    if unit.parent is not None:
        entry |= {"parent": unit.parent, "connector": unit.connector}
    if unit.axis is not None:
        entry["axis"] = _axis(unit.axis)
    if with_joint:
        entry |= _joint(unit)
    if unit.friction != default:
        entry["friction"] = _friction(unit.friction)
    return entry


def _joint(unit: PlacedUnit) -> dict[str, Any]:
    """``levels_deg`` (and ``locked_deg``) of an active unit with a parent; nothing else."""
    if unit.axis is None:
        return {}
    if unit.locked_rad is not None:
        return {"locked_deg": _degrees(unit.locked_rad)}
    return {"levels_deg": [_degrees(level) for level in unit.levels_rad]}


def _axis(axis: tuple[float, float, float]) -> str | list[float]:
    for name, named in AXES.items():
        if all(math.isclose(a, b, abs_tol=1e-12) for a, b in zip(axis, named, strict=True)):
            return name
    return [round(float(a), 12) for a in axis]


def _degrees(angle_rad: float) -> float | int:
    value = round(math.degrees(angle_rad), _DECIMALS)
    return int(value) if value.is_integer() else value


def _friction(friction: Friction) -> dict[str, Any]:
    return {"lateral": friction.lateral, "anisotropic": list(friction.anisotropic)}
