import dataclasses
import math

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from qdsega.baselines.classic_gaits import leg_gait
from qdsega.description import Friction, load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.locomotion.env import LocomotionEnv
from qdsega.task import TaskConfig


def _wave(step: int, joints: int) -> np.ndarray:
    """A travelling wave over the snake's 9 levels: 4 postures a cycle, 90 deg phase lag."""
    return np.array(
        [round(4 + 4 * math.sin(2 * math.pi * step / 4 - i * math.pi / 2)) for i in range(joints)]
    )


@pytest.fixture(scope="module")
def snake5():
    return load_formation("assemblies/snake5.yaml")


def test_passes_gymnasiums_env_checker(snake5):
    env = LocomotionEnv(formation=snake5, task=TaskConfig(trial_steps=4))
    try:
        check_env(env, skip_render_check=True)
    finally:
        env.close()


def test_same_seed_same_rollout(snake5):
    rollouts = []
    for _ in range(2):
        env = LocomotionEnv(formation=snake5, task=TaskConfig(trial_steps=6))
        env.action_space.seed(3)
        observations = [env.reset(seed=3)[0]]
        rewards = []
        for _step in range(6):
            observation, reward, *_ = env.step(env.action_space.sample())
            observations.append(observation)
            rewards.append(reward)
        rollouts.append((np.array(observations), np.array(rewards)))
        env.close()
    assert np.array_equal(rollouts[0][0], rollouts[1][0])
    assert np.array_equal(rollouts[0][1], rollouts[1][1])


def test_reset_restores_the_start_exactly(snake5):
    env = LocomotionEnv(formation=snake5, task=TaskConfig(trial_steps=8))
    rewards = []
    for _episode in range(2):
        env.reset(seed=0)
        rewards.append([env.step(_wave(k, 4))[1] for k in range(4)])
    env.close()
    assert rewards[0] == rewards[1]


def test_snake_moves_toward_the_light_because_of_anisotropic_friction(snake5):
    isotropic = dataclasses.replace(
        snake5,
        units=tuple(
            dataclasses.replace(u, friction=Friction(u.friction.lateral, (1.0, 1.0, 1.0)))
            for u in snake5.units
        ),
    )
    covered = {}
    for name, formation in (("anisotropic", snake5), ("isotropic", isotropic)):
        env = LocomotionEnv(formation=formation, task=TaskConfig(trial_steps=16))
        env.reset(seed=0)
        total = 0.0
        for k in range(16):
            _, reward, terminated, _, info = env.step(_wave(k, 4))
            total += reward
            assert not terminated, info["failure"]
        covered[name] = info["distance_covered_m"]
        assert total == pytest.approx(100 * covered[name], rel=1e-6)  # eq. (17) sums up
        env.close()
    assert covered["anisotropic"] > 0.1
    assert abs(covered["isotropic"]) < 0.2 * covered["anisotropic"]


def test_lifting_every_leg_fails_and_ends_the_trial():
    legged = load_formation("assemblies/quadruped.yaml")
    env = LocomotionEnv(formation=legged)
    observation, _ = env.reset(seed=0)
    all_up = np.array(observation[:-1])
    for leg in legged.legs:
        all_up[legged.joint_index(leg.lift_joint)] = 1  # lift level 1 = up
    _, reward, terminated, truncated, info = env.step(all_up)
    env.close()
    assert terminated and not truncated
    assert reward == TaskConfig().penalty
    assert info["failure"] == "trunk touched the ground"


def test_contacts_record_the_episodes_footfalls():
    legged = load_formation("assemblies/quadruped.yaml")
    env = LocomotionEnv(formation=legged)
    try:
        observation, _ = env.reset(seed=0)
        assert env.contacts().shape == (0, len(legged.units))
        env.step(observation[:-1])  # stand at rest for a step
        env.step(observation[:-1])
        contacts = env.contacts()
        checks = 2 * math.ceil(env.lower_agent.physics_steps / 12)
        assert contacts.shape == (checks, len(legged.units))
        index = {u.name: i for i, u in enumerate(legged.units)}
        for leg in legged.legs:  # every leg stands on the ground (a contact may flicker) ...
            assert contacts[:, [index[name] for name in leg.units]].any(axis=1).mean() >= 0.9
        assert not contacts[:, [index[u.name] for u in legged.trunk_units]].any()  # ... not it
        env.reset(seed=0)
        assert len(env.contacts()) == 0
    finally:
        env.close()


def test_a_posture_too_weak_joints_cannot_reach_fails(project):
    servo = project / "units" / "servo" / "unit.yaml"
    servo.write_text(servo.read_text().replace("effort_nm: 2.5", "effort_nm: 0.001"))
    weak = load_formation(ASSEMBLIES_DIR / "snake5.yaml", units_dir=project / "units")
    env = LocomotionEnv(formation=weak)
    env.reset(seed=0)
    _, reward, terminated, _, info = env.step(np.array([0, 8, 0, 8]))
    env.close()
    assert terminated and reward == TaskConfig().penalty
    assert "missed its level" in info["failure"]


def test_bad_action_is_refused(snake5):
    env = LocomotionEnv(formation=snake5)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="not in"):
        env.step(np.array([9, 0, 0, 0]))
    env.close()


def test_an_episode_after_a_fall_replays_exactly():
    """A fall makes new contact pairs (the trunk on the ground); the next episode must not
    depend on them (PhysicsSettings.deterministic_pairs)."""
    legged = load_formation("assemblies/quadruped.yaml")
    env = LocomotionEnv(formation=legged)
    gait = leg_gait(legged, gait="wave", steps=4)
    all_up = np.array(legged.rest_levels())
    for leg in legged.legs:
        all_up[legged.joint_index(leg.lift_joint)] = 1
    episodes = []
    for _ in range(2):
        env.reset(seed=0)
        episodes.append([env.step(p)[1] for p in gait] + [env.step(all_up)[1]])
    env.close()
    assert episodes[0][-1] == TaskConfig().penalty
    assert episodes[0] == episodes[1]
