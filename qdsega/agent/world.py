"""How the agent sees the world: posture-transition tables, and a step-by-step interface.

The upper agent (section 3.2.2) commands postures; a lower agent drives the joints there or
fails. Two kinds of world:

* A **transition table** (:class:`TransitionProvider`): the outcome of commanding posture ``j``
  from posture ``i`` does not depend on where the robot is, so it is a table of body-frame
  moves ``(dx, dy, dtheta, failed)``. The Minimal Simulation Model is one (analytic), a
  simulator measured once per transition is another. The compiled learning loop runs on it.
* A **step-by-step world** (:class:`World`): anything else; the plain Python loop runs on it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np


@dataclass(frozen=True)
class Transitions:
    """Body-frame outcome of commanding each ``to`` posture from each ``from`` posture.

    Attributes:
        dx: forward displacement in the body frame at the start of the move, shape (n, m) (m).
        dy: leftward displacement in that frame, shape (n, m) (m).
        dtheta: heading change, counter-clockwise, shape (n, m) (rad).
        failed: the lower agent could not reach the posture (the robot fell), shape (n, m).
    """

    dx: np.ndarray
    dy: np.ndarray
    dtheta: np.ndarray
    failed: np.ndarray

    def __post_init__(self) -> None:
        shape = np.shape(self.dx)
        if len(shape) != 2:
            raise ValueError(f"transitions are (n, m) tables, got shape {shape}")
        for name in ("dy", "dtheta", "failed"):
            if np.shape(getattr(self, name)) != shape:
                raise ValueError(f"{name} has shape {np.shape(getattr(self, name))}, not {shape}")


class TransitionProvider(Protocol):
    """A world whose moves depend only on the posture pair (see the module docstring)."""

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
    """

    reward: float
    exterior: int
    failed: bool


@runtime_checkable
class World(Protocol):
    """A step-by-step world: one trial at a time, one commanded posture at a time."""

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
