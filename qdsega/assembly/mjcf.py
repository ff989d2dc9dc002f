"""MJCF, MuJoCo's XML model format, of an assembled formation.

It is read from the assembled URDF, the one home of the geometry: each link becomes a body
(the root with a free joint), each revolute joint a hinge with its range, each inertial,
collision and visual shape its MuJoCo counterpart; each unit's lateral friction becomes the
friction of its collision geoms (an anisotropic one is named in a comment: a MuJoCo geom
slides alike every way). Each actuated joint gets a position actuator, in formation order
(``ctrl`` takes a posture as :meth:`Formation.posture_rad` gives it). A floor and a ``rest``
keyframe (the rest posture just above the floor) make the file a scene that MuJoCo loads and
steps as it is. What differs from PyBullet, and why: docs/formations.md.
"""

from __future__ import annotations

import copy
import math
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import trimesh
from trimesh.transformations import quaternion_from_euler, rotation_matrix

from qdsega.assembly.assembler import AssembledRobot, number_text, vector_text
from qdsega.assembly.mass_properties import origin_transform, shape_mesh
from qdsega.description.formation import PlacedUnit
from qdsega.errors import FormationError

FULL_TORQUE_ERROR_RAD = math.radians(5.0)
"""A joint's position actuator gives the joint's whole torque limit at this position error
(rad): its gain is ``kp = effort / FULL_TORQUE_ERROR_RAD``."""
START_CLEARANCE_M = 0.002
"""Gap between the body's lowest point and the floor in the file's start poses (m)."""
MESH_SUFFIXES = (".stl", ".obj", ".msh")
"""The mesh files MuJoCo reads."""


def assemble_mjcf(robot: AssembledRobot) -> str:
    """The MJCF text of ``robot``, on a floor; its mesh files are the URDF's (``assets/``:
    write them with :func:`~qdsega.assembly.assembler.write_model`).

    Joints are damped by ``effort / velocity`` (N m s/rad): a motor at its torque limit then
    runs at the joint's speed limit, which MuJoCo's actuators have no setting for.

    Raises:
        FormationError: a unit's mesh is in a format MuJoCo does not read.
    """
    urdf = ET.fromstring(robot.urdf)
    links = {link.get("name", ""): link for link in urdf.findall("link")}
    joints_of: dict[str, list[ET.Element]] = {name: [] for name in links}
    for joint in urdf.findall("joint"):
        joints_of[_get(joint, "parent", "link")].append(joint)
    formation = robot.formation
    root = formation.root.name

    model = ET.Element("mujoco", model=formation.name)
    ET.SubElement(model, "compiler", angle="radian", autolimits="true", inertiafromgeom="false")
    ET.SubElement(model, "option", integrator="implicitfast")
    if robot.assets:
        _declare_meshes(robot, ET.SubElement(model, "asset"))
    world = ET.SubElement(model, "worldbody")
    ET.SubElement(world, "geom", name="floor", type="plane", size="0 0 1")
    zero = _start_height(robot, urdf, {})
    body = ET.SubElement(world, "body", name=root, pos=vector_text((0.0, 0.0, zero)))
    ET.SubElement(body, "freejoint", name="root")
    hinges: list[str] = []
    _fill_body(body, root, links, joints_of, formation.units_by_name, hinges)

    actuators = ET.SubElement(model, "actuator")
    for actuated in formation.joints:
        spec = actuated.spec
        ET.SubElement(
            actuators,
            "position",
            name=actuated.name,
            joint=actuated.name,
            kp=number_text(spec.effort_nm / FULL_TORQUE_ERROR_RAD),
            forcerange=vector_text((-spec.effort_nm, spec.effort_nm)),
            ctrlrange=vector_text((spec.lower_rad, spec.upper_rad)),
        )
    rest = dict(
        zip(
            (j.name for j in formation.joints),
            formation.posture_rad(formation.rest_levels()),
            strict=True,
        )
    )
    height = _start_height(robot, urdf, rest)
    qpos = (0.0, 0.0, height, 1.0, 0.0, 0.0, 0.0, *(rest[name] for name in hinges))
    keyframes = ET.SubElement(model, "keyframe")
    ET.SubElement(
        keyframes,
        "key",
        name="rest",
        qpos=vector_text(qpos),
        ctrl=vector_text(tuple(rest[j.name] for j in formation.joints)),
    )
    ET.indent(model, space="  ")
    return ET.tostring(model, encoding="unicode") + "\n"


