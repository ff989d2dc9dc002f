"""A Gymnasium environment: any formation walks toward the light in PyBullet.

Observation: the current posture (one level index per joint) and the exterior state (the bin of
the angle from the heading to the light), as ``MultiDiscrete([n_1, ..., n_J, n_bins])``.
Action: a posture, ``MultiDiscrete([n_1, ..., n_J])``. One step is one upper-agent step: the
lower agent drives every joint to its level (:mod:`qdsega.locomotion.lower_agent`). Reward,
penalty, exterior state and episode length are the task's (:mod:`qdsega.task`): eq. (17), or
the penalty when the lower agent fails, which ends the episode; episodes are truncated after
``trial_steps`` steps. The physics is deterministic; every episode starts from one settled
snapshot of the start posture.

Poses are in the trial's frame, as the task has them (:mod:`qdsega.locomotion.scene`). Moves
measured here therefore integrate to the same poses in a transition table.

With ``render_mode="rgb_array"``, :meth:`LocomotionEnv.render` returns the picture of a camera
that follows the body, looking toward the light (a yellow sphere on the horizon), rendered
off-screen by pybullet's EGL plugin, or by its TinyRenderer (with a
:class:`~qdsega.errors.QdsegaWarning`) where EGL does not load. Rendering changes nothing in
the physics. ``on_physics_step`` lets a recorder film within a step
(:func:`qdsega.analysis.recorder.record`).

Registered with Gymnasium as ``qdsega/Locomotion-v0`` when :mod:`qdsega` is imported::

    env = gymnasium.make("qdsega/Locomotion-v0", formation="snake5", render_mode="rgb_array")
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from qdsega.description import Formation, World
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.rules import ExactRules
from qdsega.locomotion.scene import Scene, lit
from qdsega.locomotion.surroundings import world_task
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.camera import CameraConfig
from qdsega.task import Pose, TaskConfig


class LocomotionEnv(gym.Env[np.ndarray, np.ndarray]):
    """Walk toward the light: one formation, one PyBullet world.

    Args:
        formation: the robot and where the light is: a :class:`Formation`, a formation file,
            or the name of a shipped one (``"snake5"``).
        task: trial length, reward, penalty and exterior bins.
        lower_agent: how postures are executed and when that fails.
        physics: engine settings.
        start_levels: start posture as level indices, shape (J,); default
            ``formation.rest_levels()``.
        render_mode: None, or ``"rgb_array"`` for :meth:`render`.
        camera: picture size and camera placement for :meth:`render` (its ``fps`` is the
            recorder's); default :class:`CameraConfig`.
        world: the ground and what stands on it: a :class:`World`, a world file or the name
            of a shipped one (``"stairs"``); its light, if it has one, replaces the
            formation's; default the flat plane.
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"]}  # noqa: RUF012 - Gymnasium's

    def __init__(
        self,
        *,
        formation: Formation | Path | str,
        task: TaskConfig | None = None,
        lower_agent: LowerAgentConfig | None = None,
        physics: PhysicsSettings | None = None,
        start_levels: tuple[int, ...] | None = None,
        render_mode: str | None = None,
        camera: CameraConfig | None = None,
        world: World | Path | str | None = None,
    ) -> None:
        formation, self.world = lit(formation, world)
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.formation = formation
        self.render_mode = render_mode
        self.camera = camera or CameraConfig()
        physics = physics or PhysicsSettings()
        self.task = world_task(formation, task or TaskConfig(), self.world, physics)
        if not formation.joints:
            raise ValueError(f"{formation.name} has no actuated joint to command")
        self.start_levels = np.array(start_levels or formation.rest_levels(), dtype=np.int64)
        counts = [len(j.levels_rad) for j in formation.joints]
        self.action_space = gym.spaces.MultiDiscrete(counts)
        self.observation_space = gym.spaces.MultiDiscrete([*counts, self.task.n_exterior])
        self.scene = Scene(
            formation=formation,
            world=self.world,
            lower_agent=lower_agent or LowerAgentConfig(),
            physics=physics,
            start_rad=np.array(formation.posture_rad(self.start_levels)),
            pictures=render_mode is not None,
        )
        self.sim = self.scene.sim
        self.lower_agent = self.scene.lower_agent
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.lower_agent.step_duration_s}
        self._posture = self.start_levels.copy()
        self._pose: Pose = (0.0, 0.0, 0.0)
        self._steps = 0
        self._contacts: list[np.ndarray] = []
        self.on_physics_step: Callable[[], None] | None = None
        """Called after every physics step of :meth:`step`, if set (to film within a step)."""

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self.scene.restart()
        self._posture = self.start_levels.copy()
        self._pose = (0.0, 0.0, 0.0)
        self._steps = 0
        self._contacts = []
        return self._observation(), self._info(None)

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        levels = np.asarray(action, dtype=np.int64)
        if not self.action_space.contains(levels):
            raise ValueError(f"action {action!r} is not in {self.action_space}")
        before = self._pose
        outcome = self.lower_agent.execute(levels, on_physics_step=self.on_physics_step)
        self._steps += 1
        self._contacts.append(outcome.contacts)
        self._posture = levels.copy()
        failed = outcome.failed
        if failed:
            reward = self.task.penalty
        else:
            self._pose = self.scene.trial_pose(outcome.pose)
            reward = self.task.reward(before, self._pose)
        truncated = not failed and self._steps >= self.task.trial_steps
        return self._observation(), float(reward), failed, truncated, self._info(outcome.failure)

    def pose(self) -> Pose:
        """The body's pose in the trial's frame after the last successful step (or at the
        episode's start): x (m), y (m), heading (rad)."""
        return self._pose

    def distance_covered(self) -> float:
        """Distance toward the light gained since the episode started (m)."""
        return self.task.covered((0.0, 0.0, 0.0), self._pose)

    def contacts(self) -> np.ndarray:
        """Which units touched the ground at each failure check of the episode so far,
        (checks, units) bool, units in the formation's order."""
        units = len(self.formation.units)
        return np.concatenate([np.empty((0, units), dtype=bool), *self._contacts])

    def render(self) -> np.ndarray | None:
        """The camera's picture now, (height, width, 3) uint8, with ``render_mode`` set to
        ``"rgb_array"``; None without a render mode."""
        if self.render_mode is None:
            return None
        return self.scene.picture(self.camera)

    def close(self) -> None:
        self.scene.close()

    def _observation(self) -> np.ndarray:
        exterior = self.task.exterior(self._pose)
        return np.array([*self._posture, exterior], dtype=np.int64)

    def _info(self, failure: str | None) -> dict[str, Any]:
        return {
            "failure": failure,
            "x_m": self._pose[0],
            "y_m": self._pose[1],
            "heading_rad": self._pose[2],
            "distance_covered_m": self.distance_covered(),
        }


