"""The continuous-control env: registration, Gymnasium's checker, eq. (17) returns, the trial's
physics time, failures, worlds and the window."""

from __future__ import annotations

import math
import time
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from qdsega.errors import QdsegaWarning
from qdsega.locomotion import (
    CONTROLS_PER_POSTURE,
    ENV_ID,
    JOINT_ENV_ID,
    TABLE_ENV_ID,
    TRIAL_STEPS,
)
from qdsega.locomotion.joint_env import JointLocomotionEnv
from qdsega.simulation import bullet
from qdsega.simulation.camera import CameraConfig
from qdsega.task import TaskConfig

SHORT = TaskConfig(trial_steps=2)
"""Episodes of 24 steps."""
INFINITE_BOUNDS = "infinity. This is probably too"
"""Gymnasium's checker warns of every unbounded Box: velocities have no bound."""


def _wave(env: JointLocomotionEnv, step: int) -> np.ndarray:
    """A travelling wave at 1 Hz, 40% of each joint's range, 90 deg between joints."""
    phase = 2 * math.pi * step * env.dt
    joints = env.action_space.shape[0]
    return np.array([0.4 * math.sin(phase - k * math.pi / 2) for k in range(joints)], np.float32)


def test_the_registrations_cut_episodes_at_the_trial():
    assert TaskConfig().trial_steps == TRIAL_STEPS  # written twice: registering compiles nothing
    for env_id in (ENV_ID, TABLE_ENV_ID):
        assert gym.spec(env_id).max_episode_steps == TRIAL_STEPS
    env = gym.make(JOINT_ENV_ID, formation="snake5")
    try:
        unwrapped = env.unwrapped
        assert env.spec.max_episode_steps == unwrapped.episode_steps == 360
        assert unwrapped.physics_steps_per_step == 10 and unwrapped.dt == pytest.approx(1 / 24)
        # An episode holds a trial's physics time, a QDSEGA trial's.
        physics = unwrapped.episode_steps * unwrapped.physics_steps_per_step
        assert physics == TRIAL_STEPS * unwrapped.lower_agent.physics_steps
    finally:
        env.close()


def test_gymnasiums_env_checker_passes_with_both_render_modes(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)  # a "human" env then opens no window
    small = CameraConfig(width=64, height=48)
    env = gym.make(JOINT_ENV_ID, formation="snake5", task=SHORT, camera=small)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            check_env(env.unwrapped)  # it makes one env per render mode and renders it
        unexpected = [
            str(w.message)
            for w in caught
            if INFINITE_BOUNDS not in str(w.message) and not issubclass(w.category, QdsegaWarning)
        ]
        assert unexpected == []
        assert env.observation_space.shape == (19,) and env.action_space.shape == (4,)
        assert env.metadata["render_fps"] == pytest.approx(24.0)
    finally:
        env.close()


def test_an_episodes_return_is_eq17_of_the_distance_covered():
    task = TaskConfig(trial_steps=3, distance_unit_m=0.01)  # eq. (17) in centimetres
    env = JointLocomotionEnv(formation="snake5", task=task)
    try:
        observation, info = env.reset(seed=0)
        assert info["distance_covered_m"] == 0.0
        np.testing.assert_allclose(observation[8:11], [0, 0, -1], atol=1e-3)  # lying flat
        np.testing.assert_allclose(observation[-2:], [0, 1], atol=1e-3)  # the light ahead
        rewards, step = [], 0
        truncated = terminated = False
        while not (terminated or truncated):
            observation, reward, terminated, truncated, info = env.step(_wave(env, step))
            rewards.append(reward)
            step += 1
        assert (terminated, truncated, step) == (False, True, 3 * CONTROLS_PER_POSTURE)
        assert info["distance_covered_m"] == env.distance_covered() > 0.02  # it moves on
        assert sum(rewards) == pytest.approx(1e4 * env.distance_covered(), rel=1e-9)
        assert np.all(np.abs(observation[4:8]) > 0.01)  # the joints are on their way
    finally:
        env.close()


