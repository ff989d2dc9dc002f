"""The Gymnasium environment seen as the agent's step-by-step model (exact mode)."""

from __future__ import annotations

import numpy as np

from qdsega.agent.model import StepResult
from qdsega.locomotion.env import LocomotionEnv
from qdsega.task import Pose


class EnvModel:
    """A :class:`qdsega.agent.model.World` over a :class:`LocomotionEnv`: every command is
    simulated in PyBullet.

    Args:
        env: the environment; its task sets reward, penalty, exterior bins and trial length.
    """

    def __init__(self, *, env: LocomotionEnv) -> None:
        self.env = env
        self.commands = 0
        """Postures commanded so far (upper-agent steps simulated)."""

    @property
    def n_joints(self) -> int:
        return len(self.env.formation.joints)

    def start_posture(self) -> np.ndarray:
        return self.env.start_levels.copy()

    def start_trial(self) -> int:
        observation, _ = self.env.reset(seed=0)
        return int(observation[-1])

    def command(self, posture: np.ndarray) -> StepResult:
        observation, reward, terminated, _, info = self.env.step(posture)
        self.commands += 1
        return StepResult(reward, int(observation[-1]), terminated, info["failure"])

    def distance_covered(self) -> float:
        return self.env.distance_covered()

    def pose(self) -> Pose:
        return self.env.pose()

    def close(self) -> None:
        self.env.close()
