"""Every shipped unit type is complete and sound, and every shipped formation (and every unit
on its own) loads in PyBullet and rests on the plane (MuJoCo Menagerie style)."""

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import yaml
from helpers import SHIPPED_FORMATIONS, SHIPPED_UNITS

from qdsega.assembly import assemble
from qdsega.assembly.mass_properties import link_mass_properties
from qdsega.description import Formation, load_formation, load_unit_type
from qdsega.description.shipped import UNITS_DIR
from qdsega.description.unit_type import LINK_PLACEHOLDER
from qdsega.simulation.bullet import BulletSimulation


def test_units_are_shipped():
    assert {folder.name for folder in SHIPPED_UNITS} >= {"servo", "hub"}


@pytest.mark.parametrize("folder", SHIPPED_UNITS, ids=lambda f: f.name)
def test_unit_folder_is_complete_and_sound(folder):
    assert (folder / "unit.yaml").is_file()
    assert (folder / "unit.yaml").read_text().startswith("#"), "unit.yaml starts with a comment"
    unit = load_unit_type(UNITS_DIR, folder.name)
    assert unit.template_file.parent == folder and unit.template_file.is_file()
    robot = ET.fromstring(unit.link_template.replace(LINK_PLACEHOLDER, "probe"))
    (link,) = robot.findall("link")
    collisions = link.findall("collision")
    assert collisions and all(c.find("geometry") is not None for c in collisions)
    props = link_mass_properties(link, unit.mass_kg, folder=folder)
    assert props.mass_kg == pytest.approx(unit.mass_kg) and unit.mass_kg > 0
    assert np.all(np.linalg.eigvalsh(props.inertia_kg_m2) > 0)
    assert unit.connectors, "a unit offers at least one connector"
    for connector in unit.connectors.values():
        assert all(math.isfinite(x) for x in (*connector.xyz_m, *connector.rpy_rad))
    if unit.joint is not None:
        assert unit.joint.lower_rad < 0 < unit.joint.upper_rad
        assert unit.joint.effort_nm > 0 and unit.joint.velocity_rad_s > 0


@pytest.mark.parametrize("folder", SHIPPED_UNITS, ids=lambda f: f.name)
def test_unit_alone_and_in_a_pair_loads_and_rests(folder, tmp_path):
    """The unit on its own, then with a second one on its first connector (a joint if active)."""
    unit = load_unit_type(UNITS_DIR, folder.name)
    child = {
        "name": "b",
        "unit": unit.name,
        "parent": "a",
        "connector": next(iter(unit.connectors)),
    }
    if unit.is_active:
        child |= {"axis": "yaw", "levels_deg": [0]}
    for units in ([{"name": "a", "unit": unit.name}], [{"name": "a", "unit": unit.name}, child]):
        file = tmp_path / "probe.yaml"
        data = {"name": "probe", "light": {"distance_m": 5.0}, "units": units}
        file.write_text(yaml.safe_dump(data))
        formation = load_formation(file)
        assert len(formation.joints) == (len(units) - 1) * unit.is_active
        _assert_loads_and_rests(formation, seconds=1.0)


@pytest.mark.parametrize("file", SHIPPED_FORMATIONS, ids=lambda f: f.stem)
def test_formation_loads_and_rests_for_two_seconds(file):
    _assert_loads_and_rests(load_formation(file), seconds=2.0)


def _assert_loads_and_rests(formation: Formation, *, seconds: float) -> None:
    with BulletSimulation(robot=assemble(formation)) as sim:
        assert sim.client.getNumJoints(sim.body_id) == len(formation.units) - 1
        revolute = [
            j
            for j in range(sim.client.getNumJoints(sim.body_id))
            if sim.client.getJointInfo(sim.body_id, j)[2] == 0  # JOINT_REVOLUTE
        ]
        assert len(revolute) == len(formation.joints)
        rest = formation.posture_rad(formation.rest_levels())
        sim.reset(rest)
        sim.step(60)  # 0.25 s to settle the drop clearance
        start, _ = sim.base_pose()
        steps = round(seconds / sim.settings.time_step_s)
        sim.step(steps)
        end, orientation = sim.base_pose()
        positions = sim.unit_states()[0]
        assert np.all(np.isfinite(positions)) and np.all(np.isfinite(orientation))
        assert np.linalg.norm(end - start) < 0.01
        assert np.allclose(sim.joint_positions(), rest, atol=0.02)
        assert sim.ground_contacts(), "the robot touches the ground"


def test_friction_is_applied_to_every_link():
    formation = load_formation("assemblies/snake5.yaml")
    with BulletSimulation(robot=assemble(formation)) as sim:
        for unit in formation.units:
            info = sim.client.getDynamicsInfo(sim.body_id, sim.link_index[unit.name])
            assert info[1] == pytest.approx(unit.friction.lateral)
            assert info[1] == pytest.approx(0.8)


def test_two_simulations_do_not_share_a_client():
    robot = assemble(load_formation("assemblies/snake5.yaml"))
    with BulletSimulation(robot=robot) as a, BulletSimulation(robot=robot) as b:
        assert a.client._client != b.client._client
        a.reset(np.zeros(4))
        b.reset(np.zeros(4))
        a.command(np.radians([20, 20, 20, 20]))
        a.step(240)
        assert np.allclose(b.joint_positions(), 0.0, atol=1e-6)
        assert not np.allclose(a.joint_positions(), 0.0, atol=0.1)


def test_joints_move_at_most_at_their_speed_limit():
    formation = load_formation("assemblies/snake5.yaml")
    with BulletSimulation(robot=assemble(formation)) as sim:
        sim.reset(np.zeros(4))
        sim.command(np.radians([20, -20, 20, -20]))
        sim.step(1)
        speeds = np.abs(
            [s[1] for s in sim.client.getJointStates(sim.body_id, sim.joint_ids.tolist())]
        )
        limit = formation.joints[0].spec.velocity_rad_s
        assert np.all(speeds <= limit * 1.05)