def test_max_episode_steps_truncates_through_gym_make():
    env = gym.make(JOINT_ENV_ID, formation="snake5", max_episode_steps=5)
    try:
        env.reset(seed=0)
        ends = [env.step(env.action_space.sample())[2:4] for _ in range(5)]
        assert ends == [(False, False)] * 4 + [(False, True)]
    finally:
        env.close()


def test_the_same_actions_give_the_same_episode():
    env = JointLocomotionEnv(formation="snake5", task=SHORT)
    try:
        runs = []
        for _ in range(2):
            env.reset(seed=0)
            runs.append([env.step(_wave(env, k))[:2] for k in range(6)])
        assert all(np.array_equal(a[0], b[0]) and a[1] == b[1] for a, b in zip(*runs, strict=True))
    finally:
        env.close()


def test_a_legged_trunk_on_the_ground_ends_the_episode_with_the_penalty():
    env = JointLocomotionEnv(formation="quadruped", task=SHORT)
    try:
        env.reset(seed=0)
        lift_up = np.ones(env.action_space.shape, dtype=np.float32)  # every leg folds up
        for _ in range(env.episode_steps):
            _, reward, terminated, truncated, info = env.step(lift_up)
            if terminated or truncated:
                break
        assert terminated and not truncated
        assert reward == env.task.penalty and info["failure"] == "trunk touched the ground"
    finally:
        env.close()


def test_a_world_by_name_tilts_the_ground_under_the_body():
    env = gym.make(JOINT_ENV_ID, formation="snake5", world="slope")
    try:
        observation, _ = env.reset(seed=0)
        assert env.unwrapped.world.name == "slope"
        gravity = observation[8:11]  # up the hill toward the light: gravity pulls backward
        assert gravity[0] == pytest.approx(-math.sin(math.radians(8)), abs=0.01)
        env.step(env.action_space.sample())
    finally:
        env.close()


def test_actions_are_clipped_to_the_joint_limits_and_checked():
    env = JointLocomotionEnv(formation="snake5", task=SHORT)
    try:
        env.reset(seed=0)
        clipped = env.step(np.full(4, 5.0, dtype=np.float32))[0]
        env.reset(seed=0)
        assert np.array_equal(env.step(np.ones(4, dtype=np.float32))[0], clipped)
        with pytest.raises(ValueError, match=r"action must be \(4,\) finite"):
            env.step(np.array([0.0, 0.0, math.nan, 0.0]))
        with pytest.raises(ValueError, match="render_mode must be None, 'human' or 'rgb_array'"):
            JointLocomotionEnv(formation="snake5", render_mode="ansi")
    finally:
        env.close()


def test_human_rendering_says_in_one_line_where_there_is_no_display(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    with pytest.warns(QdsegaWarning, match=r"^no PyBullet window without a display \(DISPLAY"):
        env = gym.make(JOINT_ENV_ID, formation="snake5", render_mode="human")
    try:
        env.reset(seed=0)
        env.step(env.action_space.sample())
        assert not env.unwrapped.sim.window and env.render() is None
    finally:
        env.close()


def test_the_window_plays_steps_at_real_speed_and_changes_nothing(monkeypatch):
    # A display, faked: DIRECT mode stands in for the window's GUI mode, which needs one.
    monkeypatch.setenv("DISPLAY", ":0")
    monkeypatch.setattr(bullet.pybullet, "GUI", bullet.pybullet.DIRECT)
    observations, seconds = {}, {}
    for render_mode in ("human", None):
        env = JointLocomotionEnv(formation="snake5", task=SHORT, render_mode=render_mode)
        try:
            assert env.sim.window == (render_mode == "human")
            start = time.monotonic()
            env.reset(seed=0)
            observations[render_mode] = [env.step(_wave(env, k))[0].tolist() for k in range(6)]
            seconds[render_mode] = time.monotonic() - start
        finally:
            env.close()
    assert seconds["human"] >= 6 * env.dt
    assert observations["human"] == observations[None]
