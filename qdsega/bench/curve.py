"""A learning curve: what a method's current answer covers in exact physics, against budget.

A point ``(steps[k], distance_m[k])`` says: after spending ``steps[k]`` upper-agent steps in its
world, the method's answer (its greedy policy, or the best posture sequence it has tried)
covers ``distance_m[k]`` toward the light in exact physics. Between points the curve holds its
last value (a step function); before its first point the method has no answer and scores 0.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from qdsega.atomic import replaced_atomically


@dataclass(frozen=True)
class Curve:
    """One run of one method.

    Attributes:
        steps: budget spent at each point, increasing, shape (K,) (upper-agent steps).
        distance_m: the answer's exact distance toward the light there, shape (K,) (m).
        wall_s: wall time at each point since the run began, shape (K,) (s).
    """

    steps: np.ndarray
    distance_m: np.ndarray
    wall_s: np.ndarray

    def __post_init__(self) -> None:
        k = len(self.steps)
        if np.shape(self.distance_m) != (k,) or np.shape(self.wall_s) != (k,):
            raise ValueError("steps, distance_m and wall_s must have one value per point")
        if k and np.any(np.diff(self.steps) < 0):
            raise ValueError("steps must not decrease")

    @classmethod
    def of(cls, points: list[tuple[int, float, float]]) -> Curve:
        """From ``(steps, distance_m, wall_s)`` points in order."""
        array = np.array(points, dtype=np.float64).reshape(-1, 3)
        return cls(array[:, 0].astype(np.int64), array[:, 1], array[:, 2])

    def until(self, budget: int) -> Curve:
        """The points within ``budget`` steps."""
        keep = self.steps <= budget
        return Curve(self.steps[keep], self.distance_m[keep], self.wall_s[keep])

    def at(self, budgets: np.ndarray) -> np.ndarray:
        """The curve's value at each budget (steps), shape like ``budgets`` (m): its last point
        within the budget, 0 before its first."""
        k = np.searchsorted(self.steps, np.asarray(budgets), side="right") - 1
        return np.where(k >= 0, self.distance_m[np.maximum(k, 0)], 0.0)

    def first_reaching(self, distance_m: float) -> tuple[int, float] | None:
        """Steps and wall seconds at the first point reaching ``distance_m``, or None."""
        hits = np.flatnonzero(self.distance_m >= distance_m)
        if len(hits) == 0:
            return None
        return int(self.steps[hits[0]]), float(self.wall_s[hits[0]])

    def save(self, file: Path, *, key: str) -> None:
        """Write the curve as JSON, atomically, with ``key``: what it was made under."""
        data = {
            "key": key,
            "steps": self.steps.tolist(),
            "distance_m": self.distance_m.tolist(),
            "wall_s": self.wall_s.tolist(),
        }
        with replaced_atomically(file) as partial:
            partial.write_text(json.dumps(data) + "\n", encoding="utf-8")

    @staticmethod
    def key_of(file: Path) -> str | None:
        """The key ``file`` was saved with; None for a file of before keys, or none there."""
        try:
            return json.loads(file.read_text(encoding="utf-8")).get("key")
        except (OSError, ValueError):
            return None

    @classmethod
    def load(cls, file: Path) -> Curve:
        data = json.loads(file.read_text(encoding="utf-8"))
        return cls(
            np.array(data["steps"], dtype=np.int64),
            np.array(data["distance_m"], dtype=np.float64),
            np.array(data["wall_s"], dtype=np.float64),
        )
