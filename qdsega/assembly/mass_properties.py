"""Mass properties of a link, computed from its collision geometry with trimesh."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import cast

import numpy as np
import trimesh

from qdsega.description.limits import POSITION_M, ROTATION_RAD, SIZE_M
from qdsega.errors import FormationError
from qdsega.yaml_reader import Interval


@dataclass(frozen=True)
class MassProperties:
    """Rigid-body inertia of a link.

    Attributes:
        mass_kg: mass (kg).
        center_of_mass_m: centre of mass in the link frame (m), shape (3,).
        inertia_kg_m2: inertia tensor about the centre of mass, link-frame axes (kg m^2),
            shape (3, 3).
    """

    mass_kg: float
    center_of_mass_m: np.ndarray
    inertia_kg_m2: np.ndarray


def link_mass_properties(link: ET.Element, mass_kg: float, *, folder: Path) -> MassProperties:
    """Mass properties of ``link`` (a URDF ``<link>``) of uniform density and total ``mass_kg``.

    Every ``<collision>`` shape (box, cylinder, sphere, or a closed mesh relative to ``folder``)
    contributes its volume; shapes must not overlap.
    """
    meshes = [shape_mesh(c, folder) for c in link.findall("collision")]
    # concatenate is annotated as returning any Geometry; of Trimesh meshes it makes a Trimesh
    combined = cast(trimesh.Trimesh, trimesh.util.concatenate(meshes))
    volume = float(combined.volume)
    if not volume > 0.0:
        raise FormationError(f"link {link.get('name')}: collision volume must be positive")
    combined.density = mass_kg / volume
    return MassProperties(
        mass_kg=float(combined.mass),
        center_of_mass_m=np.asarray(combined.center_mass, dtype=float),
        inertia_kg_m2=np.asarray(combined.moment_inertia, dtype=float),
    )


def shape_mesh(element: ET.Element, folder: Path) -> trimesh.Trimesh:
    """The mesh of a URDF ``<collision>`` or ``<visual>`` in its link's frame: its
    ``<geometry>`` (box, cylinder, sphere, or a closed mesh relative to ``folder``) placed by
    its ``<origin>``."""
    transform = origin_transform(element.find("origin"))
    geometry = element.find("geometry")
    shape = None if geometry is None or len(geometry) == 0 else geometry[0]
    if shape is None:
        raise FormationError(f"a <{element.tag}> needs a <geometry>")
    if shape.tag == "box":
        extents = _floats(shape.get("size"), 3, "box size", SIZE_M)
        return trimesh.creation.box(extents=extents, transform=transform)
    if shape.tag == "cylinder":
        radius = _floats(shape.get("radius"), 1, "cylinder radius", SIZE_M)[0]
        length = _floats(shape.get("length"), 1, "cylinder length", SIZE_M)[0]
        return trimesh.creation.cylinder(radius=radius, height=length, transform=transform)
    if shape.tag == "sphere":
        radius = _floats(shape.get("radius"), 1, "sphere radius", SIZE_M)[0]
        return trimesh.creation.icosphere(subdivisions=4, radius=radius).apply_transform(transform)
    if shape.tag == "mesh":
        mesh = trimesh.load_mesh(folder / shape.get("filename", ""), force="mesh")
        if not mesh.is_watertight:
            raise FormationError(f"{element.tag} mesh {shape.get('filename')} is not closed")
        return mesh.apply_transform(transform)
    raise FormationError(f"unsupported {element.tag} geometry <{shape.tag}>")


def origin_transform(origin: ET.Element | None) -> np.ndarray:
    """The 4x4 transform of a URDF ``<origin>`` (``xyz``, fixed-axis ``rpy``); identity if
    there is none."""
    if origin is None:
        return np.eye(4)
    xyz = _floats(origin.get("xyz", "0 0 0"), 3, "origin xyz", POSITION_M)
    roll, pitch, yaw = _floats(origin.get("rpy", "0 0 0"), 3, "origin rpy", ROTATION_RAD)
    transform = trimesh.transformations.euler_matrix(roll, pitch, yaw, axes="sxyz")
    transform[:3, 3] = xyz
    return transform


def _floats(text: str | None, count: int, what: str, within: Interval) -> list[float]:
    """``count`` numbers from a URDF attribute, each in ``within`` (so never NaN)."""
    try:
        values = [float(x) for x in (text or "").split()]
    except ValueError:
        values = []
    if len(values) != count:
        raise FormationError(f"{what} needs {count} number(s), got {text!r}")
    if not all(v in within for v in values):
        raise FormationError(f"{what} must be in {within}, got {text!r}")
    return values
