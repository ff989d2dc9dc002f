"""Unit types: one folder per unit under ``units/``, a ``unit.yaml`` and a URDF link template.

A unit is one rigid body. An *active* unit also owns one revolute joint, the joint that attaches
it to its parent in a formation; a *passive* unit (no ``joint`` section) attaches rigidly.
The unit frame's origin is the attachment point; the body trails along the unit's -x axis.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from qdsega.description.limits import (
    ANGLE_DEG,
    EFFORT_NM,
    JOINT_LIMIT_DEG,
    MASS_KG,
    POSITION_M,
    SPEED_RAD_S,
)
from qdsega.errors import FormationError
from qdsega.yaml_reader import Reader, load_yaml

LINK_PLACEHOLDER = "${link}"
"""Written in a link template wherever the link's (unique) name goes."""


@dataclass(frozen=True)
class Connector:
    """Where a child unit attaches: a frame in the unit's frame.

    Attributes:
        name: connector name, unique in its unit.
        xyz_m: position (m), shape (3,).
        rpy_rad: orientation as roll, pitch, yaw (rad), shape (3,).
    """

    name: str
    xyz_m: tuple[float, float, float]
    rpy_rad: tuple[float, float, float]


@dataclass(frozen=True)
class JointSpec:
    """The active joint's actuator: limits of a servo motor.

    Attributes:
        lower_rad: lower position limit (rad).
        upper_rad: upper position limit (rad).
        effort_nm: maximum torque (N m).
        velocity_rad_s: maximum angular speed (rad/s).
    """

    lower_rad: float
    upper_rad: float
    effort_nm: float
    velocity_rad_s: float


@dataclass(frozen=True)
class UnitType:
    """A unit type read from ``units/<name>/unit.yaml``.

    Attributes:
        name: unit type name (its folder's name).
        folder: the unit's folder.
        description: one line for humans.
        mass_kg: total mass (kg); inertia follows from the collision geometry.
        link_template: URDF text of one ``<link>`` (inside ``<robot>``), with ``${link}``.
        template_file: where ``link_template`` came from.
        joint: the active joint's actuator, or None for a passive unit.
        connectors: attachment frames by name.
    """

    name: str
    folder: Path
    description: str
    mass_kg: float
    link_template: str
    template_file: Path
    joint: JointSpec | None
    connectors: dict[str, Connector]

    @property
    def is_active(self) -> bool:
        return self.joint is not None


def find_unit_type(units_dirs: Sequence[Path], name: str) -> Path:
    """The first folder of ``units_dirs`` that defines unit type ``name`` (holds
    ``name/unit.yaml``). Two folders may define it only alike (a copy of a shipped type, file
    for file).

    Raises:
        FormationError: no folder defines it, or two define it differently (the message names
            both files).
    """
    if Path(name).name != name or name in (".", ".."):
        raise FormationError(f"a unit type is a folder name in {units_dirs[0]}, got '{name}'")
    folders = list(dict.fromkeys(folder.resolve() for folder in units_dirs))
    found = [folder for folder in folders if (folder / name / "unit.yaml").is_file()]
    if len(found) > 1 and _contents(found[0] / name) != _contents(found[1] / name):
        first, second = (folder / name / "unit.yaml" for folder in found[:2])
        raise FormationError(f"unit type '{name}' is defined twice: {first} and {second}")
    if not found:
        where = " or ".join(str(folder / name / "unit.yaml") for folder in folders)
        raise FormationError(f"unknown unit type '{name}' (no {where})")
    return found[0]


