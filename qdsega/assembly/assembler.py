"""The assembler: a :class:`Formation` becomes one self-contained URDF text.

Same formation, byte-identical URDF: numbers are printed with a fixed format and elements in
formation order.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from trimesh.transformations import euler_from_matrix, euler_matrix, rotation_matrix

from qdsega.assembly.mass_properties import MassProperties, link_mass_properties
from qdsega.assembly.urdf_checks import check_urdf
from qdsega.description.formation import Formation, PlacedUnit
from qdsega.description.unit_type import LINK_PLACEHOLDER, Connector
from qdsega.errors import FormationError

ASSET_FOLDER = "assets"
"""Meshes are copied next to the URDF into this folder, one subfolder per unit type."""


@dataclass(frozen=True)
class AssembledRobot:
    """An assembled formation.

    Attributes:
        formation: what was assembled.
        urdf: the URDF text; mesh filenames are relative to the URDF's folder.
        assets: files the URDF references: relative path -> source file.
        mass_kg: total mass (kg).
    """

    formation: Formation
    urdf: str
    assets: dict[str, Path]
    mass_kg: float


def assemble(formation: Formation) -> AssembledRobot:
    """Build and check the URDF of ``formation``; nothing is written.

    Raises:
        FormationError: the unit templates or the resulting URDF fail a check.
    """
    robot = ET.Element("robot", name=formation.name)
    assets: dict[str, Path] = {}
    total_mass = 0.0
    properties: dict[str, MassProperties] = {}
    for unit in formation.units:
        link, link_assets = _link(unit, properties)
        robot.append(link)
        assets.update(link_assets)
        total_mass += properties[unit.unit_type.name].mass_kg
    by_name = formation.units_by_name
    for unit in formation.units[1:]:
        assert unit.parent is not None and unit.connector is not None  # every unit but the root
        robot.append(_joint(unit, by_name[unit.parent].unit_type.connectors[unit.connector]))
    ET.indent(robot, space="  ")
    urdf = '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"
    check_urdf(urdf, formation)
    return AssembledRobot(formation=formation, urdf=urdf, assets=assets, mass_kg=total_mass)


def write_assembly(robot: AssembledRobot, out: Path) -> None:
    """Write the URDF to ``out`` and its assets next to it; all or nothing.

    Files are first written into a temporary folder beside ``out`` and then moved into place.
    """
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    try:
        for relative, source in sorted(robot.assets.items()):
            target = staging / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(source, target)
        (staging / out.name).write_text(robot.urdf, encoding="utf-8")
        for relative in sorted(robot.assets):
            final = out.parent / relative
            final.parent.mkdir(parents=True, exist_ok=True)
            os.replace(staging / relative, final)
        os.replace(staging / out.name, out)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _link(
    unit: PlacedUnit, properties: dict[str, MassProperties]
) -> tuple[ET.Element, dict[str, Path]]:
    unit_type = unit.unit_type
    text = unit_type.link_template.replace(LINK_PLACEHOLDER, unit.name)
    link = ET.fromstring(text).find("link")
    assert link is not None  # checked when the unit type was loaded
    if unit_type.name not in properties:
        try:
            properties[unit_type.name] = link_mass_properties(
                link, unit_type.mass_kg, folder=unit_type.folder
            )
        except FormationError as exc:
            raise FormationError(exc.message, file=unit_type.template_file) from None
    link.insert(0, _inertial(properties[unit_type.name]))
    assets = {}
    for mesh in link.iter("mesh"):
        source = (unit_type.folder / mesh.get("filename", "")).resolve()
        relative = source.relative_to(unit_type.folder.resolve()).as_posix()
        target = f"{ASSET_FOLDER}/{unit_type.name}/{relative}"
        mesh.set("filename", target)
        assets[target] = source
    return link, assets


def _inertial(props: MassProperties) -> ET.Element:
    inertial = ET.Element("inertial")
    ET.SubElement(inertial, "origin", xyz=_vector(props.center_of_mass_m), rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=_number(props.mass_kg))
    i = props.inertia_kg_m2
    ET.SubElement(
        inertial,
        "inertia",
        ixx=_number(i[0, 0]),
        ixy=_number(i[0, 1]),
        ixz=_number(i[0, 2]),
        iyy=_number(i[1, 1]),
        iyz=_number(i[1, 2]),
        izz=_number(i[2, 2]),
    )
    return inertial


def _joint(unit: PlacedUnit, connector: Connector) -> ET.Element:
    """The joint that attaches ``unit`` at its parent's ``connector``; a locked joint is a
    fixed one whose frame is turned by the locked angle about the joint's axis."""
    assert unit.parent is not None and unit.joint_name is not None
    kind = "revolute" if unit.is_actuated else "fixed"
    joint = ET.Element("joint", name=unit.joint_name, type=kind)
    ET.SubElement(joint, "parent", link=unit.parent)
    ET.SubElement(joint, "child", link=unit.name)
    rpy = connector.rpy_rad
    if unit.locked_rad is not None:
        assert unit.axis is not None
        turned = euler_matrix(*rpy, axes="sxyz") @ rotation_matrix(unit.locked_rad, unit.axis)
        rpy = euler_from_matrix(turned, axes="sxyz")
    ET.SubElement(joint, "origin", xyz=_vector(connector.xyz_m), rpy=_vector(rpy))
    if unit.is_actuated:
        spec = unit.unit_type.joint
        assert spec is not None and unit.axis is not None
        ET.SubElement(joint, "axis", xyz=_vector(unit.axis))
        ET.SubElement(
            joint,
            "limit",
            lower=_number(spec.lower_rad),
            upper=_number(spec.upper_rad),
            effort=_number(spec.effort_nm),
            velocity=_number(spec.velocity_rad_s),
        )
    return joint


def _number(x: float) -> str:
    text = f"{float(x):.9g}"
    return "0" if text == "-0" else text


def _vector(values: tuple[float, ...] | np.ndarray) -> str:
    return " ".join(_number(v) for v in values)
