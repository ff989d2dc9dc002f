"""Behaviour descriptors of a gait, in the unit cube, for any body, from the trial it walked.

* A legged body: each leg's duty factor, the share of the trial in which the leg touched the
  ground (IT&E's descriptor for its hexapod). It is measured, not read from the commands: a leg
  commanded up may still carry the trunk, and a gait that does not lean on a leg is the one
  that walks when that leg is lost.
* Any other body: how the gait steers: the heading change and the sideways drift per cycle,
  each mapped from ``[-bound, bound]`` to ``[0, 1]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from qdsega.description import Formation
from qdsega.task import relative_move

TURN_BOUND_RAD = math.pi / 4
"""Heading change per cycle that maps to the descriptor's edge (rad)."""
DRIFT_BOUND_M = 0.1
"""Sideways drift per cycle, in the body frame at the trial's start, that maps to its edge (m)."""


def duty_factors(legs: tuple[tuple[int, ...], ...], contacts: np.ndarray) -> np.ndarray:
    """Each leg's share of a trial's checks in which one of its units (indices into the
    formation's units) touched the ground, from ``contacts`` (checks, units) bool, (n_legs,);
    a trial with no check gives one half for every leg."""
    contacts = np.asarray(contacts, dtype=bool)
    if contacts.ndim != 2:
        raise ValueError(f"contacts are (checks, units), got {contacts.shape}")
    if len(contacts) == 0:
        return np.full(len(legs), 0.5)
    return np.array([contacts[:, list(units)].any(axis=1).mean() for units in legs])


def turn_and_drift(poses: np.ndarray, cycle_length: int) -> np.ndarray:
    """The heading change and sideways drift per cycle of a trial's poses (T + 1, 3) (x m,
    y m, heading rad) over the steps it completed, mapped to ``[0, 1]`` (2,); a trial that
    completed no step sits in the middle."""
    poses = np.asarray(poses, dtype=np.float64)
    if poses.ndim != 2 or poses.shape[1] != 3 or cycle_length < 1:
        raise ValueError(f"need poses (T + 1, 3) and a cycle length >= 1, got {poses.shape}")
    steps = len(poses) - 1
    if steps == 0:
        return np.full(2, 0.5)
    _, dy, _ = relative_move(tuple(poses[0]), tuple(poses[-1]))
    cycles = steps / cycle_length
    turn = float(np.unwrap(poses[:, 2])[-1] - poses[0, 2]) / cycles  # whole turns count
    drift = dy / cycles
    return np.clip(np.array([turn / TURN_BOUND_RAD, drift / DRIFT_BOUND_M]) / 2.0 + 0.5, 0.0, 1.0)


@dataclass(frozen=True)
class GaitDescriptor:
    """The descriptor of a body's gaits.

    Attributes:
        kind: what it measures, in words.
        names: the name of each number (a leg's, or ``turn`` and ``drift``).
        legs: each leg's units, as indices into the formation's units; empty for a body
            without legs.
    """

    kind: str
    names: tuple[str, ...]
    legs: tuple[tuple[int, ...], ...]

    @classmethod
    def of(cls, formation: Formation) -> GaitDescriptor:
        """Duty factors for a body with legs, else the turn and drift."""
        if not formation.legs:
            return cls("turn and drift per cycle", ("turn", "drift"), ())
        legs = tuple(
            tuple(formation.unit_index[name] for name in leg.units) for leg in formation.legs
        )
        names = tuple(leg.name for leg in formation.legs)
        return cls("measured ground contact per leg", names, legs)

    @property
    def size(self) -> int:
        """How many numbers describe a gait."""
        return len(self.names)

    def __call__(self, contacts: np.ndarray, poses: np.ndarray, cycle_length: int) -> np.ndarray:
        """The descriptor (size,) of a trial of a cycle of ``cycle_length`` postures: its
        ``contacts`` (checks, units) bool and its ``poses`` (T + 1, 3)."""
        if self.legs:
            return duty_factors(self.legs, contacts)
        return turn_and_drift(poses, cycle_length)
