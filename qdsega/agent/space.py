"""The exploration space a population spans: actions, interior states (Fig. 8, section 3.2.6).

A gene has one character per actuated joint, valued in that joint's level indices; its
phenotype is the posture those levels form. Genes with the same phenotype are one action.
Interior states are the postures the robot can be in: the initial posture and every action's
posture (a successful command puts the robot in the commanded posture), each once.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

_ARRAYS = ("actions", "action_of", "postures", "next_interior")


@dataclass(frozen=True)
class ExplorationSpace:
    """The Q-table's rows and columns for one generation.

    Attributes:
        actions: the distinct phenotypes, sorted lexicographically, shape (A, J), int64.
        action_of: the action each individual expresses, shape (N,).
        postures: interior-state postures, the initial one first, then the actions' postures
            not equal to it in action order, shape (n_interior, J).
        next_interior: interior state reached by each action, shape (A,).
    """

    actions: np.ndarray
    action_of: np.ndarray
    postures: np.ndarray
    next_interior: np.ndarray

    @classmethod
    def from_population(cls, population: np.ndarray, initial: np.ndarray) -> ExplorationSpace:
        """Build the space of a population (N, J) around the initial posture (J,)."""
        population = np.asarray(population, dtype=np.int64)
        initial = np.asarray(initial, dtype=np.int64)
        if population.ndim != 2 or initial.shape != (population.shape[1],):
            raise ValueError(
                f"population must be (N, J) and initial (J,); got {population.shape} and "
                f"{initial.shape}"
            )
        actions, action_of = np.unique(population, axis=0, return_inverse=True)
        is_initial = np.all(actions == initial, axis=1)
        next_interior = np.empty(len(actions), dtype=np.int64)
        next_interior[is_initial] = 0
        next_interior[~is_initial] = 1 + np.arange(int(np.sum(~is_initial)))
        postures = np.vstack([initial[None, :], actions[~is_initial]])
        return cls(
            actions=actions,
            action_of=action_of.reshape(-1),
            postures=postures,
            next_interior=next_interior,
        )

    def arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """Its arrays by name, each name after ``prefix`` (for an ``.npz``)."""
        return {f"{prefix}{name}": getattr(self, name) for name in _ARRAYS}

    @classmethod
    def from_arrays(cls, data: Mapping[str, np.ndarray], prefix: str = "") -> ExplorationSpace:
        """The space :meth:`arrays` gave (``data``: a mapping, or an open ``.npz``)."""
        return cls(**{name: data[f"{prefix}{name}"] for name in _ARRAYS})

    @property
    def n_actions(self) -> int:
        return len(self.actions)

    @property
    def n_interior(self) -> int:
        return len(self.postures)
