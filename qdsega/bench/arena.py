"""Where the sequence methods play their trials: the MSM, or exact PyBullet.

An arena plays open-loop posture sequences, one trial each, and counts the upper-agent steps it
simulated (``commands``), the budget every method of a task spends. In the MSM a batch of
sequences is played at once, pair by pair through the model's own equations
(:meth:`qdsega.msm.MinimalSimulationModel.moves`); in PyBullet it is
:class:`qdsega.locomotion.exact_trials.ExactTrials`, the trials evaluation runs.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np
from numba import njit

from qdsega.locomotion.env import Replay
from qdsega.msm import MinimalSimulationModel
from qdsega.task import Task, move_pose


class Arena(Protocol):
    """Plays posture sequences (trial_steps, J) of level indices, one trial each."""

    commands: int
    """Upper-agent steps simulated so far."""

    def replays(self, postures: Sequence[np.ndarray]) -> list[Replay]: ...

    def close(self) -> None: ...


class MSMArena:
    """Trials in the Minimal Simulation Model, from its start posture.

    Args:
        model: the model.
        task: the rules (light, trial length).
    """

    def __init__(self, *, model: MinimalSimulationModel, task: Task) -> None:
        self.model = model
        self.task = task
        self.commands = 0

    def replays(self, postures: Sequence[np.ndarray]) -> list[Replay]:
        """Each sequence played as one trial: a fall ends it (no move on that step)."""
        if len(postures) == 0:
            return []
        after = np.asarray(np.stack(postures), dtype=np.int64)  # (B, T, J)
        start = np.broadcast_to(self.model.start_posture(), after[:, :1].shape)
        before = np.concatenate([start, after[:, :-1]], axis=1)
        dx, dtheta, failed = self.model.moves(before, after)
        poses, completed, fell = _walk(dx, dtheta, failed)
        self.commands += int(np.sum(completed + fell))
        origin = (0.0, 0.0, 0.0)
        return [
            Replay(self.task.covered(origin, tuple(pose)), int(done), "fell" if f else None)
            for pose, done, f in zip(poses, completed, fell, strict=True)
        ]

    def close(self) -> None:
        """Nothing to release."""


@njit(cache=True)
def _walk(
    dx: np.ndarray, dtheta: np.ndarray, failed: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Integrate body-frame moves (B, T) from the origin until the first failed step:
    final poses (B, 3), steps completed (B,), whether a step failed (B,)."""
    trials, steps = dx.shape
    poses = np.zeros((trials, 3))
    completed = np.zeros(trials, dtype=np.int64)
    fell = np.zeros(trials, dtype=np.bool_)
    for b in range(trials):
        x, y, theta = 0.0, 0.0, 0.0
        for t in range(steps):
            if failed[b, t]:
                fell[b] = True
                break
            x, y, theta = move_pose(x, y, theta, dx[b, t], 0.0, dtheta[b, t])
            completed[b] += 1
        poses[b, 0], poses[b, 1], poses[b, 2] = x, y, theta
    return poses, completed, fell
