"""A continuous-control Gymnasium environment: any formation walks toward the light in
PyBullet, its joints driven to targets an agent sets at every step.

Action: one number in [-1, 1] per joint, scaled to the joint's limits (-1 its lower, 1 its
upper limit; values outside are clipped), held as the joint's position target for one step.
The joints move toward their targets as the lower agent moves them: at most at its joint speed
(1.5 rad/s, the paper's stepping motors) and at most at each unit's torque.

Observation, ``Box`` of 2 J + 11 float32:

* the joint angles (rad), then their angular velocities (rad/s), J each;
* gravity's direction in the root unit's frame (3, a unit vector): the body's roll and pitch;
* the root unit's linear velocity (m/s) and angular velocity (rad/s) in its own frame, 3 each;
* the sine and cosine of the light's bearing: the angle from the body's heading to the light
  (:meth:`qdsega.task.Task.bearing`, what the discrete envs' exterior state bins).

One step is ``physics_steps_per_step`` physics steps: a posture step of the lower agent split
into :data:`~qdsega.locomotion.CONTROLS_PER_POSTURE` (12) parts, 10 physics steps (1/24 s) for
the shipped formations. An episode lasts ``trial_steps`` posture steps' physics time, as a
QDSEGA trial does: 360 steps, 3600 physics steps (15 s), truncated then.

Reward: eq. (17) of the task (:mod:`qdsega.task`) for the step's progress toward the light, so
that an episode's return is ``reward_per_m`` times the distance it covered. The episode ends
(``terminated``), with the task's penalty as its last reward, where the lower agent would fail
it too, at the same checks (:meth:`qdsega.locomotion.lower_agent.LowerAgent.check`): the body
flipped, a legged body's trunk touched the ground, or the physics state became non-finite
(its observation then reads 0 where it is not finite); ``info["failure"]`` says which. A
joint's arrival is not judged: targets are the agent's to move at any time. Poses are in the
trial's frame (:mod:`qdsega.locomotion.scene`).

Rendering: ``"rgb_array"`` as in :mod:`qdsega.locomotion.env`; ``"human"`` opens PyBullet's
window, its camera following the body, and plays the episode at real speed. Where there is no
display (Linux without ``DISPLAY``), it says so in one :class:`~qdsega.errors.QdsegaWarning`
and runs as without a render mode.

Registered with Gymnasium as ``qdsega/JointLocomotion-v0`` when :mod:`qdsega` is imported::

    env = gymnasium.make("qdsega/JointLocomotion-v0", formation="snake5", world="slope")
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from trimesh.transformations import quaternion_matrix

from qdsega.description import Formation, World
from qdsega.locomotion import CONTROLS_PER_POSTURE
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.scene import Scene, lit
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.camera import CameraConfig
from qdsega.task import Pose, Task, TaskConfig

BODY_STATE = 11
"""Observed numbers besides the joints' (-): gravity (3), linear (3) and angular velocity (3),
the light's bearing (2)."""


