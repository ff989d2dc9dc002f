"""Every shipped formation loads in PyBullet and rests on the plane (MuJoCo Menagerie style)."""

import numpy as np
import pytest
from helpers import SHIPPED_FORMATIONS

from qdsega.assembly import assemble
from qdsega.description import load_formation
from qdsega.simulation.bullet import BulletSimulation


@pytest.mark.parametrize("file", SHIPPED_FORMATIONS, ids=lambda f: f.stem)
def test_formation_loads_and_rests_for_two_seconds(file):
    formation = load_formation(file)
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
        steps = round(2.0 / sim.settings.time_step_s)
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
