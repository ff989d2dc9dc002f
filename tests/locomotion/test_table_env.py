"""The table models as a Gymnasium environment: checked by Gymnasium, and the same rewards as
the compiled learning loop for the same postures."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from qdsega import TABLE_ENV_ID
from qdsega.agent.qlearning import learn_on_table
from qdsega.agent.space import ExplorationSpace
from qdsega.baselines.classic_gaits import leg_gait
from qdsega.description import World, load_formation, load_world, resolve_world
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.errors import FormationError
from qdsega.locomotion.table_env import TableLocomotionEnv
from qdsega.task import TaskConfig

GREEDY = np.array([1e-9, 0.0, 0.0])
"""An eq. (18) schedule so cold that the roulette always takes the best action."""


@pytest.mark.parametrize(("formation", "world"), [("quadruped", "msm"), ("snake5", "memo")])
def test_gymnasium_checks_the_env(formation, world):
    env = gym.make(TABLE_ENV_ID, formation=formation, sim=world, task=TaskConfig(trial_steps=3))
    try:
        check_env(env.unwrapped, skip_render_check=True)
    finally:
        env.close()


def test_the_env_gives_the_compiled_loops_rewards_for_the_same_postures():
    """A legged12 gait, then every leg lifted (a fall), in the MSM: the env's rewards equal what
    the compiled loop writes into Q when forced along the same postures (alpha 1, gamma 0)."""
    formation = load_formation(ASSEMBLIES_DIR / "legged12.yaml")
    config = TaskConfig(trial_steps=6)
    env = TableLocomotionEnv(formation=formation, sim="msm", task=config)
    start = env.provider.start_posture()
    all_up = start.copy()
    for leg in formation.legs:
        all_up[formation.joint_index(leg.lift_joint)] = 1
    sequence = np.vstack([leg_gait(formation, gait="alternating", steps=5), all_up])
    env.reset(seed=0)
    rewards, ends = [], []
    for posture in sequence:
        observation, reward, terminated, truncated, _ = env.step(posture)
        rewards.append(reward)
        ends.append((terminated, truncated))
    assert ends[-1] == (True, False) and rewards[-1] == config.penalty
    assert not any(terminated for terminated, _ in ends[:-1])
    assert env.distance_covered() > 0

    space = ExplorationSpace.from_population(sequence, start)
    table = env.provider.transitions(space.postures, space.actions)
    order = [int(np.flatnonzero((space.actions == p).all(axis=1))[0]) for p in sequence]
    task = env.task
    q = np.zeros((space.n_interior * task.n_exterior, space.n_actions))
    visited, interior, exterior = [], 0, task.exterior((0.0, 0.0, 0.0))
    env.reset(seed=0)
    for a in order:
        observation, *_ = env.step(space.actions[a])
        visited.append((interior * task.n_exterior + exterior, a))
        interior, exterior = int(space.next_interior[a]), int(observation[-1])
    for s, a in visited:
        q[s, a] = 1e6
    uses = np.zeros(space.n_actions, dtype=np.int64)
    steps = learn_on_table(
        q, *table.compiled(), space.next_interior, task.light, task.edges,
        *task.map_arrays(), 1, task.trial_steps,
        1.0, 0.0, GREEDY, task.config.reward_per_m, task.penalty, np.random.default_rng(0), uses,
        np.zeros(1), np.zeros(1, dtype=np.bool_),
    )  # fmt: skip
    assert steps == len(order)
    assert [q[s, a] for s, a in visited] == pytest.approx(rewards, rel=1e-12, abs=1e-12)


def test_episodes_repeat_exactly():
    env = TableLocomotionEnv(formation="hexapod", sim="msm")
    env.action_space.seed(3)
    actions = [env.action_space.sample() for _ in range(8)]
    episodes = []
    for _ in range(2):
        env.reset(seed=0)
        episodes.append([(o.tolist(), r, t, u) for o, r, t, u, _ in map(env.step, actions)])
    assert episodes[0] == episodes[1]


def test_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="sim must be one of msm, memo"):
        TableLocomotionEnv(formation="quadruped", sim="mujoco")
    with pytest.raises(FormationError, match="legged"):
        TableLocomotionEnv(formation="snake5", sim="msm")
    env = TableLocomotionEnv(formation="quadruped")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="is not in MultiDiscrete"):
        env.step(np.full(len(env.formation.joints), 99))


def test_a_memo_env_measures_in_its_world_and_the_msm_knows_none():
    ice = load_world(resolve_world("ice"))
    actions = np.random.default_rng(0).integers(0, 9, size=(10, 4))
    covered = []
    for world in (None, ice):
        env = TableLocomotionEnv(formation="snake5", sim="memo", world=world, spots=2)
        assert env.provider.world == (world or World()) and len(env.provider.spots) == 2
        env.reset(seed=0)
        for action in actions:
            env.step(action)
        covered.append(env.distance_covered())
        env.close()
    assert covered[1] != covered[0]  # the same postures move the body otherwise on ice
    with pytest.raises(ValueError, match="the MSM knows no terrain"):
        TableLocomotionEnv(formation="quadruped", sim="msm", world=ice)


def test_a_memo_env_senses_obstacles_and_measures_clear_of_them(tmp_path):
    file = tmp_path / "post.yaml"
    file.write_text(
        "name: post\nboxes:\n  - {xyz_m: [0.5, 0.0, 0.1], size_m: [0.1, 0.1, 0.2]}\n",
        encoding="utf-8",
    )
    env = TableLocomotionEnv(formation="snake5", sim="memo", world=load_world(file), spots=2)
    try:
        assert env.observation_space.nvec[-1] == 12  # the light's 4 bins x 3 sensed states
        assert env.provider.spots == ((0.0, 0.0),)  # at 0.25 m its head would touch the post
        observation, _ = env.reset(seed=0)
        assert observation[-1] >= 4  # the post is sensed ahead
    finally:
        env.close()
