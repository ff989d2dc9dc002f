"""The friction model moves bodies the way it should: scripted gaits, no learning."""

import dataclasses
import math

import numpy as np

from qdsega.assembly import assemble
from qdsega.description import Formation, Friction, load_formation
from qdsega.simulation.bullet import BulletSimulation


def _serpentine_displacement(formation: Formation, seconds: float = 4.0) -> np.ndarray:
    """Centroid displacement (m) under a travelling wave from head to tail: 20 deg amplitude,
    1 s period, 90 deg phase lag between neighbouring joints."""
    with BulletSimulation(robot=assemble(formation)) as sim:
        joints = len(formation.joints)
        sim.reset(np.zeros(joints))
        sim.step(30)
        start = sim.unit_states()[0].mean(axis=0)
        dt = sim.settings.time_step_s
        for k in range(round(seconds / dt)):
            phase = 2 * math.pi * k * dt
            sim.command(
                [math.radians(20) * math.sin(phase - i * math.pi / 2) for i in range(joints)]
            )
            sim.step()
        return sim.unit_states()[0].mean(axis=0) - start


def test_snake_moves_forward_with_anisotropic_friction_only():
    snake = load_formation("assemblies/snake5.yaml")
    isotropic = dataclasses.replace(
        snake,
        units=tuple(
            dataclasses.replace(u, friction=Friction(u.friction.lateral, (1.0, 1.0, 1.0)))
            for u in snake.units
        ),
    )
    moved = _serpentine_displacement(snake)
    slid = _serpentine_displacement(isotropic)
    assert moved[0] > 0.5, moved  # clearly forward (+x, the head's direction)
    assert abs(moved[1]) < 0.2 * moved[0]
    assert np.linalg.norm(slid[:2]) < 0.1 * moved[0], slid


def _leg_posture(formation: Formation, states: dict[str, int]) -> np.ndarray:
    """Joint angles (rad) for paper leg states 1..4 (1 + swing index + 2 * lift index)."""
    levels = list(formation.rest_levels())
    for leg in formation.legs:
        swing, lift = (states[leg.name] - 1) % 2, (states[leg.name] - 1) // 2
        levels[formation.joint_index(leg.swing_joint)] = swing
        levels[formation.joint_index(leg.lift_joint)] = lift
    return np.array(formation.posture_rad(levels))


def test_legged12_walks_forward_with_an_alternating_gait():
    formation = load_formation("assemblies/legged12.yaml")
    # Tripod-like alternation: every other leg along a side, opposite phase across sides.
    left, right = formation.legs_on("left"), formation.legs_on("right")
    group_a = {leg.name for leg in left[0::2]} | {leg.name for leg in right[1::2]}
    cycle_a, cycle_b = (1, 2, 4, 3), (4, 3, 1, 2)  # down-forward, push back, lift, swing forward
    with BulletSimulation(robot=assemble(formation)) as sim:
        sim.reset(_leg_posture(formation, {leg.name: 1 for leg in formation.legs}))
        sim.step(120)
        start, _ = sim.base_pose()
        lowest = math.inf
        for _cycle in range(4):
            for phase in range(4):
                states = {
                    leg.name: (cycle_a if leg.name in group_a else cycle_b)[phase]
                    for leg in formation.legs
                }
                sim.command(_leg_posture(formation, states))
                for _ in range(60):  # 0.25 s a phase
                    sim.step()
                    lowest = min(lowest, sim.base_pose()[0][2])
        end, _ = sim.base_pose()
    displacement = end - start
    assert displacement[0] > 0.3, displacement  # about 0.14 m a cycle
    assert abs(displacement[1]) < 0.5 * displacement[0]
    assert lowest > 0.025 + 0.005, "the trunk (half-height 0.025 m) never touches the ground"
