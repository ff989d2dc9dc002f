"""Behaviour descriptors of a gait, in the unit cube, for any body.

* A legged body: each leg's duty factor, the share of the cycle's postures in which that leg's
  lift joint is down (IT&E's descriptor for its hexapod), read from the commands alone.
* Any other body: how the gait steers, from the trial it walked: the heading change and the
  sideways drift per cycle, each mapped from ``[-bound, bound]`` to ``[0, 1]``.
"""

from __future__ import annotations

import math

import numpy as np

from qdsega.msm import LegLayout
from qdsega.task import relative_move

TURN_BOUND_RAD = math.pi / 4
"""Heading change per cycle that maps to the descriptor's edge (rad)."""
DRIFT_BOUND_M = 0.1
"""Sideways drift per cycle, in the body frame at the trial's start, that maps to its edge (m)."""


def duty_factors(layout: LegLayout, cycle: np.ndarray) -> np.ndarray:
    """Each leg's share of the cycle (k, J) with its lift joint down (level 0), (n_legs,)."""
    cycle = np.asarray(cycle, dtype=np.int64)
    if cycle.ndim != 2 or len(cycle) == 0:
        raise ValueError(f"a cycle is (k >= 1, J) postures, got {cycle.shape}")
    return np.mean(cycle[:, list(layout.lift)] == 0, axis=0).astype(np.float64)


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


def descriptor_size(layout: LegLayout | None) -> int:
    """How many numbers describe a gait of a body: one per leg, else turn and drift."""
    return 2 if layout is None else layout.n_legs


def describe(layout: LegLayout | None, cycle: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """A gait's descriptor: duty factors for a legged body (``layout``), else the turn and
    drift of the trial it walked (``poses``, (T + 1, 3))."""
    if layout is not None:
        return duty_factors(layout, cycle)
    return turn_and_drift(poses, len(cycle))