class JointLocomotionEnv(gym.Env[np.ndarray, np.ndarray]):
    """Walk toward the light under continuous control: one formation, one PyBullet world.

    Args:
        formation: the robot and where the light is: a :class:`Formation`, a formation file,
            or the name of a shipped one (``"snake5"``).
        task: trial length (the episode's physics time), reward scale, penalty.
        lower_agent: the joints' speed, the posture step's duration (the episode's clock) and
            when the body has failed.
        physics: engine settings.
        render_mode: None, ``"rgb_array"`` for :meth:`render`, or ``"human"`` for PyBullet's
            window.
        camera: picture size and camera placement for :meth:`render`, or the window's camera
            placement; default :class:`CameraConfig`.
        world: the ground and what stands on it: a :class:`World`, a world file or the name of
            a shipped one (``"slope"``); its light, if it has one, replaces the formation's;
            default the flat plane.
    """

    metadata: dict[str, Any] = {"render_modes": ["human", "rgb_array"]}  # noqa: RUF012

    def __init__(
        self,
        *,
        formation: Formation | Path | str,
        task: TaskConfig | None = None,
        lower_agent: LowerAgentConfig | None = None,
        physics: PhysicsSettings | None = None,
        render_mode: str | None = None,
        camera: CameraConfig | None = None,
        world: World | Path | str | None = None,
    ) -> None:
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(
                f"render_mode must be None, 'human' or 'rgb_array', got {render_mode!r}"
            )
        formation, self.world = lit(formation, world)
        if not formation.joints:
            raise ValueError(f"{formation.name} has no actuated joint to command")
        self.formation = formation
        self.render_mode = render_mode
        self.camera = camera or CameraConfig()
        self.task = Task(config=task or TaskConfig(), light_xy=formation.light.position_m)
        self.scene = Scene(
            formation=formation,
            world=self.world,
            lower_agent=lower_agent or LowerAgentConfig(),
            physics=physics or PhysicsSettings(),
            start_rad=np.array(formation.posture_rad(formation.rest_levels())),
            pictures=render_mode == "rgb_array",
            window=render_mode == "human",
        )
        self.sim = self.scene.sim
        self.lower_agent = self.scene.lower_agent
        self.physics_steps_per_step = max(
            1, round(self.lower_agent.physics_steps / CONTROLS_PER_POSTURE)
        )
        """Physics steps one step holds the joint targets for (-)."""
        self.dt = self.physics_steps_per_step * self.sim.settings.time_step_s
        """Simulated time of one step (s)."""
        self.episode_steps = self.task.trial_steps * CONTROLS_PER_POSTURE
        """Steps after which an episode is truncated: a trial's physics time (-)."""
        self.metadata = {**self.metadata, "render_fps": 1.0 / self.dt}
        joints = len(formation.joints)
        self._lower = np.array([j.spec.lower_rad for j in formation.joints])
        self._upper = np.array([j.spec.upper_rad for j in formation.joints])
        self.action_space = gym.spaces.Box(-1.0, 1.0, shape=(joints,), dtype=np.float32)
        self.observation_space = gym.spaces.Box(
            -np.inf, np.inf, shape=(2 * joints + BODY_STATE,), dtype=np.float32
        )
        self._pose: Pose = (0.0, 0.0, 0.0)
        self._steps = 0
        self._shown_at = 0.0

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self.scene.restart()
        self._pose = (0.0, 0.0, 0.0)
        self._steps = 0
        if self.render_mode == "human":
            self._show()
        return self._observation(), self._info(None)

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        share = np.asarray(action, dtype=np.float64)
        if share.shape != self.action_space.shape or not np.all(np.isfinite(share)):
            raise ValueError(f"action must be {self.action_space.shape} finite, got {action!r}")
        share = (np.clip(share, -1.0, 1.0) + 1.0) / 2.0
        targets = self._lower + share * (self._upper - self._lower)
        self.sim.command(targets, speed_rad_s=self.lower_agent.config.joint_speed_rad_s)
        self.sim.step(self.physics_steps_per_step)
        pose, failure = self.lower_agent.check([])  # the footfalls are not kept
        self._steps += 1
        if failure is None:
            before, self._pose = self._pose, self.scene.trial_pose(pose)
            reward = self.task.reward(before, self._pose)
        else:
            reward = self.task.penalty
        truncated = failure is None and self._steps >= self.episode_steps
        if self.render_mode == "human":
            self._show()
        terminated = failure is not None
        return self._observation(), float(reward), terminated, truncated, self._info(failure)

    def pose(self) -> Pose:
        """The body's pose in the trial's frame after the last step that did not fail (or at
        the episode's start): x (m), y (m), heading (rad)."""
        return self._pose

    def distance_covered(self) -> float:
        """Distance toward the light gained since the episode started (m)."""
        return self.task.covered((0.0, 0.0, 0.0), self._pose)

    def render(self) -> np.ndarray | None:
        """The camera's picture now, (height, width, 3) uint8, with ``render_mode`` set to
        ``"rgb_array"``; None otherwise (the window shows every step by itself)."""
        if self.render_mode != "rgb_array":
            return None
        return self.scene.picture(self.camera)

    def close(self) -> None:
        self.scene.close()

    def _show(self) -> None:
        """Follow the body with the window's camera, one step's time after the last view."""
        if not self.sim.window:
            return
        self.scene.aim_window(self.camera)
        time.sleep(max(0.0, self._shown_at + self.dt - time.monotonic()))
        self._shown_at = time.monotonic()

    def _observation(self) -> np.ndarray:
        angles, speeds = self.sim.joint_states()
        _, quaternion = self.sim.base_pose()
        linear, angular = self.sim.base_velocity()
        x, y, z, w = quaternion
        body_from_world = quaternion_matrix([w, x, y, z])[:3, :3].T
        bearing = self.task.bearing(self._pose)
        observation = np.concatenate(
            [
                angles,
                speeds,
                body_from_world @ np.array([0.0, 0.0, -1.0]),
                body_from_world @ linear,
                body_from_world @ angular,
                [np.sin(bearing), np.cos(bearing)],
            ]
        )
        return np.nan_to_num(observation, nan=0.0, posinf=0.0, neginf=0.0).astype(np.float32)

    def _info(self, failure: str | None) -> dict[str, Any]:
        return {
            "failure": failure,
            "x_m": self._pose[0],
            "y_m": self._pose[1],
            "heading_rad": self._pose[2],
            "distance_covered_m": self.distance_covered(),
        }
