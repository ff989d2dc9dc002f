"""How the agent models its surroundings: posture-transition tables, and a step-by-step interface.

The upper agent (section 3.2.2) commands postures; a lower agent drives the joints there or
fails. Two kinds of model (the terrain itself is a world, :mod:`qdsega.description.world`):

* A **transition table** (:class:`TransitionProvider`): the outcome of commanding posture ``j``
  from posture ``i`` does not depend on where the robot is, so it is a table of body-frame
  moves ``(dx, dy, dtheta, failed)``, optionally refined by the posture ``h`` the robot came
  from (a moving body carries its last move into the next) and by whole trials remembered
  command by command (:class:`Paths`). The Minimal Simulation Model is one (analytic), a
  simulator measured once per transition is another. The compiled learning loop runs on it.
* A **step-by-step model** (:class:`StepModel`): anything else; the plain Python loop runs on it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np


@dataclass(frozen=True)
class Paths:
    """Trials remembered move by move: a tree of the commands sent since a trial's start.

    Deterministic physics moves a robot the same way whenever it is sent down the same
    sequence of commands from the start of a trial, so a walk through the table that follows a
    remembered trial moves exactly as that trial did, however the same postures moved in other
    trials.

    Attributes:
        child: ``child[k, a]``: the node reached by commanding target column ``a`` at node
            ``k``, or -1; node 0 is the start of a trial; shape (N, m).
        dx, dy, dtheta: the move into each node, in the body frame at its start, shape (N,)
            (m, m, rad); node 0's are unused.
        failed: the command into each node failed (its trial ended there), shape (N,).
    """

    child: np.ndarray
    dx: np.ndarray
    dy: np.ndarray
    dtheta: np.ndarray
    failed: np.ndarray

    def __post_init__(self) -> None:
        n = len(self.child)
        if np.ndim(self.child) != 2 or n < 1:
            raise ValueError(f"child must be (N >= 1, m), got {np.shape(self.child)}")
        for name in ("dx", "dy", "dtheta", "failed"):
            if np.shape(getattr(self, name)) != (n,):
                raise ValueError(f"{name} has shape {np.shape(getattr(self, name))}, not ({n},)")
        if np.any(self.child >= n) or np.any(self.child < -1) or np.any(self.child == 0):
            raise ValueError(f"child nodes must be -1 or 1 .. {n - 1}")

    @classmethod
    def none(cls, targets: int) -> Paths:
        """No remembered trial: a start node without children."""
        zeros = np.zeros(1)
        return cls(np.full((1, targets), -1, dtype=np.int64), zeros, zeros, zeros, zeros > 0)


CompiledTable = tuple[
    np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
    np.ndarray, np.ndarray, np.ndarray, np.ndarray,
    np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
]  # fmt: skip
"""The 14 arrays of :meth:`Transitions.compiled`, in the compiled loop's argument order."""


