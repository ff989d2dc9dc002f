"""The assembler: a :class:`Formation` becomes one self-contained URDF text.

Same formation, byte-identical URDF: numbers are printed with a fixed format and elements in
formation order. Each link carries its lateral friction in PyBullet's ``<contact>`` extension;
anisotropic friction has no URDF element PyBullet reads, so the file names it in a comment and
:mod:`qdsega.simulation.bullet` sets it when it loads the body.
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
from qdsega.description.formation import Formation, Friction, PlacedUnit
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
    """Write the URDF to ``out`` and its assets next to it; all or nothing."""
    write_model(robot.urdf, robot.assets, out)


def write_model(text: str, assets: dict[str, Path], out: Path) -> None:
    """Write a model file's ``text`` to ``out`` and the ``assets`` it names (relative path ->
    source file) next to it; all or nothing.

    Files are first written into a temporary folder beside ``out`` and then moved into place.
    """
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    try:
        for relative, source in sorted(assets.items()):
            target = staging / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(source, target)
        (staging / out.name).write_text(text, encoding="utf-8")
        for relative in sorted(assets):
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
    link.insert(1, _contact(unit.friction))
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
    ET.SubElement(inertial, "origin", xyz=vector_text(props.center_of_mass_m), rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=number_text(props.mass_kg))
    i = props.inertia_kg_m2
    ET.SubElement(
        inertial,
        "inertia",
        ixx=number_text(i[0, 0]),
        ixy=number_text(i[0, 1]),
        ixz=number_text(i[0, 2]),
        iyy=number_text(i[1, 1]),
        iyz=number_text(i[1, 2]),
        izz=number_text(i[2, 2]),
    )
    return inertial


def _contact(friction: Friction) -> ET.Element:
    """PyBullet's URDF ``<contact>``: the lateral friction, and a comment naming an anisotropic
    friction that PyBullet's URDF reader has no element for."""
    contact = ET.Element("contact")
    ET.SubElement(contact, "lateral_friction", value=number_text(friction.lateral))
    if not friction.is_isotropic:
        contact.append(
            ET.Comment(
                f" anisotropic friction x y z: {vector_text(friction.anisotropic)} (no URDF "
                "element PyBullet reads carries it; qdsega sets it with changeDynamics) "
            )
        )
    return contact


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
    ET.SubElement(joint, "origin", xyz=vector_text(connector.xyz_m), rpy=vector_text(rpy))
    if unit.is_actuated:
        spec = unit.unit_type.joint
        assert spec is not None and unit.axis is not None
        ET.SubElement(joint, "axis", xyz=vector_text(unit.axis))
        ET.SubElement(
            joint,
            "limit",
            lower=number_text(spec.lower_rad),
            upper=number_text(spec.upper_rad),
            effort=number_text(spec.effort_nm),
            velocity=number_text(spec.velocity_rad_s),
        )
    return joint


def number_text(x: float) -> str:
    """``x`` as a model file prints it: 9 significant digits, never ``-0``."""
    text = f"{float(x):.9g}"
    return "0" if text == "-0" else text


def vector_text(values: tuple[float, ...] | np.ndarray) -> str:
    """Numbers as a model file prints them, separated by spaces."""
    return " ".join(number_text(v) for v in values)
