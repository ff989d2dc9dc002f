"""Leg layout: where each leg's two joints sit in a posture vector, and which side it is on."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qdsega.description import Formation
from qdsega.errors import FormationError

LEG_STATES = (1, 2, 3, 4)
"""The paper's leg states (section 4.1.2): 1 forward+down, 2 back+down, 3 forward+up, 4 back+up."""
LEG_STATE_NAMES = {1: "forward, down", 2: "back, down", 3: "forward, up", 4: "back, up"}
"""What each leg state means, for figures."""


@dataclass(frozen=True)
class LegLayout:
    """The legs of a body as index arrays into a posture (one level index per actuated joint).

    Level conventions follow :class:`qdsega.description.Leg`: swing level 0 = forward,
    1 = back; lift level 0 = down, 1 = up; so leg state = 1 + swing + 2 * lift.

    Attributes:
        n_joints: length J of a posture vector.
        swing: posture index of each leg's swing joint, shape (n_legs,).
        lift: posture index of each leg's lift joint, shape (n_legs,).
        right: True for a right-side leg, shape (n_legs,).
        names: leg names, front to back per side, in declaration order.
    """

    n_joints: int
    swing: tuple[int, ...]
    lift: tuple[int, ...]
    right: tuple[bool, ...]
    names: tuple[str, ...]

    def __post_init__(self) -> None:
        n = len(self.swing)
        if n == 0:
            raise ValueError("a leg layout needs at least one leg")
        if not len(self.lift) == len(self.right) == len(self.names) == n:
            raise ValueError("swing, lift, right and names must have one entry per leg")
        used = list(self.swing) + list(self.lift)
        if len(set(used)) != len(used) or min(used) < 0 or max(used) >= self.n_joints:
            raise ValueError(f"leg joint indices must be distinct and in [0, {self.n_joints})")

    @classmethod
    def from_formation(cls, formation: Formation, *, both_sides: bool = True) -> LegLayout:
        """The layout of a legged formation; with ``both_sides`` (the MSM's need) it must have
        legs on both sides.

        Raises:
            FormationError: the formation has no legs, or (``both_sides``) none on one side.
        """
        if not formation.legs:
            raise FormationError(
                "the Minimal Simulation Model needs a legged formation (this one has no legs)",
                file=formation.file,
            )
        for side in ("left", "right") if both_sides else ():
            if not formation.legs_on(side):
                raise FormationError(
                    f"the Minimal Simulation Model needs legs on both sides (none on the {side})",
                    file=formation.file,
                )
        return cls(
            n_joints=len(formation.joints),
            swing=tuple(formation.joint_index(leg.swing_joint) for leg in formation.legs),
            lift=tuple(formation.joint_index(leg.lift_joint) for leg in formation.legs),
            right=tuple(leg.side == "right" for leg in formation.legs),
            names=tuple(leg.name for leg in formation.legs),
        )

    @property
    def n_legs(self) -> int:
        return len(self.swing)

    def legs_per_side(self) -> tuple[int, int]:
        """(left, right) leg counts."""
        n_right = sum(self.right)
        return self.n_legs - n_right, n_right

    def states(self, postures: np.ndarray) -> np.ndarray:
        """Leg states 1..4 of postures (..., J) -> (..., n_legs), int64."""
        postures = np.asarray(postures)
        if postures.shape[-1] != self.n_joints:
            raise ValueError(f"postures need {self.n_joints} joints, got {postures.shape[-1]}")
        swing = postures[..., list(self.swing)].astype(np.int64)
        lift = postures[..., list(self.lift)].astype(np.int64)
        return 1 + swing + 2 * lift

    def posture(self, states: np.ndarray, *, base: np.ndarray) -> np.ndarray:
        """The posture (J,) with leg states (n_legs,) and every other joint as in ``base``."""
        states = np.asarray(states, dtype=np.int64)
        if states.shape != (self.n_legs,) or np.any((states < 1) | (states > 4)):
            raise ValueError(f"need {self.n_legs} leg states in 1..4, got {states}")
        posture = np.array(base, dtype=np.int64, copy=True)
        posture[list(self.swing)] = (states - 1) % 2
        posture[list(self.lift)] = (states - 1) // 2
        return posture
