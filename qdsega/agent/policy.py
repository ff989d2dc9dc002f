"""The greedy policy of a learnt Q-table, and the one function that runs it in any model.

Training (each generation's greedy trial on the table and its replay in exact physics),
evaluation and rendering all replay a policy through :func:`rollout`, so they see the same
trial: the same tie rule, the same interior-state bookkeeping, the same end of the trial.
"""

from __future__ import annotations

import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np

from qdsega.agent.boltzmann import boltzmann_select, greedy
from qdsega.agent.model import StepModel
from qdsega.agent.space import ExplorationSpace
from qdsega.atomic import replaced_atomically

_ARRAYS = ("q", "actions", "postures", "next_interior")


@dataclass(frozen=True)
class GreedyPolicy:
    """Take the action of largest Q(s, .) (ties: the first) in state ``s``.

    Attributes:
        q: the Q-table, shape (n_interior * n_exterior, A); row ``interior * n_exterior +
            exterior``.
        actions: the action postures (level indices), shape (A, J).
        postures: interior-state postures, the start posture first, shape (n_interior, J).
        next_interior: interior state each action leads to, shape (A,).
    """

    q: np.ndarray
    actions: np.ndarray
    postures: np.ndarray
    next_interior: np.ndarray

    def __post_init__(self) -> None:
        n_actions = len(self.actions)
        if self.q.ndim != 2 or self.q.shape[1] != n_actions or n_actions == 0:
            raise ValueError(f"q {self.q.shape} does not fit {n_actions} actions")
        if len(self.postures) == 0 or self.q.shape[0] % len(self.postures):
            raise ValueError(f"q has {self.q.shape[0]} rows for {len(self.postures)} postures")
        if self.next_interior.shape != (n_actions,):
            raise ValueError(f"next_interior {self.next_interior.shape} != ({n_actions},)")

    @classmethod
    def of(cls, space: ExplorationSpace, q: np.ndarray) -> GreedyPolicy:
        """The greedy policy of ``q`` over a generation's ``space``."""
        return cls(
            q=q, actions=space.actions, postures=space.postures, next_interior=space.next_interior
        )

    @property
    def n_exterior(self) -> int:
        return self.q.shape[0] // len(self.postures)

    def act(self, interior: int, exterior: int) -> int:
        """The action index to take in (interior, exterior)."""
        return int(greedy(self.q[interior * self.n_exterior + exterior]))

    def save(self, file: Path) -> None:
        """Write ``file`` (npz: q, actions, postures, next_interior), atomically."""
        with replaced_atomically(file) as partial:
            np.savez_compressed(partial, **{name: getattr(self, name) for name in _ARRAYS})

    @classmethod
    def load(cls, file: Path) -> GreedyPolicy:
        """Read a policy written by :meth:`save`.

        Raises:
            ValueError: the file is missing, unreadable or not a policy.
        """
        try:
            with np.load(file) as stored:
                return cls(**{name: stored[name] for name in _ARRAYS})
        except (OSError, KeyError, zipfile.BadZipFile) as exc:
            raise ValueError(f"{exc.__class__.__name__}: {exc}") from None


class Policy(Protocol):
    """Chooses an action index in (interior, exterior) over ``actions`` (A, J)."""

    # read-only members, so that a frozen GreedyPolicy is a Policy too
    @property
    def actions(self) -> np.ndarray: ...

    @property
    def next_interior(self) -> np.ndarray: ...

    def act(self, interior: int, exterior: int) -> int: ...


class BoltzmannPolicy:
    """Draw actions from eq. (18)'s distribution over a greedy policy's Q-table.

    Args:
        greedy: the Q-table and its space.
        temperature: T of the Boltzmann distribution (reward units).
        rng: the source of the draws (one uniform per action).
    """

    def __init__(
        self, *, greedy: GreedyPolicy, temperature: float, rng: np.random.Generator
    ) -> None:
        if not temperature > 0:
            raise ValueError(f"temperature must be positive, got {temperature}")
        self.greedy = greedy
        self.actions = greedy.actions
        self.next_interior = greedy.next_interior
        self.temperature = temperature
        self.rng = rng
        self._weights = np.empty(len(greedy.actions))

    def act(self, interior: int, exterior: int) -> int:
        row = self.greedy.q[interior * self.greedy.n_exterior + exterior]
        return int(boltzmann_select(row, self.temperature, self.rng.random(), self._weights))