def rules_env(
    formation: Formation, rules: ExactRules, *, camera: CameraConfig | None = None
) -> LocomotionEnv:
    """The exact-physics environment of ``formation`` under ``rules``; rendering through
    ``camera`` when given."""
    return LocomotionEnv(
        formation=formation,
        task=rules.task,
        lower_agent=rules.lower_agent,
        physics=rules.physics,
        render_mode=None if camera is None else "rgb_array",
        camera=camera,
        world=rules.world,
    )


@dataclass(frozen=True)
class Replay:
    """A fixed posture sequence played from the start of an episode.

    Attributes:
        distance_m: distance toward the light covered (m).
        completed: postures reached before the sequence ended or the lower agent failed.
        failure: why the lower agent failed, or None.
    """

    distance_m: float
    completed: int
    failure: str | None


def replay_postures(env: LocomotionEnv, postures: np.ndarray) -> Replay:
    """Play ``postures`` (steps, J) of level indices from a reset, at most one episode."""
    env.reset(seed=0)
    completed = 0
    for posture in postures:
        _, _, terminated, truncated, info = env.step(posture)
        if terminated:
            return Replay(env.distance_covered(), completed, info["failure"])
        completed += 1
        if truncated:
            break
    return Replay(env.distance_covered(), completed, None)
