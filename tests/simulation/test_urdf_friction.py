"""The assembled URDF carries the friction: the file alone, loaded by a plain
``pybullet.loadURDF``, plays the toolkit's trial; anisotropic friction alone it cannot carry."""

import dataclasses
import xml.etree.ElementTree as ET

import numpy as np
import pybullet
import pytest

from qdsega.assembly import assemble, write_assembly
from qdsega.baselines.classic_gaits import leg_gait
from qdsega.description import Formation, Friction, load_formation
from qdsega.simulation.bullet import BulletSimulation

FLAGS = (
    pybullet.URDF_USE_INERTIA_FROM_FILE
    | pybullet.URDF_USE_SELF_COLLISION
    | pybullet.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT
)
"""The flags docs/formations.md gives for loading the file as qdsega does."""


def _trial(formation: Formation, commands_rad: np.ndarray, hold: int, *, file=None) -> np.ndarray:
    """Every unit's position (m), shape (U, 3), after the toolkit commands each row of
    ``commands_rad`` (joint angles) for ``hold`` physics steps from rest; with ``file``, on
    the body that a plain loadURDF of the file makes, in place of the toolkit's own (same
    world, same engine, same commands)."""
    with BulletSimulation(robot=assemble(formation)) as sim:
        if file is not None:
            sim.client.removeBody(sim.body_id)
            sim.body_id = sim.client.loadURDF(str(file), flags=FLAGS)
        sim.reset(np.array(formation.posture_rad(formation.rest_levels())))
        sim.step(120)
        for command in commands_rad:
            sim.command(command)
            sim.step(hold)
        return sim.unit_states()[0]


def test_each_link_of_the_file_carries_its_own_lateral_friction(tmp_path):
    quadruped = load_formation("assemblies/quadruped.yaml")
    units = tuple(
        dataclasses.replace(u, friction=Friction(0.5 + 0.05 * i, u.friction.anisotropic))
        for i, u in enumerate(quadruped.units)
    )
    formation = dataclasses.replace(quadruped, units=units)
    file = tmp_path / "quadruped.urdf"
    write_assembly(assemble(formation), file)
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(file), physicsClientId=client)
        links = {pybullet.getBodyInfo(body, physicsClientId=client)[0].decode(): -1}
        for j in range(pybullet.getNumJoints(body, physicsClientId=client)):
            links[pybullet.getJointInfo(body, j, physicsClientId=client)[12].decode()] = j
        for unit in units:
            info = pybullet.getDynamicsInfo(body, links[unit.name], physicsClientId=client)
            assert info[1] == pytest.approx(unit.friction.lateral, abs=1e-12), unit.name
    finally:
        pybullet.disconnect(client)


def test_the_file_alone_plays_the_toolkits_trial_bit_for_bit(tmp_path):
    """An isotropic body: nothing of its friction is left outside the file."""
    quadruped = load_formation("assemblies/quadruped.yaml")
    assert all(u.friction.is_isotropic for u in quadruped.units)
    file = tmp_path / "quadruped.urdf"
    write_assembly(assemble(quadruped), file)
    levels = leg_gait(quadruped, gait="alternating", steps=8)
    gait = np.array([quadruped.posture_rad(posture) for posture in levels])
    toolkit = _trial(quadruped, gait, 60)  # 0.25 s a posture
    alone = _trial(quadruped, gait, 60, file=file)
    assert toolkit[0, 0] > 0.2, toolkit[0]  # it walked
    np.testing.assert_array_equal(alone, toolkit)


def test_the_file_names_anisotropic_friction_that_pybullet_does_not_read(tmp_path):
    snake = load_formation("assemblies/snake5.yaml")
    robot = assemble(snake)
    contact = ET.fromstring(robot.urdf).find("link/contact")
    assert contact is not None and contact.find("lateral_friction").get("value") == "0.8"
    assert "anisotropic friction x y z: 0.01 1 0.01" in robot.urdf
    file = tmp_path / "snake5.urdf"
    write_assembly(robot, file)
    seconds = np.arange(480)[:, None] / 240.0  # 2 s, a travelling wave of 1 Hz
    wave = np.radians(20.0) * np.sin(2 * np.pi * seconds - np.arange(4) * np.pi / 2)
    toolkit, alone = _trial(snake, wave, 1), _trial(snake, wave, 1, file=file)
    assert toolkit[0, 0] > 0.3 > 0.03 > alone[0, 0], (toolkit[0], alone[0])  # 0.40 m, 0.016 m
