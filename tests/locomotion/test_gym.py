"""The env through Gymnasium: registration, ``formation=``, rendering and the env checkers."""

from __future__ import annotations

import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from qdsega import ENV_ID
from qdsega.description import load_formation
from qdsega.locomotion.env import LocomotionEnv
from qdsega.simulation.camera import CameraConfig
from qdsega.task import TaskConfig

SMALL = CameraConfig(width=64, height=48)


def _python(code: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )


def test_importing_qdsega_registers_the_env_without_starting_pybullet():
    result = _python(
        "import sys, gymnasium, qdsega\n"
        "assert qdsega.ENV_ID in gymnasium.registry, sorted(gymnasium.registry)[-3:]\n"
        "assert 'pybullet' not in sys.modules\n"
    )
    assert result.returncode == 0, result.stderr


def test_make_imports_qdsega_by_itself_through_the_module_prefix():
    result = _python(
        "import gymnasium\n"
        f"env = gymnasium.make('qdsega:{ENV_ID}', formation='snake5')\n"
        "observation, _ = env.reset(seed=0)\n"
        "print(observation.tolist(), env.step(observation[:-1])[1])\n"
        "env.close()\n"
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("[4, 4, 4, 4, 2] ")


@pytest.mark.parametrize("kind", ["name", "path", "formation"])
def test_formation_is_a_shipped_name_a_path_or_a_formation(kind):
    formation = {
        "name": "snake5",
        "path": "assemblies/snake5.yaml",
        "formation": load_formation("assemblies/snake5.yaml"),
    }[kind]
    env = gym.make(ENV_ID, formation=formation)
    try:
        assert env.unwrapped.formation.name == "snake5"
        assert env.action_space == gym.spaces.MultiDiscrete([9, 9, 9, 9])
        assert env.render_mode is None and env.unwrapped.render() is None
    finally:
        env.close()


def test_gymnasiums_env_checker_passes_with_rendering():
    env = gym.make(
        ENV_ID,
        formation="snake5",
        task=TaskConfig(trial_steps=4),
        render_mode="rgb_array",
        camera=SMALL,
    )
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            check_env(env.unwrapped)
        env.reset(seed=0)
        frame = env.render()
        assert frame.shape == (48, 64, 3) and frame.dtype == np.uint8 and frame.std() > 10
        assert env.metadata["render_fps"] == 2.0  # one picture per 0.5 s step
    finally:
        env.close()


def test_stable_baselines3_env_checker_passes():
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    env = gym.make(ENV_ID, formation="snake5", task=TaskConfig(trial_steps=4))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            sb3_checker.check_env(env.unwrapped)
    finally:
        env.close()


@pytest.mark.parametrize("world", [None, "rubble"])  # rubble: its relief is drawn for pictures
def test_rendering_changes_nothing_in_the_physics(world):
    rollouts = []
    for render_mode in (None, "rgb_array"):
        env = gym.make(
            ENV_ID, formation="snake5", render_mode=render_mode, camera=SMALL, world=world
        )
        env.action_space.seed(1)
        env.reset(seed=0)
        steps = [env.step(env.action_space.sample()) for _ in range(3)]
        rollouts.append([(o.tolist(), r, i["x_m"], i["y_m"]) for o, r, _, _, i in steps])
        env.close()
    assert rollouts[0] == rollouts[1]


def test_an_unknown_render_mode_is_refused():
    with pytest.raises(ValueError, match="render_mode must be None or 'rgb_array', got 'ansi'"):
        LocomotionEnv(formation="snake5", render_mode="ansi")
