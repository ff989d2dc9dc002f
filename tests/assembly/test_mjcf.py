"""The MJCF of an assembled formation: MuJoCo loads it, steps it, and the body stands."""

import dataclasses
import math

import numpy as np
import pytest
import trimesh
from helpers import run_cli

from qdsega.assembly import assemble
from qdsega.assembly.assembler import write_model
from qdsega.assembly.mjcf import FULL_TORQUE_ERROR_RAD, assemble_mjcf
from qdsega.description import Friction, load_formation
from qdsega.errors import FormationError

mujoco = pytest.importorskip("mujoco")


def _model(name: str, *, varied_friction: bool = False):
    """The formation and its MJCF model, each unit's friction made different if asked."""
    formation = load_formation(f"assemblies/{name}.yaml")
    if varied_friction:
        units = tuple(
            dataclasses.replace(u, friction=Friction(0.5 + 0.05 * i, u.friction.anisotropic))
            for i, u in enumerate(formation.units)
        )
        formation = dataclasses.replace(formation, units=units)
    return formation, mujoco.MjModel.from_xml_string(assemble_mjcf(assemble(formation)))


def _names(model, kind, count: int) -> list[str]:
    return [mujoco.mj_id2name(model, kind, i) for i in range(count)]


@pytest.mark.parametrize("name", ["quadruped", "snake5", "legged12_locked_leg"])
def test_mujoco_loads_the_joints_actuators_and_friction(name):
    formation, model = _model(name, varied_friction=True)
    joints = [j.name for j in formation.joints]
    assert model.nbody == 1 + len(formation.units)  # the world, then a body a unit
    assert model.njnt == 1 + len(joints)  # the free joint, then the hinges
    assert model.nu == len(joints)
    assert _names(model, mujoco.mjtObj.mjOBJ_ACTUATOR, model.nu) == joints  # formation order
    for i, joint in enumerate(formation.joints):
        hinge = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint.name)
        np.testing.assert_allclose(
            model.jnt_range[hinge], [joint.spec.lower_rad, joint.spec.upper_rad]
        )
        np.testing.assert_allclose(
            model.actuator_forcerange[i], [-joint.spec.effort_nm, joint.spec.effort_nm]
        )
        assert model.actuator_gainprm[i, 0] == pytest.approx(
            joint.spec.effort_nm / FULL_TORQUE_ERROR_RAD
        )
    assert model.body_mass[1:].sum() == pytest.approx(assemble(formation).mass_kg)
    colliding = np.flatnonzero(model.geom_contype)
    floor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "floor")
    for geom in colliding[colliding != floor]:
        body = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.geom_bodyid[geom])
        unit = formation.units_by_name[body]
        assert model.geom_friction[geom, 0] == pytest.approx(unit.friction.lateral)


@pytest.mark.parametrize("name", ["quadruped", "snake5"])
def test_the_body_rests_on_the_floor_for_a_second_from_its_rest_keyframe(name):
    formation, model = _model(name)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    np.testing.assert_allclose(data.ctrl, formation.posture_rad(formation.rest_levels()))
    start = data.qpos[:3].copy()
    while data.time < 1.0:
        mujoco.mj_step(model, data)
    assert np.all(np.isfinite(data.qpos))
    assert np.abs(data.qvel).max() < 0.05  # at rest, not shaking or blown apart
    assert np.linalg.norm(data.qpos[:2] - start[:2]) < 0.01
    half_height = 0.025  # of the root unit: the body stands on its legs, the snake lies
    assert data.qpos[2] > (0.07 if formation.legs else half_height - 0.002)
    for i, joint in enumerate(formation.joints):
        address = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint.name)]
        assert data.qpos[address] == pytest.approx(data.ctrl[i], abs=math.radians(3))


def test_a_mesh_unit_is_a_mesh_geom_and_a_format_mujoco_cannot_read_is_refused(project, tmp_path):
    folder = project / "units" / "my_servo"  # a unit type of the user's own
    (project / "units" / "servo").rename(folder)
    (folder / "meshes").mkdir()
    box = trimesh.creation.box(extents=(0.1, 0.05, 0.05))
    box.export(folder / "meshes" / "shell.stl")
    template = folder / "link.urdf"
    template.write_text(
        template.read_text().replace(
            '<box size="0.1 0.05 0.05"/>', '<mesh filename="meshes/shell.stl"/>'
        )
    )
    formation_file = project / "assemblies" / "pair.yaml"
    formation_file.write_text(
        "name: pair\nlight: {distance_m: 3}\nunits_dir: ../units\nunits:\n"
        "  - {name: a, unit: my_servo}\n"
        "  - {name: b, unit: my_servo, parent: a, connector: back, axis: yaw, levels_deg: [0]}\n"
    )
    robot = assemble(load_formation(formation_file))
    out = tmp_path / "pair.xml"
    write_model(assemble_mjcf(robot), robot.assets, out)
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.nmesh == 1 and (model.geom_type == mujoco.mjtGeom.mjGEOM_MESH).sum() == 2
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert data.qpos[2] == pytest.approx(0.025 + 0.002)  # the mesh's bottom 2 mm over the floor

    box.export(folder / "meshes" / "shell.ply")
    template.write_text(template.read_text().replace("shell.stl", "shell.ply"))
    with pytest.raises(FormationError, match=r"MuJoCo reads \.stl, .* not .*shell\.ply"):
        assemble_mjcf(assemble(load_formation(formation_file)))


def test_assemble_writes_the_mjcf_beside_the_urdf(tmp_path):
    result = run_cli("assemble", "snake5", "-o", tmp_path / "snake.urdf", "--mjcf")
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[0].split()[-2:] == ["urdf", "mjcf"]
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "snake.xml"))
    assert model.nu == 4
    refused = run_cli("assemble", "snake5", "-o", tmp_path / "snake.xml", "--mjcf")
    assert refused.returncode == 2 and "name the URDF *.urdf" in refused.stderr
