"""A Gymnasium environment over a table model: the MSM, or a formation's memo table.

The same task as :class:`qdsega.locomotion.env.LocomotionEnv` (observation: the posture and
the exterior state, ``MultiDiscrete([n_1, ..., n_J, n_bins])``; action: a posture,
``MultiDiscrete([n_1, ..., n_J])``; reward eq. (17), the penalty ending an episode when the
move fails, truncation after ``trial_steps``), but each step is one lookup of the posture pair
in a :class:`qdsega.agent.model.TransitionProvider`: the Minimal Simulation Model (``msm``,
legged formations) or the PyBullet transitions measured once each (``memo``: a pair not yet in
the table is measured on first use, in this process). So a learner other than QDSEGA (PPO, say)
runs at table speed in the same world QDSEGA learns in. The memo world here is the plain
table, keyed by the posture pair alone, without the corrections a training run's grounding adds;
on ground other than the flat plane (``world``) each move is measured from ``spots`` places
along the way to the light, as a training run's table is. Where obstacles stand, the body senses
them and a move into one is lost, by the same rules as training (:mod:`qdsega.task`), and no
move is measured where the body would touch one.

Registered with Gymnasium as ``qdsega/TableLocomotion-v0`` when :mod:`qdsega` is imported::

    env = gymnasium.make("qdsega/TableLocomotion-v0", formation="quadruped", sim="msm")
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from qdsega.agent.model import TransitionProvider
from qdsega.description import Formation, World, load_formation, resolve_formation
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters
from qdsega.task import Pose, Task, TaskConfig

SIMS = ("msm", "memo")
"""The table models this environment walks (``sim``)."""


class TableLocomotionEnv(gym.Env[np.ndarray, np.ndarray]):
    """Walk toward the light in a table model.

    Args:
        formation: a :class:`Formation`, a formation file, or a shipped formation's name.
        sim: ``msm`` or ``memo`` (module docstring).
        task: trial length, reward, penalty and exterior bins.
        msm: the MSM's constants (``sim="msm"``).
        world: the ground memo moves are measured on (default the flat plane; the MSM knows
            no other); its light, if it has one, replaces the formation's.
        spots: places along the way to the light each memo move is measured from, its mean
            kept (:func:`qdsega.locomotion.memo.spots_toward`).
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 - Gymnasium's

    def __init__(
        self,
        *,
        formation: Formation | Path | str,
        sim: str = "msm",
        task: TaskConfig | None = None,
        msm: MSMParameters | None = None,
        world: World | None = None,
        spots: int = 1,
    ) -> None:
        if sim not in SIMS:
            raise ValueError(f"sim must be one of {', '.join(SIMS)}, got {sim!r}")
        world = world or World()
        if sim == "msm" and not world.is_flat:
            raise ValueError(f"the MSM knows no terrain: {world.name} needs sim='memo'")
        if not isinstance(formation, Formation):
            formation = load_formation(resolve_formation(Path(formation)))
        formation = world.lights(formation)
        self.formation = formation
        if sim == "msm":
            self.task = Task(config=task or TaskConfig(), light_xy=formation.light.position_m)
            self.provider: TransitionProvider = MinimalSimulationModel(
                legs=LegLayout.from_formation(formation), params=msm or MSMParameters()
            )
        else:
            self.task, self.provider = _memo(formation, task or TaskConfig(), world, spots)
        levels = [len(joint.levels_rad) for joint in formation.joints]
        self.action_space = gym.spaces.MultiDiscrete(levels)
        self.observation_space = gym.spaces.MultiDiscrete([*levels, self.task.n_exterior])
        self._posture = self.provider.start_posture()
        self._pose: Pose = (0.0, 0.0, 0.0)
        self._steps = 0

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self._posture = self.provider.start_posture()
        self._pose = (0.0, 0.0, 0.0)
        self._steps = 0
        return self._observation(), self._info()

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        levels = np.asarray(action, dtype=np.int64)
        if not self.action_space.contains(levels):
            raise ValueError(f"action {action!r} is not in {self.action_space}")
        move = self.provider.transitions(self._posture[None, :], levels[None, :])
        self._steps += 1
        self._posture = levels.copy()
        self._pose, reward, failed = self.task.move(
            self._pose, move.dx[0, 0], move.dy[0, 0], move.dtheta[0, 0], bool(move.failed[0, 0])
        )
        truncated = not failed and self._steps >= self.task.trial_steps
        return self._observation(), float(reward), failed, truncated, self._info()

    def distance_covered(self) -> float:
        """Distance toward the light gained since the episode started (m)."""
        return self.task.covered((0.0, 0.0, 0.0), self._pose)

    def close(self) -> None:
        close = getattr(self.provider, "close", None)
        if close is not None:
            close()

    def _observation(self) -> np.ndarray:
        return np.array([*self._posture, self.task.exterior(self._pose)], dtype=np.int64)

    def _info(self) -> dict[str, Any]:
        x, y, heading = self._pose
        return {
            "x_m": x,
            "y_m": y,
            "heading_rad": heading,
            "distance_covered_m": self.distance_covered(),
        }


def _memo(
    formation: Formation, config: TaskConfig, world: World, spots: int
) -> tuple[Task, TransitionProvider]:
    """The task with ``world``'s obstacles, and the memo table measured from the ``spots``
    places the body stands clear at."""
    # Imported here: they start PyBullet, which the MSM does not need.
    from qdsega.locomotion.lower_agent import LowerAgentConfig
    from qdsega.locomotion.memo import MeasuredTransitions, clear_spots
    from qdsega.locomotion.surroundings import world_task
    from qdsega.simulation import PhysicsSettings

    physics = PhysicsSettings()
    task = world_task(formation, config, world, physics)
    every, blocked = clear_spots(formation, task=task, physics=physics, world=world, count=spots)
    memo = MeasuredTransitions(
        formation=formation,
        lower_agent=LowerAgentConfig(),
        physics=physics,
        workers=1,
        world=world,
        spots=tuple(spot for spot in every if spot not in blocked),
    )
    return task, memo
