"""A transition table grounded in exact trials: measured moves corrected by observed ones.

A table measures each transition ``i -> j`` once, from a settled start in ``i``. A body whose
step depends on more than its posture (a snake's momentum, the friction it has built up)
moves differently inside a trial. :class:`GroundedTransitions` keeps, for every transition an
exact trial went through, the moves observed there, and answers with their mean instead of the
table's measurement (Dyna-style: the learner plans on a model, and the model is corrected where
the learner's policies actually go). A transition observed to fail more often than not fails.
"""

from __future__ import annotations

import numpy as np

from qdsega.agent.policy import Rollout
from qdsega.agent.world import TransitionProvider, Transitions
from qdsega.task import relative_move


class GroundedTransitions:
    """A :class:`qdsega.agent.world.TransitionProvider`: ``base`` corrected by observations.

    Args:
        base: the table of measured transitions.
    """

    def __init__(self, *, base: TransitionProvider) -> None:
        self.base = base
        # key (from + to levels as bytes) -> [sum dx, sum dy, sum dtheta, moves, failures]
        self._observed: dict[bytes, np.ndarray] = {}

    @property
    def n_joints(self) -> int:
        return self.base.n_joints

    def start_posture(self) -> np.ndarray:
        return self.base.start_posture()

    def __len__(self) -> int:
        """Transitions observed at least once."""
        return len(self._observed)

    def transitions(self, from_postures: np.ndarray, to_postures: np.ndarray) -> Transitions:
        """The base table's outcomes, observed means where a transition was observed."""
        table = self.base.transitions(from_postures, to_postures)
        if not self._observed:
            return table
        dx, dy, dtheta = (np.array(a, dtype=np.float64) for a in (table.dx, table.dy, table.dtheta))
        failed = np.array(table.failed, dtype=np.bool_)
        sources = np.asarray(from_postures, dtype=np.int64)
        targets = np.asarray(to_postures, dtype=np.int64)
        for i, source in enumerate(sources):
            for j, target in enumerate(targets):
                row = self._observed.get(_key(source, target))
                if row is None:
                    continue
                moves, failures = row[3], row[4]
                failed[i, j] = failures > moves
                if moves > 0:
                    dx[i, j], dy[i, j], dtheta[i, j] = row[:3] / moves
        return Transitions(dx=dx, dy=dy, dtheta=dtheta, failed=failed)

    def observe(self, trial: Rollout, start: np.ndarray) -> int:
        """Record the moves of an exact trial that started in posture ``start`` (J,); returns
        the transitions it went through."""
        reached = trial.reached_postures(start)
        steps = len(reached) - 1
        for t in range(steps):
            move = relative_move(tuple(trial.poses[t]), tuple(trial.poses[t + 1]))
            self._row(reached[t], reached[t + 1])[:4] += (*move, 1.0)
        if trial.failed:
            self._row(reached[-1], trial.postures[-1])[4] += 1.0
            steps += 1
        return steps

    def state(self) -> dict[str, np.ndarray]:
        """The observations as arrays (for a checkpoint): ``pairs`` (n, 2J) levels and
        ``sums`` (n, 5): summed dx (m), dy (m), dtheta (rad), moves and failures."""
        keys = sorted(self._observed)
        pairs = np.array([np.frombuffer(k, dtype=np.int64) for k in keys], dtype=np.int64)
        sums = np.array([self._observed[k] for k in keys], dtype=np.float64)
        return {
            "pairs": pairs.reshape(len(keys), 2 * self.n_joints),
            "sums": sums.reshape(len(keys), 5),
        }

    def restore(self, state: dict[str, np.ndarray]) -> None:
        """Replace the observations with those of :meth:`state`.

        Raises:
            ValueError: the arrays do not fit this body.
        """
        pairs, sums = state["pairs"], state["sums"]
        if pairs.shape[1:] != (2 * self.n_joints,) or sums.shape != (len(pairs), 5):
            raise ValueError(
                f"observations {pairs.shape}, {sums.shape} do not fit {self.n_joints} joints"
            )
        self._observed = {
            pair.astype(np.int64).tobytes(): row.astype(np.float64).copy()
            for pair, row in zip(pairs, sums, strict=True)
        }

    def _row(self, source: np.ndarray, target: np.ndarray) -> np.ndarray:
        return self._observed.setdefault(_key(source, target), np.zeros(5))


def _key(source: np.ndarray, target: np.ndarray) -> bytes:
    return np.concatenate([source, target]).astype(np.int64).tobytes()