@dataclass(frozen=True)
class Transitions:
    """Body-frame outcome of commanding each ``to`` posture from each ``from`` posture.

    Attributes:
        dx: forward displacement in the body frame at the start of the move, shape (n, m) (m).
        dy: leftward displacement in that frame, shape (n, m) (m).
        dtheta: heading change, counter-clockwise, shape (n, m) (rad).
        failed: the lower agent could not reach the posture (the robot fell), shape (n, m).
        context: where the outcome also depends on the posture the robot just came from:
            ``context[h, i]`` is the row of ``in_context`` that holds the outcomes of the moves
            from ``from`` posture ``i`` reached from ``from`` posture ``h`` (``h = n``: ``i``
            is where the trial started), or -1 where the plain row ``i`` holds; shape
            (n + 1, n), or None for none.
        in_context: those rows, shape (R, m) (a table of its own, without context).
        paths: remembered trials over these targets, which rule wherever a walk from the
            start of a trial follows one (``from`` row 0 is where trials start); None for none.
    """

    dx: np.ndarray
    dy: np.ndarray
    dtheta: np.ndarray
    failed: np.ndarray
    context: np.ndarray | None = None
    in_context: Transitions | None = None
    paths: Paths | None = None

    def __post_init__(self) -> None:
        shape = np.shape(self.dx)
        if len(shape) != 2:
            raise ValueError(f"transitions are (n, m) tables, got shape {shape}")
        for name in ("dy", "dtheta", "failed"):
            if np.shape(getattr(self, name)) != shape:
                raise ValueError(f"{name} has shape {np.shape(getattr(self, name))}, not {shape}")
        if (self.context is None) != (self.in_context is None):
            raise ValueError("context and in_context come together")
        if self.context is not None and self.in_context is not None:
            rows = len(self.in_context.dx)
            if np.shape(self.context) != (shape[0] + 1, shape[0]):
                raise ValueError(
                    f"context has shape {np.shape(self.context)}, not {(shape[0] + 1, shape[0])}"
                )
            if np.shape(self.in_context.dx)[1:] != shape[1:] or self.in_context.context is not None:
                raise ValueError("in_context must be plain rows of the same targets")
            if np.any(self.context >= rows) or np.any(self.context < -1):
                raise ValueError(f"context rows must be -1 .. {rows - 1}")
        if self.paths is not None and np.shape(self.paths.child)[1] != shape[1]:
            raise ValueError(f"paths have {np.shape(self.paths.child)[1]} targets, not {shape[1]}")

    def row(self, h: int, i: int) -> tuple[Transitions, int]:
        """The table and row that hold the moves from ``i`` reached from ``h`` (-1: the trial
        has just started)."""
        if self.context is not None and self.in_context is not None:
            r = int(self.context[h if h >= 0 else len(self.dx), i])
            if r >= 0:
                return self.in_context, r
        return self, i

    def move(self, node: int, h: int, i: int, a: int) -> tuple[float, float, float, bool, int]:
        """Commanding target ``a`` from ``i`` (reached from ``h``) at path node ``node`` (0 at
        a trial's start, -1 off every remembered trial): dx (m), dy (m), dtheta (rad), failed,
        and the path node it leads to. The compiled loop applies the same rule."""
        paths = self.paths or Paths.none(np.shape(self.dx)[1])
        k = int(paths.child[node, a]) if node >= 0 else -1
        if k >= 0:
            return (float(paths.dx[k]), float(paths.dy[k]), float(paths.dtheta[k]),
                    bool(paths.failed[k]), k)  # fmt: skip
        t, r = self.row(h, i)
        return float(t.dx[r, a]), float(t.dy[r, a]), float(t.dtheta[r, a]), bool(t.failed[r, a]), -1

    def compiled(self) -> CompiledTable:
        """The arrays the compiled loop takes: dx, dy, dtheta, failed (n, m); context
        (n + 1, n) (all -1 without context); the in-context rows' dx, dy, dtheta, failed
        (R, m); and the paths' child (N, m), dx, dy, dtheta, failed (N,)."""
        n, m = np.shape(self.dx)
        dx, dy, dtheta = (
            np.ascontiguousarray(a, dtype=np.float64) for a in (self.dx, self.dy, self.dtheta)
        )
        failed = np.ascontiguousarray(self.failed, dtype=np.bool_)
        paths = self.paths or Paths.none(m)
        path_dx, path_dy, path_dtheta = (
            np.ascontiguousarray(a, dtype=np.float64) for a in (paths.dx, paths.dy, paths.dtheta)
        )
        walk = (
            np.ascontiguousarray(paths.child, dtype=np.int64),
            path_dx,
            path_dy,
            path_dtheta,
            np.ascontiguousarray(paths.failed, dtype=np.bool_),
        )
        if self.context is None or self.in_context is None:
            empty = np.zeros((0, m))
            return (dx, dy, dtheta, failed, np.full((n + 1, n), -1, dtype=np.int64), empty, empty,
                    empty, np.zeros((0, m), dtype=np.bool_), *walk)  # fmt: skip
        inner = self.in_context.compiled()
        return (dx, dy, dtheta, failed, np.ascontiguousarray(self.context, dtype=np.int64),
                *inner[:4], *walk)  # fmt: skip


class TransitionProvider(Protocol):
    """A model whose moves depend only on the posture pair (see the module docstring)."""

    @property
    def n_joints(self) -> int:
        """Length J of a posture vector."""
        ...

    def start_posture(self) -> np.ndarray:
        """Level indices (J,) of the posture every trial starts from."""
        ...

    def transitions(self, from_postures: np.ndarray, to_postures: np.ndarray) -> Transitions:
        """Outcome of commanding each row of ``to_postures`` (m, J) from each of (n, J)."""
        ...


@dataclass(frozen=True)
class StepResult:
    """What the upper agent observes after commanding a posture.

    Attributes:
        reward: eq. (17) reward of the step, or the penalty if the lower agent failed (-).
        exterior: exterior state index (the bin of the angle to the light).
        failed: the lower agent could not reach the posture; the trial is over.
        failure: why, where the model can tell (exact physics does), else None.
    """

    reward: float
    exterior: int
    failed: bool
    failure: str | None = None


@runtime_checkable
class StepModel(Protocol):
    """A step-by-step model: one trial at a time, one commanded posture at a time."""

    @property
    def n_joints(self) -> int:
        """Length J of a posture vector."""
        ...

    def start_posture(self) -> np.ndarray:
        """Level indices (J,) of the posture every trial starts from."""
        ...

    def start_trial(self) -> int:
        """Put the robot at its start pose and posture; return the exterior state."""
        ...

    def command(self, posture: np.ndarray) -> StepResult:
        """Command a posture (J,) of level indices; move the robot; report the outcome."""
        ...

    def distance_covered(self) -> float:
        """Distance toward the light covered since the trial started (m)."""
        ...

    def pose(self) -> tuple[float, float, float]:
        """The robot's planar pose now: x (m), y (m), heading (rad)."""
        ...
