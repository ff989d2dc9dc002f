"""PPO from stable-baselines3 on the table model's Gymnasium environment.

PPO learns in ``qdsega/TableLocomotion-v0`` (:mod:`qdsega.locomotion.table_env`): the MSM, or for
a PyBullet task the memo table, each pair measured in PyBullet on first use, so PPO runs at
table speed where QDSEGA does and spends the same budget (MSM steps; PyBullet steps measured),
in the task's world (its table measured there from as many spots as QDSEGA's).
Its hyperparameters are stable-baselines3's defaults but for the environments side by side,
the rollout length and the minibatch (below). After every rollout its deterministic policy is
scored in exact physics (the MSM itself, or :class:`qdsega.locomotion.env.LocomotionEnv`);
those scoring episodes are not counted in its budget, as QDSEGA's exact replays are (they steer
its learning).

Needs the ``bench`` extra (``pip install -e '.[bench]'`` in the checkout).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, cast

import gymnasium as gym
import numpy as np

from qdsega.bench.curve import Curve
from qdsega.bench.tasks import LEARNING_SIM, BenchTask
from qdsega.locomotion.table_env import TableLocomotionEnv
from qdsega.training.sims import memo_spots

if TYPE_CHECKING:  # the memo table starts PyBullet
    from qdsega.locomotion.memo import MeasuredTransitions

ENVS = {"msm": 64, "pybullet": 1}
"""Environments PPO steps side by side per simulator: in the MSM 64, so that each policy call
serves 64 steps (stable-baselines3 spends most of its time building one distribution per joint
per call; 16 gave half the speed, 256 no more); in PyBullet 1, since each environment would
measure its own memo table (-)."""
ROLLOUT_STEPS = {"msm": 8192, "pybullet": 256}
"""Steps per PPO rollout, all environments together: 128 per environment in the MSM; shorter in
PyBullet, whose budget holds a few thousand steps (-). A task whose ``ppo_steps`` are fewer has
one rollout of that many steps."""
BATCH = {"msm": 1024, "pybullet": 256}
"""PPO's minibatch per simulator (-): 8 minibatches per rollout in the MSM, so that 1e7 steps
take under an hour on one core; 4x stable-baselines3's default of 64 in PyBullet."""


def _factory(env: gym.Env) -> Callable[[], gym.Env]:
    """A maker of ``env`` itself (DummyVecEnv takes makers)."""
    return lambda: env


def ppo_curve(task: BenchTask, seed: int) -> Curve:
    """One PPO run on ``task``: its deterministic policy's exact distance after every rollout.

    Raises:
        ModuleNotFoundError: stable-baselines3 is not installed (the message says how).
    """
    try:
        import torch
        from stable_baselines3 import PPO
        from stable_baselines3.common.callbacks import BaseCallback
        from stable_baselines3.common.vec_env import DummyVecEnv
    except ModuleNotFoundError as exc:
        raise ModuleNotFoundError(
            f"the ppo method needs stable-baselines3 ({exc}): "
            "pip install -e '.[bench]' in the checkout"
        ) from None
    torch.set_num_threads(1)
    torch.distributions.Distribution.set_default_validate_args(False)
    formation, config, world = task.load(), task.config(seed=seed), task.load_world()
    envs = [
        TableLocomotionEnv(
            formation=formation,
            sim=LEARNING_SIM[task.sim],
            task=config.task,
            msm=config.msm,
            world=world,
            spots=memo_spots(config, world),
        )
        for _ in range(ENVS[task.sim])
    ]
    vector = DummyVecEnv([_factory(env) for env in envs])
    judge = _exact_env(task)
    start = time.perf_counter()
    points: list[tuple[int, float, float]] = []

    def spent() -> int:
        if task.sim == "msm":
            return model.num_timesteps
        # every sim but the MSM learns in a memo table, whose measured pairs are the budget
        return int(cast("MeasuredTransitions", envs[0].provider).measured)

    class Score(BaseCallback):
        def _on_rollout_end(self) -> None:
            distance = greedy_distance(judge, model)
            points.append((spent(), distance, time.perf_counter() - start))

        def _on_step(self) -> bool:
            return spent() < task.budget_steps

    rollout = min(ROLLOUT_STEPS[task.sim], task.ppo_steps)
    n_steps = max(rollout // len(envs), 2)
    batch = min(BATCH[task.sim], n_steps * len(envs))
    model = PPO(
        "MlpPolicy", vector, n_steps=n_steps, batch_size=batch, seed=seed, device="cpu", verbose=0
    )
    try:
        model.learn(total_timesteps=task.ppo_steps, callback=Score())
        points.append((spent(), greedy_distance(judge, model), time.perf_counter() - start))
    finally:
        vector.close()
        judge.close()
    return Curve.of(points).until(task.budget_steps)


def _exact_env(task: BenchTask) -> gym.Env[np.ndarray, np.ndarray]:
    """Where PPO's policy is scored: the MSM itself, or exact PyBullet in the task's world."""
    formation, config = task.load(), task.config(seed=0)
    if task.sim == "msm":
        return TableLocomotionEnv(formation=formation, sim="msm", task=config.task, msm=config.msm)
    from qdsega.locomotion.env import rules_env  # starts PyBullet: only here

    return rules_env(formation, task.exact_rules())


def greedy_distance(env: Any, model: Any) -> float:
    """Distance toward the light (m) of one episode of ``model``'s deterministic policy in
    ``env`` (any env with ``distance_covered``: the joint-env learners score with it too)."""
    observation, _ = env.reset(seed=0)
    done = False
    while not done:
        action, _ = model.predict(observation, deterministic=True)
        observation, _, terminated, truncated, _ = env.step(action)
        done = terminated or truncated
    return float(env.distance_covered())
