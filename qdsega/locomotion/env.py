"""A Gymnasium environment: any formation walks toward the light in PyBullet.

Observation: the current posture (one level index per joint) and the exterior state (the bin of
the angle from the heading to the light), as ``MultiDiscrete([n_1, ..., n_J, n_bins])``.
Action: a posture, ``MultiDiscrete([n_1, ..., n_J])``. One step is one upper-agent step: the
lower agent drives every joint to its level (:mod:`qdsega.locomotion.lower_agent`). Reward:
eq. (17), ``reward_scale * (d(t-1) - d(t))`` with ``d`` the distance (m) from the body to the
light, or ``penalty`` when the lower agent fails, which ends the episode. Episodes are truncated
after ``trial_steps`` steps. The physics is deterministic; every episode starts from one
settled snapshot of the start posture.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import gymnasium as gym
import numpy as np

from qdsega.agent.exterior import bin_edges_rad, exterior_state
from qdsega.assembly import assemble
from qdsega.description import Formation
from qdsega.locomotion.body_pose import BodyPose
from qdsega.locomotion.lower_agent import LowerAgent, LowerAgentConfig
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation

SETTLE_S = 0.5
"""Time the start posture is left to settle on the ground before a snapshot is taken (s)."""


@dataclass(frozen=True, kw_only=True)
class TaskConfig:
    """The light-seeking task as the upper agent sees it (paper section 4.1.3).

    Attributes:
        trial_steps: upper-agent steps per trial (episode) (-).
        reward_scale: the 100 of eq. (17), reward per metre gained (1/m).
        penalty: reward of a step whose posture the lower agent failed to reach (-).
        exterior_bin_edges_deg: edges of the bins of the angle to the light (deg); as in
            :mod:`qdsega.agent.exterior`, state 0 is "outside", so there are as many states
            as edges.
    """

    trial_steps: int = 20
    reward_scale: float = 100.0
    penalty: float = -100.0
    exterior_bin_edges_deg: tuple[float, ...] = (-45.0, -15.0, 15.0, 45.0)
    lower_agent: LowerAgentConfig = field(default_factory=LowerAgentConfig)


class LocomotionEnv(gym.Env[np.ndarray, np.ndarray]):
    """Walk toward the light: one formation, one PyBullet world.

    Args:
        formation: the robot and where the light is.
        task: trial length, reward, exterior bins and the lower agent.
        physics: engine settings.
        start_levels: start posture as level indices, shape (J,); default
            ``formation.rest_levels()``.
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 - Gymnasium's convention

    def __init__(
        self,
        *,
        formation: Formation,
        task: TaskConfig | None = None,
        physics: PhysicsSettings | None = None,
        start_levels: tuple[int, ...] | None = None,
    ) -> None:
        self.formation = formation
        self.task = task or TaskConfig()
        if not formation.joints:
            raise ValueError(f"{formation.name} has no actuated joint to command")
        self.start_levels = np.array(start_levels or formation.rest_levels(), dtype=np.int64)
        counts = [len(j.levels_rad) for j in formation.joints]
        n_bins = len(self.task.exterior_bin_edges_deg)
        self.action_space = gym.spaces.MultiDiscrete(counts)
        self.observation_space = gym.spaces.MultiDiscrete([*counts, n_bins])
        self._edges = bin_edges_rad(self.task.exterior_bin_edges_deg)
        self._light = formation.light.position_m
        self.sim = BulletSimulation(robot=assemble(formation), settings=physics)
        self.lower_agent = LowerAgent(sim=self.sim, config=self.task.lower_agent)
        self.sim.reset(formation.posture_rad(self.start_levels))
        self.sim.step(max(1, round(SETTLE_S / self.sim.settings.time_step_s)))
        self._start_state = self.sim.save_state()
        self._posture = self.start_levels.copy()
        self._pose = self.lower_agent.pose()
        self._start_pose = self._pose
        self._steps = 0

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self.sim.restore_state(self._start_state)
        self.sim.command(self.formation.posture_rad(self.start_levels))
        self._posture = self.start_levels.copy()
        self._pose = self._start_pose = self.lower_agent.pose()
        self._steps = 0
        return self._observation(), self._info(None)

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        levels = np.asarray(action, dtype=np.int64)
        if not self.action_space.contains(levels):
            raise ValueError(f"action {action!r} is not in {self.action_space}")
        before = self._distance(self._pose)
        outcome = self.lower_agent.execute(levels)
        self._steps += 1
        self._posture = levels.copy()
        failed = outcome.failed
        if failed:
            reward = self.task.penalty
        else:
            self._pose = outcome.pose
            reward = self.task.reward_scale * (before - self._distance(self._pose))
        truncated = not failed and self._steps >= self.task.trial_steps
        return self._observation(), float(reward), failed, truncated, self._info(outcome.failure)

    def body_pose(self) -> BodyPose:
        """The body's pose after the last successful step (or at the episode's start)."""
        return self._pose

    def distance_covered(self) -> float:
        """Distance toward the light gained since the episode started (m)."""
        return self._distance(self._start_pose) - self._distance(self._pose)

    def close(self) -> None:
        self.sim.close()

    def _distance(self, pose: BodyPose) -> float:
        return math.hypot(self._light[0] - pose.x_m, self._light[1] - pose.y_m)

    def _observation(self) -> np.ndarray:
        exterior = exterior_state(
            self._pose.x_m, self._pose.y_m, self._pose.heading_rad, *self._light, self._edges
        )
        return np.array([*self._posture, exterior], dtype=np.int64)

    def _info(self, failure: str | None) -> dict[str, Any]:
        return {
            "failure": failure,
            "x_m": self._pose.x_m,
            "y_m": self._pose.y_m,
            "heading_rad": self._pose.heading_rad,
            "distance_covered_m": self.distance_covered(),
        }
