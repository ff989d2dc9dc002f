"""Checks on an assembled URDF that yourdfpy's ``validate()`` does not make.

They look at the URDF text itself, so they also catch what a unit template brings in.
"""

from __future__ import annotations

import io
import math
import xml.etree.ElementTree as ET
from collections.abc import Callable

import numpy as np
import yourdfpy

from qdsega.description.formation import Formation
from qdsega.errors import FormationError

_INERTIA_TOLERANCE = 1e-12
"""Absolute slack (kg m^2) for the triangle inequality of principal moments."""

Fail = Callable[[str], FormationError]


def check_urdf(urdf: str, formation: Formation) -> None:
    """Raise :class:`FormationError` if ``urdf`` is not a sound kinematic tree.

    Checks: unique link and joint names (one namespace), exactly one root link, every joint's
    parent and child exist, no link has two parents, no cycles, positive masses, physically
    valid inertia tensors (symmetric positive definite, principal moments obeying the triangle
    inequality), ordered joint limits, each formation level inside its joint's limits; then
    the text must load in yourdfpy.
    """

    def fail(message: str) -> FormationError:
        return FormationError(f"assembled URDF: {message}", file=formation.file)

    robot = ET.fromstring(urdf)
    links = {link.get("name"): link for link in robot.findall("link")}
    joints = robot.findall("joint")
    names = [link.get("name") for link in robot.findall("link")] + [j.get("name") for j in joints]
    duplicates = sorted({n for n in names if names.count(n) > 1}, key=str)
    if duplicates:
        raise fail(f"duplicate link/joint name '{duplicates[0]}'")
    parent_of: dict[str, str] = {}
    for joint in joints:
        owner = f"joint '{joint.get('name')}'"
        parent = _attribute(_child(joint, "parent", owner, fail), "link", owner, fail)
        child = _attribute(_child(joint, "child", owner, fail), "link", owner, fail)
        for role, end in (("parent", parent), ("child", child)):
            if end not in links:
                raise fail(f"joint '{joint.get('name')}' has unknown {role} link '{end}'")
        if child in parent_of:
            raise fail(f"link '{child}' has two parent joints")
        parent_of[child] = parent
    roots = [name for name in links if name not in parent_of]
    if len(roots) != 1:
        raise fail(f"expected exactly one root link, found {len(roots)}: {roots}")
    for name in links:
        seen = {name}
        while name in parent_of:
            name = parent_of[name]
            if name in seen:
                raise fail(f"cycle through link '{name}'")
            seen.add(name)
    for name, link in links.items():
        _check_inertial(link, name, fail)
    for joint in joints:
        _check_limits(joint, fail)
    by_joint = {j.get("name"): j for j in joints}
    for actuated in formation.joints:
        limit = _child(by_joint[actuated.name], "limit", f"joint '{actuated.name}'", fail)
        lower, upper = float(limit.get("lower", "0")), float(limit.get("upper", "0"))
        for level in actuated.levels_rad:
            if not lower - 1e-9 <= level <= upper + 1e-9:
                raise fail(
                    f"joint '{actuated.name}': level {math.degrees(level):g} deg outside limits"
                )
    try:
        model = yourdfpy.URDF.load(
            io.StringIO(urdf),
            load_meshes=False,
            build_scene_graph=False,
            build_collision_scene_graph=False,
        )
    except Exception as exc:  # yourdfpy raises many kinds; report any of them as bad input
        raise fail(f"yourdfpy cannot load it: {exc}") from None
    if not model.validate():
        raise fail("yourdfpy validation failed")


def _child(element: ET.Element, tag: str, owner: str, fail: Fail) -> ET.Element:
    """``element``'s first ``<tag>``; a failure naming ``owner`` where it has none."""
    found = element.find(tag)
    if found is None:
        raise fail(f"{owner} has no <{tag}>")
    return found


def _attribute(element: ET.Element, key: str, owner: str, fail: Fail) -> str:
    """``element``'s attribute ``key``; a failure naming ``owner`` where it is missing."""
    value = element.get(key)
    if value is None:
        raise fail(f"{owner}: <{element.tag}> has no '{key}'")
    return value


def _check_inertial(link: ET.Element, name: str | None, fail: Fail) -> None:
    owner = f"link '{name}'"
    inertial = _child(link, "inertial", owner, fail)
    mass = float(_attribute(_child(inertial, "mass", owner, fail), "value", owner, fail))
    if not mass > 0:
        raise fail(f"link '{name}' mass must be positive, got {mass}")
    inertia = _child(inertial, "inertia", owner, fail)
    ixx, ixy, ixz, iyy, iyz, izz = (
        float(_attribute(inertia, k, owner, fail))
        for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    )
    tensor = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    moments = np.linalg.eigvalsh(tensor)
    if not np.all(moments > 0):
        raise fail(f"link '{name}' inertia is not positive definite (moments {moments})")
    a, b, c = moments
    if a + b < c - _INERTIA_TOLERANCE:
        raise fail(f"link '{name}' inertia violates the triangle inequality (moments {moments})")


def _check_limits(joint: ET.Element, fail: Fail) -> None:
    if joint.get("type") not in ("revolute", "prismatic"):
        return
    limit = joint.find("limit")
    if limit is None:
        raise fail(f"joint '{joint.get('name')}' has no <limit>")
    lower, upper = float(limit.get("lower", "0")), float(limit.get("upper", "0"))
    if not lower < upper:
        raise fail(f"joint '{joint.get('name')}' limits not ordered ({lower} >= {upper})")
    for key in ("effort", "velocity"):
        if not float(limit.get(key, "0")) > 0:
            raise fail(f"joint '{joint.get('name')}' {key} limit must be positive")
