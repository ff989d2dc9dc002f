"""Formation files: YAML read into a validated :class:`Formation`, every mistake located.

Reading expands ``repeat`` entries and template instances into flat unit entries, then checks
each unit against its unit type and the whole against the tree rules.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from qdsega.description.formation import (
    ISOTROPIC,
    Formation,
    Friction,
    Leg,
    Light,
    PlacedUnit,
    Side,
)
from qdsega.description.limits import (
    ANGLE_DEG,
    AXIS_COMPONENT,
    FRICTION,
    LEVEL_STEP_DEG,
    LIGHT_DISTANCE_M,
    MAX_LEVELS,
    MAX_UNITS,
    REPEAT_INDEX,
)
from qdsega.description.shipped import UNITS_DIR
from qdsega.description.unit_type import JointSpec, UnitType, find_unit_type, load_unit_type
from qdsega.errors import FormationError, QdsegaError
from qdsega.yaml_reader import KeyPath, Reader, load_yaml

AXES = {"roll": (1.0, 0.0, 0.0), "pitch": (0.0, 1.0, 0.0), "yaw": (0.0, 0.0, 1.0)}
"""Named joint axes, in the joint (= child unit) frame."""

_TOP_KEYS = ("name", "units", "light")
_TOP_OPTIONAL = ("description", "friction", "templates", "units_dir")
_UNIT_KEYS = (
    "name", "unit", "parent", "connector", "axis", "levels_deg", "locked_deg", "friction", "repeat"
)  # fmt: skip
_INSTANCE_KEYS = ("name", "template", "parent", "connector", "side", "overrides", "repeat")
_OVERRIDE_KEYS = ("axis", "levels_deg", "locked_deg", "friction")
_INDEX = re.compile(r"\{i([+-]\d+)?\}")


@dataclass(frozen=True)
class _Value:
    """A raw YAML value and where it came from."""

    value: Any
    path: KeyPath


@dataclass
class _RawUnit:
    """A unit entry after repeats and templates are expanded, before validation."""

    path: KeyPath
    name: str
    fields: dict[str, _Value]
    note: str = ""


def load_formation(file: Path | str, *, units_dir: Path | None = None) -> Formation:
    """Read and validate a formation file.

    Args:
        file: the formation YAML.
        units_dir: the one folder unit types come from (a run folder's copy); default: the
            file's ``units_dir`` key, a folder of the user's own unit types searched beside
            the shipped ``units/``, else the shipped ``units/`` alone.

    Raises:
        FormationError: one line naming the file, the line, the key path and what is wrong.
    """
    file = Path(file)
    reader = Reader(load_yaml(file))
    top = reader.mapping((), reader.document.data, required=_TOP_KEYS, optional=_TOP_OPTIONAL)
    name = reader.text(("name",), top["name"])
    description = reader.text(("description",), top.get("description", name))
    units_dirs = [UNITS_DIR] if units_dir is None else [units_dir]
    if units_dir is None and "units_dir" in top:
        units_dirs.insert(0, file.parent / reader.text(("units_dir",), top["units_dir"]))
    default_friction = _read_friction(reader, ("friction",), top.get("friction", {}), None)
    light = read_light(reader, ("light",), top["light"])
    templates = _read_templates(reader, top.get("templates", {}))
    raw_units, leg_specs = _expand(reader, top["units"], templates)

    unit_types: dict[str, UnitType] = {}
    units: list[PlacedUnit] = []
    seen: dict[str, _RawUnit] = {}
    for raw in raw_units:
        if raw.name in seen:
            raise _error(reader, raw, "name", f"duplicate unit name '{raw.name}'")
        seen[raw.name] = raw
        units.append(_read_unit(reader, raw, unit_types, units_dirs, default_friction))
    ordered = _tree_order(reader, units, {u.name: seen[u.name] for u in units})
    legs, broken = _resolve_legs(reader, leg_specs, {u.name: u for u in ordered})
    return Formation(
        name=name,
        description=description,
        file=file,
        units=tuple(ordered),
        light=light,
        legs=tuple(legs),
        broken_legs=tuple(broken),
    )


def _error(reader: Reader, raw: _RawUnit, key: str, message: str) -> QdsegaError:
    source = raw.fields.get(key)
    path = source.path if source is not None else raw.path
    return reader.error(path, message + raw.note)


def _read_friction(reader: Reader, path: KeyPath, value: Any, default: Friction | None) -> Friction:
    raw = reader.mapping(path, value, optional=("lateral", "anisotropic"))
    lateral = 1.0 if default is None else default.lateral
    anisotropic = ISOTROPIC if default is None else default.anisotropic
    if "lateral" in raw:
        lateral = reader.number((*path, "lateral"), raw["lateral"], FRICTION)
    if "anisotropic" in raw:
        anisotropic = reader.triple((*path, "anisotropic"), raw["anisotropic"], FRICTION)
    return Friction(lateral=lateral, anisotropic=anisotropic)


def read_light(reader: Reader, path: KeyPath, value: Any) -> Light:
    """A ``light:`` mapping (``distance_m``, optional ``bearing_deg``) at ``path``."""
    raw = reader.mapping(path, value, required=("distance_m",), optional=("bearing_deg",))
    return Light(
        distance_m=reader.number((*path, "distance_m"), raw["distance_m"], LIGHT_DISTANCE_M),
        bearing_rad=math.radians(
            reader.number((*path, "bearing_deg"), raw.get("bearing_deg", 0.0), ANGLE_DEG)
        ),
    )


@dataclass(frozen=True)
class _Template:
    units: list[tuple[KeyPath, dict[str, Any]]]
    leg: tuple[_Value, _Value] | None


def _read_templates(reader: Reader, value: Any) -> dict[str, _Template]:
    templates = {}
    for key, body in reader.mapping(("templates",), value, optional=value or ()).items():
        path: KeyPath = ("templates", key)
        raw = reader.mapping(path, body, required=("units",), optional=("leg",))
        entries = reader.sequence((*path, "units"), raw["units"], min_length=1)
        units = []
        for index, entry in enumerate(entries):
            unit_path = (*path, "units", index)
            units.append(
                (
                    unit_path,
                    reader.mapping(
                        unit_path,
                        entry,
                        required=("name", "unit"),
                        optional=set(_UNIT_KEYS) - {"repeat"},
                    ),
                )
            )
        roots = [p for p, u in units if "parent" not in u]
        if len(roots) != 1:
            raise reader.error((*path, "units"), "a template needs exactly one unit without parent")
        names = {reader.text((*p, "name"), u["name"]) for p, u in units}
        leg = None
        if "leg" in raw:
            leg_raw = reader.mapping((*path, "leg"), raw["leg"], required=("swing", "lift"))
            for role in ("swing", "lift"):
                if leg_raw[role] not in names:
                    raise reader.error((*path, "leg", role), f"no unit '{leg_raw[role]}' here")
            leg = (
                _Value(leg_raw["swing"], (*path, "leg", "swing")),
                _Value(leg_raw["lift"], (*path, "leg", "lift")),
            )
        templates[key] = _Template(units=units, leg=leg)
    return templates


def _expand(
    reader: Reader, value: Any, templates: dict[str, _Template]
) -> tuple[list[_RawUnit], list[tuple[_RawUnit, _Template]]]:
    """Expand ``repeat`` and ``template`` entries into flat unit entries."""
    raw_units: list[_RawUnit] = []
    leg_specs: list[tuple[_RawUnit, _Template]] = []
    for index, entry in enumerate(reader.sequence(("units",), value, min_length=1)):
        path: KeyPath = ("units", index)
        is_instance = isinstance(entry, dict) and "template" in entry
        keys = _INSTANCE_KEYS if is_instance else _UNIT_KEYS
        required = ("name", "template") if is_instance else ("name", "unit")
        entry = reader.mapping(path, entry, required=required, optional=keys)
        name_template = reader.text((*path, "name"), entry["name"])
        indices: Sequence[int | None] = [None]
        if "repeat" in entry:
            indices = _read_repeat(reader, (*path, "repeat"), entry["repeat"])
            if not _INDEX.search(name_template):
                raise reader.error((*path, "name"), "a repeated entry's name needs {i}")
        for i in indices:
            note = "" if i is None else f" (repeat i={i})"
            fields = {
                key: _Value(_substitute(val, i), (*path, key))
                for key, val in entry.items()
                if key != "repeat"
            }
            name = _substitute(name_template, i)
            if is_instance:
                template_name = fields.pop("template")
                template = templates.get(template_name.value)
                if template is None:
                    message = f"unknown template '{template_name.value}'"
                    raise reader.error(template_name.path, message)
                instance = _RawUnit(path, name, fields, note)
                raw_units.extend(_instantiate(reader, instance, template))
                if template.leg is not None:
                    leg_specs.append((instance, template))
                elif "side" in fields:
                    raise reader.error(fields["side"].path, "'side' is only for leg templates")
            else:
                raw_units.append(_RawUnit(path, name, fields, note))
            if len(raw_units) > MAX_UNITS:
                break
        if len(raw_units) > MAX_UNITS:
            where = (*path, "repeat") if "repeat" in entry else path
            raise reader.error(where, f"more than {MAX_UNITS} units; a formation has at most that")
    return raw_units, leg_specs


def _read_repeat(reader: Reader, path: KeyPath, value: Any) -> range:
    bounds = reader.sequence(path, value)
    if len(bounds) != 2:
        raise reader.error(path, "expected [first, last] (inclusive integers)")
    first, last = (reader.integer((*path, k), x, REPEAT_INDEX) for k, x in enumerate(bounds))
    if first > last:
        raise reader.error(path, f"first ({first}) must not exceed last ({last})")
    return range(first, last + 1)


def _substitute(value: Any, i: int | None) -> Any:
    """Replace ``{i}``, ``{i-1}``, ``{i+2}`` in text with the repeat index."""
    if i is None or not isinstance(value, str):
        return value
    return _INDEX.sub(lambda m: str(i + int(m.group(1) or 0)), value)


def _instantiate(reader: Reader, instance: _RawUnit, template: _Template) -> list[_RawUnit]:
    overrides_value = instance.fields.get("overrides", _Value({}, instance.path))
    local_names = {u["name"] for _, u in template.units}
    overrides = reader.mapping(overrides_value.path, overrides_value.value, optional=local_names)
    expanded = []
    for unit_path, unit in template.units:
        local = unit["name"]
        fields = {key: _Value(val, (*unit_path, key)) for key, val in unit.items()}
        if "parent" in fields:
            fields["parent"] = _Value(f"{instance.name}_{unit['parent']}", fields["parent"].path)
        else:
            for key in ("parent", "connector"):
                if key in instance.fields:
                    fields[key] = instance.fields[key]
        if local in overrides:
            path = (*overrides_value.path, local)
            for key, val in reader.mapping(path, overrides[local], optional=_OVERRIDE_KEYS).items():
                fields[key] = _Value(val, (*path, key))
        expanded.append(_RawUnit(unit_path, f"{instance.name}_{local}", fields, instance.note))
    return expanded


def _read_unit(
    reader: Reader,
    raw: _RawUnit,
    unit_types: dict[str, UnitType],
    units_dirs: list[Path],
    default_friction: Friction,
) -> PlacedUnit:
    f = raw.fields
    type_name = reader.text(f["unit"].path, f["unit"].value)
    if type_name not in unit_types:
        try:
            unit_types[type_name] = load_unit_type(find_unit_type(units_dirs, type_name), type_name)
        except FormationError as exc:
            if exc.file is None:  # the unit folder is missing: blame the formation line
                raise _error(reader, raw, "unit", exc.message) from None
            raise
    unit_type = unit_types[type_name]
    parent = connector = None
    if ("parent" in f) != ("connector" in f):
        raise _error(
            reader,
            raw,
            "parent" if "parent" in f else "connector",
            "'parent' and 'connector' go together",
        )
    if "parent" in f:
        parent = reader.text(f["parent"].path, f["parent"].value)
        connector = reader.text(f["connector"].path, f["connector"].value)
    friction = default_friction
    if "friction" in f:
        friction = _read_friction(reader, f["friction"].path, f["friction"].value, default_friction)
    joint = None if parent is None else unit_type.joint  # the root has no joint
    axis: tuple[float, float, float] | None = None
    levels: tuple[float, ...] = ()
    locked: float | None = None
    if joint is not None:
        locked_source = f.get("locked_deg")
        needed = ("axis",) if locked_source is not None else ("axis", "levels_deg")
        for key in needed:
            if key not in f:
                raise _error(reader, raw, "unit", f"active unit '{raw.name}' needs '{key}'")
        axis = _read_axis(reader, f["axis"], raw)
        if "levels_deg" in f:
            levels = _read_levels(reader, f["levels_deg"], raw, joint)
        if locked_source is not None:  # a broken joint: fixed at this angle, no levels
            degrees = _read_level(reader, locked_source.path, locked_source.value, raw,
                                  joint, "locked angle")  # fmt: skip
            locked, levels = math.radians(degrees), ()
    else:
        for key in ("axis", "levels_deg", "locked_deg"):
            if key in f:
                why = "is the root" if parent is None else f"is passive ({type_name})"
                raise _error(reader, raw, key, f"'{key}' given but unit '{raw.name}' {why}")
    return PlacedUnit(
        name=raw.name,
        unit_type=unit_type,
        parent=parent,
        connector=connector,
        axis=axis,
        levels_rad=levels,
        friction=friction,
        line=reader.document.line(raw.path),
        locked_rad=locked,
    )


def _read_axis(reader: Reader, source: _Value, raw: _RawUnit) -> tuple[float, float, float]:
    if isinstance(source.value, str):
        if source.value not in AXES:
            raise _error(reader, raw, "axis", f"expected one of {', '.join(AXES)} or [x, y, z]")
        return AXES[source.value]
    x, y, z = reader.triple(source.path, source.value, AXIS_COMPONENT)
    norm = math.hypot(x, y, z)
    if norm < 1e-9:
        raise _error(reader, raw, "axis", "axis vector must not be zero")
    return (x / norm, y / norm, z / norm)


def _read_levels(
    reader: Reader, source: _Value, raw: _RawUnit, joint: JointSpec
) -> tuple[float, ...]:
    """A joint's levels (rad); bounds and count are checked before a range is expanded."""
    path, value = source.path, source.value
    if isinstance(value, dict):
        spec = reader.mapping(path, value, required=("min", "max", "step"))
        low = _read_level(reader, (*path, "min"), spec["min"], raw, joint)
        high = _read_level(reader, (*path, "max"), spec["max"], raw, joint)
        step = reader.number((*path, "step"), spec["step"], LEVEL_STEP_DEG)
        if high < low:
            raise reader.error((*path, "max"), f"max ({high:g}) is below min ({low:g}){raw.note}")
        spans = (high - low) / step
        if spans > MAX_LEVELS - 1 + 1e-9:
            raise reader.error(
                (*path, "step"),
                f"gives {spans + 1:.0f} levels; a joint has at most {MAX_LEVELS}{raw.note}",
            )
        count = round(spans)
        if abs(low + count * step - high) > 1e-9 * max(1.0, abs(high)):
            raise reader.error((*path, "step"), f"(max - min) is not a multiple of step{raw.note}")
        degrees = [low + k * step for k in range(count + 1)]
    else:
        items = reader.sequence(path, value, min_length=1)
        if len(items) > MAX_LEVELS:
            raise reader.error(
                path, f"{len(items)} levels; a joint has at most {MAX_LEVELS}{raw.note}"
            )
        degrees = [_read_level(reader, (*path, k), x, raw, joint) for k, x in enumerate(items)]
    if len(set(degrees)) != len(degrees):
        raise reader.error(path, f"levels must be distinct{raw.note}")
    return tuple(math.radians(d) for d in degrees)


def _read_level(
    reader: Reader,
    path: KeyPath,
    value: Any,
    raw: _RawUnit,
    joint: JointSpec,
    what: str = "level",
) -> float:
    """One angle (deg), a level or a locked angle, inside the joint's limits."""
    level = reader.number(path, value, ANGLE_DEG)
    lower, upper = math.degrees(joint.lower_rad), math.degrees(joint.upper_rad)
    if not lower - 1e-9 <= level <= upper + 1e-9:
        raise reader.error(
            path,
            f"{what} {level:g} deg is outside the joint limits [{lower:g}, {upper:g}] deg"
            f"{raw.note}",
        )
    return level


def _tree_order(
    reader: Reader, units: list[PlacedUnit], raws: dict[str, _RawUnit]
) -> list[PlacedUnit]:
    """Check the units form one tree; return them root first, parents before children."""
    by_name = {u.name: u for u in units}
    roots = [u for u in units if u.parent is None]
    if not roots:
        raise reader.error(("units",), "no root unit (every unit has a parent): a cycle")
    if len(roots) > 1:
        names = ", ".join(u.name for u in roots[:3]) + (", ..." if len(roots) > 3 else "")
        raise _error(reader, raws[roots[1].name], "name", f"more than one root unit: {names}")
    for unit in units:
        if unit.parent is None:
            continue
        raw = raws[unit.name]
        parent = by_name.get(unit.parent)
        if parent is None:
            raise _error(reader, raw, "parent", f"unknown parent unit '{unit.parent}'")
        if unit.connector not in parent.unit_type.connectors:
            known = ", ".join(parent.unit_type.connectors) or "none"
            raise _error(
                reader,
                raw,
                "connector",
                f"unit type '{parent.unit_type.name}' has no connector "
                f"'{unit.connector}' (has: {known})",
            )
    # Declaration order, except that a unit waits for its parent (a stable topological sort).
    ordered: list[PlacedUnit] = []
    placed: set[str] = set()
    pending = list(units)
    while pending:
        for unit in pending:
            if unit.parent is None or unit.parent in placed:
                ordered.append(unit)
                placed.add(unit.name)
        still_pending = [u for u in pending if u.name not in placed]
        if len(still_pending) == len(pending):
            break
        pending = still_pending
    if len(ordered) != len(units):
        reached = {u.name for u in ordered}
        stray = next(u for u in units if u.name not in reached)
        raise _error(
            reader,
            raws[stray.name],
            "parent",
            f"unit '{stray.name}' is in a cycle (never reaches the root)",
        )
    used: dict[tuple[str | None, str | None], str] = {}
    for unit in ordered[1:]:
        key = (unit.parent, unit.connector)
        if key in used:
            raise _error(
                reader,
                raws[unit.name],
                "connector",
                f"connector '{unit.connector}' of '{unit.parent}' is already used by '{used[key]}'",
            )
        used[key] = unit.name
    return ordered


def _resolve_legs(
    reader: Reader, specs: list[tuple[_RawUnit, _Template]], units: dict[str, PlacedUnit]
) -> tuple[list[Leg], list[Leg]]:
    """The leg instances: working ones, and broken ones (a joint locked)."""
    legs: list[Leg] = []
    broken: list[Leg] = []
    for instance, template in specs:
        assert template.leg is not None  # only templates with a leg make leg specs
        if "side" not in instance.fields:
            raise _error(reader, instance, "name", "a leg instance needs 'side' (left or right)")
        side: Side = reader.choice(
            instance.fields["side"].path, instance.fields["side"].value, ("left", "right")
        )
        joints: list[str] = []
        locked = False
        for role, source in zip(("swing", "lift"), template.leg, strict=True):
            unit = units[f"{instance.name}_{source.value}"]
            locked = locked or unit.locked_rad is not None
            if unit.locked_rad is None and (not unit.is_actuated or len(unit.levels_rad) != 2):
                raise reader.error(
                    source.path,
                    f"a leg's {role} unit needs a joint with exactly 2 levels{instance.note}",
                )
            assert unit.joint_name is not None  # a leg's unit has a parent, so a joint
            joints.append(unit.joint_name)
        leg_units = tuple(f"{instance.name}_{unit['name']}" for _, unit in template.units)
        leg = Leg(instance.name, side, joints[0], joints[1], leg_units)
        (broken if locked else legs).append(leg)
    return legs, broken
