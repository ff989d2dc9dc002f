"""PPO and SAC from stable-baselines3 under continuous control, on PyBullet tasks.

Both learn in ``qdsega/JointLocomotion-v0``
(:class:`qdsega.locomotion.joint_env.JointLocomotionEnv`) with the task's formation, preset rules
and world: joint targets at every step, exact PyBullet throughout (no table). Their budget is
physics time: one posture step of the other methods is
:data:`~qdsega.locomotion.CONTROLS_PER_POSTURE` env steps here (:func:`posture_steps`), so a run
stops at the task's ``budget_steps`` of those (or its ``ppo_steps``, if fewer), and its curve
counts them.

Every :data:`SCORE_EVERY` posture steps' worth of env steps, the deterministic policy plays one
episode in a second env of the same task, and its distance toward the light there (exact by
construction) is a point of the curve, as is the final policy's where the budget ends. Those
scoring episodes are not counted in the budget, as the ``ppo`` method's are not
(:mod:`qdsega.bench.ppo`). Hyperparameters are stable-baselines3's defaults but for PPO's rollout
length (``n_steps``), :data:`SCORE_EVERY`'s env steps: one point per rollout.

Needs the ``bench`` extra (``pip install -e '.[bench]'`` in the checkout).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

from qdsega.bench.curve import Curve
from qdsega.bench.ppo import greedy_distance
from qdsega.bench.tasks import BenchTask
from qdsega.locomotion import CONTROLS_PER_POSTURE

if TYPE_CHECKING:  # the env starts PyBullet
    from qdsega.locomotion.joint_env import JointLocomotionEnv

LEARNERS = ("ppo", "sac")
"""The stable-baselines3 algorithms a joint-env run may use, by lower-case name."""
SCORE_EVERY = 128
"""Posture steps' worth of env steps between two scorings of the policy (-): 1536 env steps,
PPO's rollout, a multiple of its default minibatch of 64; 24 points in a 3000-step budget."""


def posture_steps(env_steps: int) -> int:
    """The budget rule: ``env_steps`` of the joint env as the posture steps of the same physics
    time, a posture step being :data:`~qdsega.locomotion.CONTROLS_PER_POSTURE` env steps (a
    posture step begun is not counted)."""
    return env_steps // CONTROLS_PER_POSTURE


def env_steps(postures: int) -> int:
    """The env steps of ``postures`` posture steps' physics time: :func:`posture_steps`'s
    inverse."""
    return postures * CONTROLS_PER_POSTURE


def joint_curve(
    task: BenchTask, seed: int, *, learner: str, score_every: int = SCORE_EVERY
) -> Curve:
    """One run of ``learner`` (:data:`LEARNERS`) on ``task``, seeded by ``seed``: its
    deterministic policy's exact distance every ``score_every`` posture steps and where the
    budget ends.

    ``task`` is a PyBullet one: :class:`BenchTask` refuses these methods on an MSM task.

    Raises:
        ValueError: an unknown learner or a score interval below 1.
        ModuleNotFoundError: stable-baselines3 is not installed (the message says how).
    """
    if learner not in LEARNERS:
        raise ValueError(f"learner must be one of {', '.join(LEARNERS)}, got {learner!r}")
    if score_every < 1:
        raise ValueError(f"score_every must be at least 1, got {score_every}")
    try:
        import torch
        from stable_baselines3 import PPO, SAC
        from stable_baselines3.common.callbacks import BaseCallback
    except ModuleNotFoundError as exc:
        raise ModuleNotFoundError(
            f"the {learner}-joint method needs stable-baselines3 ({exc}): "
            "pip install -e '.[bench]' in the checkout"
        ) from None
    torch.set_num_threads(1)
    budget = min(task.budget_steps, task.ppo_steps)
    start = time.perf_counter()
    points: list[tuple[int, float, float]] = []
    model: Any

    with _env(task) as env, _env(task) as judge:

        def score() -> None:
            spent = posture_steps(model.num_timesteps)
            points.append((spent, greedy_distance(judge, model), time.perf_counter() - start))

        class Score(BaseCallback):
            def _on_step(self) -> bool:
                if self.num_timesteps % env_steps(score_every) == 0:
                    score()
                return posture_steps(self.num_timesteps) < budget

        if learner == "ppo":
            model = PPO("MlpPolicy", env, n_steps=env_steps(score_every), seed=seed, device="cpu")
        else:
            model = SAC("MlpPolicy", env, seed=seed, device="cpu")
        model.learn(total_timesteps=env_steps(budget), callback=Score())
        if not points or points[-1][0] < posture_steps(model.num_timesteps):
            score()  # where the budget ended, past the last interval
    return Curve.of(points)


def _env(task: BenchTask) -> JointLocomotionEnv:
    """The joint env of ``task``: its formation, lit by its world, under its exact rules."""
    from qdsega.locomotion.joint_env import JointLocomotionEnv  # starts PyBullet: only here

    rules = task.exact_rules()
    return JointLocomotionEnv(
        formation=task.load(),
        task=rules.task,
        lower_agent=rules.lower_agent,
        physics=rules.physics,
        world=rules.world,
    )