def _fill_body(
    body: ET.Element,
    link_name: str,
    links: Mapping[str, ET.Element],
    joints_of: Mapping[str, list[ET.Element]],
    units: Mapping[str, PlacedUnit],
    hinges: list[str],
) -> None:
    """Give ``body`` the link's inertial and shapes, then nest its children's bodies; the
    names of hinges go to ``hinges`` in MuJoCo's order of ``qpos``."""
    link = links[link_name]
    inertial = link.find("inertial")
    assert inertial is not None  # every assembled link has one
    i = {k: _get(inertial, "inertia", k) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
    assert _get(inertial, "origin", "rpy") == "0 0 0"  # the tensor is in the link's axes
    ET.SubElement(
        body,
        "inertial",
        pos=_get(inertial, "origin", "xyz"),
        mass=_get(inertial, "mass", "value"),
        fullinertia=" ".join(i.values()),
    )
    friction = units[link_name].friction
    for visual in link.findall("visual"):
        color = visual.find("material/color")
        geom = _geom(body, visual, contype="0", conaffinity="0", group="2")
        if color is not None:
            geom.set("rgba", color.get("rgba", "0.5 0.5 0.5 1"))
    for collision in link.findall("collision"):
        _geom(body, collision, group="3", friction=number_text(friction.lateral), priority="1")
    if not friction.is_isotropic:
        body.append(
            ET.Comment(
                f" anisotropic friction x y z: {vector_text(friction.anisotropic)} (not carried: "
                "a MuJoCo geom slides alike every way) "
            )
        )
    for joint in joints_of[link_name]:
        child = _get(joint, "child", "link")
        origin = joint.find("origin")
        xyz = "0 0 0" if origin is None else origin.get("xyz", "0 0 0")
        rpy = "0 0 0" if origin is None else origin.get("rpy", "0 0 0")
        child_body = ET.SubElement(body, "body", name=child, pos=xyz, quat=_quat(rpy))
        if joint.get("type") == "revolute":
            lower, upper = (float(_get(joint, "limit", k)) for k in ("lower", "upper"))
            effort, speed = (float(_get(joint, "limit", k)) for k in ("effort", "velocity"))
            ET.SubElement(
                child_body,
                "joint",
                name=joint.get("name", ""),
                type="hinge",
                axis=_get(joint, "axis", "xyz"),
                range=vector_text((lower, upper)),
                damping=number_text(effort / speed),
            )
            hinges.append(joint.get("name", ""))
        _fill_body(child_body, child, links, joints_of, units, hinges)


def _geom(body: ET.Element, shape: ET.Element, **attributes: str) -> ET.Element:
    """A geom for a URDF ``<visual>`` or ``<collision>``; a mesh is named by its file."""
    origin = shape.find("origin")
    xyz = "0 0 0" if origin is None else origin.get("xyz", "0 0 0")
    rpy = "0 0 0" if origin is None else origin.get("rpy", "0 0 0")
    geometry = shape.find("geometry")
    assert geometry is not None and len(geometry)  # checked when the unit type was loaded
    kind = geometry[0]
    if kind.tag == "box":
        size = vector_text(tuple(float(x) / 2 for x in kind.get("size", "").split()))
        geom = ET.SubElement(body, "geom", type="box", size=size)
    elif kind.tag == "cylinder":
        radius, length = float(kind.get("radius", "0")), float(kind.get("length", "0"))
        geom = ET.SubElement(body, "geom", type="cylinder", size=vector_text((radius, length / 2)))
    elif kind.tag == "sphere":
        geom = ET.SubElement(body, "geom", type="sphere", size=kind.get("radius", "0"))
    else:
        geom = ET.SubElement(body, "geom", type="mesh", mesh=kind.get("filename", ""))
    geom.set("pos", xyz)
    geom.set("quat", _quat(rpy))
    for key, value in attributes.items():
        geom.set(key, value)
    return geom


def _declare_meshes(robot: AssembledRobot, asset: ET.Element) -> None:
    """Declare each mesh file once, named by its path."""
    for relative in sorted(robot.assets):
        if Path(relative).suffix.lower() not in MESH_SUFFIXES:
            raise FormationError(
                f"MJCF: MuJoCo reads {', '.join(MESH_SUFFIXES)} meshes, not {relative}",
                file=robot.formation.file,
            )
        ET.SubElement(asset, "mesh", name=relative, file=relative)


def _start_height(
    robot: AssembledRobot, urdf: ET.Element, angles_rad: Mapping[str, float]
) -> float:
    """Height of the root link's frame (m) that sets the body, with its joints at
    ``angles_rad`` (0 where not given), :data:`START_CLEARANCE_M` above the floor."""
    frames = {robot.formation.root.name: np.eye(4)}
    for joint in urdf.findall("joint"):  # parents before children
        frame = frames[_get(joint, "parent", "link")] @ origin_transform(joint.find("origin"))
        if joint.get("type") == "revolute":
            axis = [float(x) for x in _get(joint, "axis", "xyz").split()]
            frame = frame @ rotation_matrix(angles_rad.get(joint.get("name", ""), 0.0), axis)
        frames[_get(joint, "child", "link")] = frame
    lowest = math.inf
    for link in urdf.findall("link"):
        frame = frames[link.get("name", "")]
        for collision in link.findall("collision"):
            vertices = _collision_mesh(collision, robot.assets).vertices
            lowest = min(lowest, float((vertices @ frame[2, :3] + frame[2, 3]).min()))
    return START_CLEARANCE_M - lowest


def _collision_mesh(collision: ET.Element, assets: Mapping[str, Path]) -> trimesh.Trimesh:
    """The collision shape's mesh in its link's frame; meshes are read from their sources."""
    shape = copy.deepcopy(collision)
    for mesh in shape.iter("mesh"):
        mesh.set("filename", str(assets[mesh.get("filename", "")]))
    return shape_mesh(shape, Path("/"))


def _quat(rpy: str) -> str:
    """URDF roll, pitch, yaw (fixed axes x, y, z) as MuJoCo's quaternion (w, x, y, z)."""
    roll, pitch, yaw = (float(a) for a in rpy.split())
    return vector_text(tuple(quaternion_from_euler(roll, pitch, yaw, axes="sxyz")))


def _get(element: ET.Element, path: str, key: str) -> str:
    """Attribute ``key`` of ``element``'s sub-element at ``path``, which the assembler wrote."""
    found = element.find(path)
    assert found is not None and key in found.attrib, f"assembled URDF: no {path}@{key}"
    return found.attrib[key]
