"""The Gymnasium environment seen as the agent's step-by-step world (exact mode)."""

from __future__ import annotations

import numpy as np

from qdsega.agent.world import StepResult
from qdsega.locomotion.env import LocomotionEnv


class EnvWorld:
    """A :class:`qdsega.agent.world.World` over a :class:`LocomotionEnv`: every command is
    simulated in PyBullet.

    Args:
        env: the environment; its task sets reward, penalty, exterior bins and trial length.
    """

    def __init__(self, *, env: LocomotionEnv) -> None:
        self.env = env

    @property
    def n_joints(self) -> int:
        return len(self.env.formation.joints)

    def start_posture(self) -> np.ndarray:
        return self.env.start_levels.copy()

    def start_trial(self) -> int:
        observation, _ = self.env.reset(seed=0)
        return int(observation[-1])

    def command(self, posture: np.ndarray) -> StepResult:
        observation, reward, terminated, _, _ = self.env.step(posture)
        return StepResult(reward=reward, exterior=int(observation[-1]), failed=terminated)

    def distance_covered(self) -> float:
        return self.env.distance_covered()

    def pose(self) -> tuple[float, float, float]:
        pose = self.env.body_pose()
        return (pose.x_m, pose.y_m, pose.heading_rad)

    def close(self) -> None:
        self.env.close()
