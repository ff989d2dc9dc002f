"""A transition table walked one command at a time: the step-by-step view of a table model.

The compiled learning loop walks the table itself; this class lets everything that runs trials
one command at a time (:func:`qdsega.agent.policy.rollout`, the Python learning loop) walk the
same table under the same rules (:class:`qdsega.task.Task`).
"""

from __future__ import annotations

import numpy as np

from qdsega.agent.model import StepResult, Transitions
from qdsega.agent.space import ExplorationSpace
from qdsega.task import Pose, Task


class TableModel:
    """A :class:`qdsega.agent.model.World` over one generation's transition table.

    Args:
        space: the generation's actions and interior states.
        table: outcomes of every action from every interior state, shape (n_interior, A).
        task: the rules.
    """

    def __init__(self, *, space: ExplorationSpace, table: Transitions, task: Task) -> None:
        if np.shape(table.dx) != (space.n_interior, space.n_actions):
            raise ValueError(
                f"table {np.shape(table.dx)} does not fit the space "
                f"({space.n_interior}, {space.n_actions})"
            )
        self.space = space
        self.table = table
        self.task = task
        self._action = {row.tobytes(): a for a, row in enumerate(space.actions)}
        self._previous, self._interior, self._node = -1, 0, 0
        self._pose: Pose = (0.0, 0.0, 0.0)

    @property
    def n_joints(self) -> int:
        return self.space.actions.shape[1]

    def start_posture(self) -> np.ndarray:
        return self.space.postures[0].copy()

    def start_trial(self) -> int:
        self._previous, self._interior, self._node = -1, 0, 0
        self._pose = (0.0, 0.0, 0.0)
        return self.task.exterior(self._pose)

    def command(self, posture: np.ndarray) -> StepResult:
        a = self._action[np.asarray(posture, dtype=np.int64).tobytes()]
        dx, dy, dtheta, failed, self._node = self.table.move(
            self._node, self._previous, self._interior, a
        )
        self._pose, reward, failed = self.task.move(self._pose, dx, dy, dtheta, failed)
        if not failed:
            self._previous, self._interior = self._interior, int(self.space.next_interior[a])
        return StepResult(reward, self.task.exterior(self._pose), failed)

    def distance_covered(self) -> float:
        return self.task.covered((0.0, 0.0, 0.0), self._pose)

    def pose(self) -> Pose:
        return self._pose