def _contents(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` by its relative path (a unit folder holds a few)."""
    files = (f for f in folder.rglob("*") if f.is_file() and "__pycache__" not in f.parts)
    return {f.relative_to(folder).as_posix(): f.read_bytes() for f in files}


def load_unit_type(units_dir: Path, name: str) -> UnitType:
    """Read unit type ``name`` from ``units_dir/name/unit.yaml``.

    Raises:
        FormationError: missing folder, bad ``unit.yaml`` or bad link template.
    """
    folder = units_dir / name
    file = folder / "unit.yaml"
    if Path(name).name != name or name in (".", ".."):
        raise FormationError(f"a unit type is a folder name in {units_dir}, got '{name}'")
    if not file.is_file():
        raise FormationError(f"unknown unit type '{name}' (no {file})")
    reader = Reader(load_yaml(file))
    raw = reader.mapping(
        (),
        reader.document.data,
        required=("mass_kg", "link_template", "connectors"),
        optional=("description", "joint"),
    )
    description = reader.text(("description",), raw.get("description", name))
    mass_kg = reader.number(("mass_kg",), raw["mass_kg"], MASS_KG)
    joint = None if "joint" not in raw else _read_joint(reader, raw["joint"])
    connectors_raw = reader.mapping(("connectors",), raw["connectors"], optional=raw["connectors"])
    connectors = {}
    for key, value in connectors_raw.items():
        path = ("connectors", key)
        entry = reader.mapping(path, value, required=("xyz_m",), optional=("rpy_deg",))
        xyz = reader.triple((*path, "xyz_m"), entry["xyz_m"], POSITION_M)
        roll, pitch, yaw = reader.triple(
            (*path, "rpy_deg"), entry.get("rpy_deg", [0, 0, 0]), ANGLE_DEG
        )
        connectors[key] = Connector(
            key, xyz, (math.radians(roll), math.radians(pitch), math.radians(yaw))
        )
    template_name = reader.text(("link_template",), raw["link_template"])
    template_file = folder / template_name
    if not template_file.resolve().is_relative_to(folder.resolve()):
        raise reader.error(("link_template",), f"must be a file in the unit's folder {folder}")
    if not template_file.is_file():
        raise reader.error(("link_template",), f"template file not found: {template_file}")
    template = template_file.read_text(encoding="utf-8")
    _check_template(template, template_file, project_root=units_dir.resolve().parent)
    return UnitType(
        name=name,
        folder=folder,
        description=description,
        mass_kg=mass_kg,
        link_template=template,
        template_file=template_file,
        joint=joint,
        connectors=connectors,
    )


def _read_joint(reader: Reader, value: object) -> JointSpec:
    path = ("joint",)
    raw = reader.mapping(
        path, value, required=("lower_deg", "upper_deg", "effort_nm", "velocity_rad_s")
    )
    lower = reader.number((*path, "lower_deg"), raw["lower_deg"], JOINT_LIMIT_DEG)
    upper = reader.number((*path, "upper_deg"), raw["upper_deg"], JOINT_LIMIT_DEG)
    if not lower < upper:
        raise reader.error((*path, "upper_deg"), f"must exceed lower_deg ({lower}), got {upper}")
    return JointSpec(
        lower_rad=math.radians(lower),
        upper_rad=math.radians(upper),
        effort_nm=reader.number((*path, "effort_nm"), raw["effort_nm"], EFFORT_NM),
        velocity_rad_s=reader.number((*path, "velocity_rad_s"), raw["velocity_rad_s"], SPEED_RAD_S),
    )


def mesh_files(template: str, folder: Path) -> list[Path]:
    """Mesh files a link template references, resolved against the unit's folder."""
    root = ET.fromstring(template.replace(LINK_PLACEHOLDER, "placeholder"))
    return [(folder / mesh.get("filename", "")).resolve() for mesh in root.iter("mesh")]


def _check_template(template: str, file: Path, *, project_root: Path) -> None:
    try:
        root = ET.fromstring(template.replace(LINK_PLACEHOLDER, "placeholder"))
    except ET.ParseError as exc:
        raise FormationError(f"link template is not valid XML: {exc}", file=file) from None
    links = root.findall("link")
    if root.tag != "robot" or len(links) != 1 or len(root) != 1:
        raise FormationError("link template must be <robot> holding exactly one <link>", file=file)
    if LINK_PLACEHOLDER not in template:
        raise FormationError(f"link template must name its link {LINK_PLACEHOLDER}", file=file)
    if links[0].find("collision") is None:
        raise FormationError("link template needs a <collision> geometry", file=file)
    if links[0].find("inertial") is not None:
        raise FormationError("link template must not set <inertial>: it is computed", file=file)
    for mesh in mesh_files(template, file.parent):
        if not mesh.is_relative_to(project_root):
            raise FormationError(f"mesh path escapes the project folder {project_root}", file=file)
        if not mesh.is_file():
            raise FormationError(f"mesh file not found: {mesh}", file=file)