class SequencePolicy:
    """Command a fixed posture sequence in turn, whatever the state (an open-loop gait).

    Args:
        commands: the postures (level indices) to command, in order, shape (k, J), started
            again from the first after the last. A policy plays one trial: make one per trial.
        space: a generation's actions and interior states to play the sequence over (the
            trial's actions and interior states are then that space's); None: the distinct
            commands are the actions, and there are no interior states.

    Raises:
        ValueError: ``commands`` is empty, or holds a posture that is not an action of
            ``space``.
    """

    def __init__(self, *, commands: np.ndarray, space: ExplorationSpace | None = None) -> None:
        commands = np.asarray(commands, dtype=np.int64)
        if commands.ndim != 2 or len(commands) == 0:
            raise ValueError(f"commands must be (k >= 1, J), got {commands.shape}")
        if space is None:
            self.actions, order = np.unique(commands, axis=0, return_inverse=True)
            self.next_interior = np.zeros(len(self.actions), dtype=np.int64)  # no states
            self._order = order.reshape(-1)
        else:
            index = {row.tobytes(): a for a, row in enumerate(space.actions)}
            missing = [row for row in commands if row.tobytes() not in index]
            if missing:
                raise ValueError(f"posture {missing[0].tolist()} is not an action of the space")
            self.actions, self.next_interior = space.actions, space.next_interior
            self._order = np.array([index[row.tobytes()] for row in commands], dtype=np.int64)
        self._sent = 0

    def act(self, interior: int, exterior: int) -> int:
        a = int(self._order[self._sent % len(self._order)])
        self._sent += 1
        return a


@dataclass(frozen=True)
class Rollout:
    """One trial of a policy.

    Attributes:
        actions: the action taken at each step, -1 after the trial ended, shape (steps,).
        postures: the commanded postures, in order, shape (k, J), k <= steps (a failed
            command included as the last row).
        poses: the world pose (x m, y m, theta rad) before each step and after the last, rows
            after the end repeating the last pose, shape (steps + 1, 3).
        failed: whether the trial ended because the lower agent failed.
        distance_m: distance toward the light covered (m).
        failure: why it failed, where the model said (exact physics does), else None.
    """

    actions: np.ndarray
    postures: np.ndarray
    poses: np.ndarray
    failed: bool
    distance_m: float
    failure: str | None = None

    def reached_postures(self, start: np.ndarray) -> np.ndarray:
        """The postures the robot was in, the start posture first, shape (k' + 1, J): a failed
        last command is not reached."""
        reached = self.postures[:-1] if self.failed else self.postures
        return np.vstack([np.asarray(start)[None, :], reached])


def rollout(
    policy: Policy,
    model: StepModel,
    *,
    steps: int,
    record: Callable[[], None] | None = None,
) -> Rollout:
    """Run one trial of ``policy`` in ``model`` for ``steps`` commands or until it fails.

    ``record``, if given, is called once the trial has started and after every command (to
    keep whatever else the model can tell)."""
    taken = np.full(steps, -1, dtype=np.int64)
    poses = np.zeros((steps + 1, 3))
    commanded = []
    exterior = model.start_trial()
    poses[0] = model.pose()
    if record is not None:
        record()
    interior, failed, failure = 0, False, None
    for step in range(steps):
        if not failed:
            a = policy.act(interior, exterior)
            taken[step] = a
            commanded.append(policy.actions[a])
            result = model.command(policy.actions[a])
            failed, failure = result.failed, result.failure
            interior, exterior = int(policy.next_interior[a]), result.exterior
            if record is not None:
                record()
        poses[step + 1] = model.pose()
    postures = np.array(commanded, dtype=np.int64).reshape(-1, policy.actions.shape[1])
    return Rollout(taken, postures, poses, failed, model.distance_covered(), failure)
