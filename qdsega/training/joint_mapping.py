"""The joints of one formation matched onto another's by name: a reconfigurable robot's units
keep their names across the versions of its formation, so what a run learnt on one body can
act on the next (:class:`JointMapping`):

* **matched**: actuated in both; each old level maps to the new level nearest in angle (the
  first of equally near ones);
* **dropped**: the old joint is not in the new formation;
* **locked**: the old joint is still there, but broken (``locked_deg``), so no action moves it;
* **added**: an actuated joint of the new formation that the old one lacks. A replayed policy
  holds it at its rest level; a warm-started learner draws its characters at random.

Training (warm starts, :mod:`qdsega.training.reconfiguration`), evaluation on another body,
and adaptation from a repertoire all map with it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from qdsega.agent.learner import LearnerState
from qdsega.agent.policy import GreedyPolicy
from qdsega.agent.space import ExplorationSpace
from qdsega.atomic import replaced_atomically
from qdsega.description import Formation

_CLASSES = ("matched", "dropped", "locked", "added")


@dataclass(frozen=True)
class JointMapping:
    """How the actuated joints of one formation map onto another's.

    Attributes:
        column: for each new joint, the index of the old joint it matches, or -1 (added),
            shape (J_new,).
        levels: for each new joint, the new level index of each old level index (-1 beyond
            the old joint's levels and for added joints), shape (J_new, L_old).
        matched, dropped, locked, added: joint names in each class (module docstring).
    """

    column: np.ndarray
    levels: np.ndarray
    matched: tuple[str, ...]
    dropped: tuple[str, ...]
    locked: tuple[str, ...]
    added: tuple[str, ...]

    @classmethod
    def between(cls, old: Formation, new: Formation) -> JointMapping:
        """Match ``old``'s actuated joints onto ``new``'s by name."""
        old_joints = {j.name: k for k, j in enumerate(old.joints)}
        locked_names = {u.joint_name for u in new.units if u.locked_rad is not None}
        width = max((len(j.levels_rad) for j in old.joints), default=0)
        column = np.full(len(new.joints), -1, dtype=np.int64)
        levels = np.full((len(new.joints), width), -1, dtype=np.int64)
        for k, joint in enumerate(new.joints):
            source = old_joints.get(joint.name)
            if source is None:
                continue
            column[k] = source
            old_levels = old.joints[source].levels_rad
            levels[k, : len(old_levels)] = nearest_levels(joint.levels_rad, old_levels)
        new_names = {j.name for j in new.joints}
        return cls(
            column=column,
            levels=levels,
            matched=tuple(j.name for j in new.joints if j.name in old_joints),
            dropped=tuple(n for n in old_joints if n not in new_names and n not in locked_names),
            locked=tuple(n for n in old_joints if n in locked_names),
            added=tuple(j.name for j in new.joints if j.name not in old_joints),
        )

    def postures(self, old: np.ndarray, fill: np.ndarray) -> np.ndarray:
        """Old postures (n, J_old) of level indices as new ones (n, J_new): matched joints at
        the nearest level, added joints from ``fill`` (n, J_new) or (J_new,)."""
        old = np.asarray(old, dtype=np.int64)
        mapped = np.broadcast_to(np.asarray(fill, dtype=np.int64), (len(old), len(self.column)))
        mapped = mapped.copy()
        for k, source in enumerate(self.column):
            if source >= 0:
                mapped[:, k] = self.levels[k, old[:, source]]
        return mapped

    def policy(self, policy: GreedyPolicy, new: Formation) -> GreedyPolicy:
        """``policy`` acting on ``new``: the same Q-table and states, every action posture
        mapped (added joints at their rest level), a trial starting in ``new``'s rest
        posture."""
        rest = np.array(new.rest_levels(), dtype=np.int64)
        postures = self.postures(policy.postures, rest)
        postures[0] = rest
        return GreedyPolicy(
            q=policy.q,
            actions=self.postures(policy.actions, rest),
            postures=postures,
            next_interior=policy.next_interior,
        )

    def report(self) -> dict[str, list[str]]:
        """The joint names of each class, for JSON."""
        return {k: list(getattr(self, k)) for k in _CLASSES}

    def save(self, file: Path, source: LearnerState) -> None:
        """Write the mapping and the learner state it maps (a warm start's inputs) to
        ``file`` (npz), atomically. A source without a learnt generation (a gait found by
        ``qdsega adapt``) keeps its population and elite path alone."""
        arrays = {
            "column": self.column,
            "levels": self.levels,
            "population": source.population,
            "elite_path": elite_path(source),
        }
        if source.previous is not None:
            space, q = source.previous
            arrays |= {**space.arrays(), "q": q}
        arrays |= {k: np.array(getattr(self, k), dtype=str) for k in _CLASSES}
        with replaced_atomically(file) as partial:
            # numpy's stubs match **arrays against savez_compressed's allow_pickle: bool
            np.savez_compressed(partial, **arrays)  # type: ignore[arg-type]

    @classmethod
    def load(cls, file: Path) -> tuple[JointMapping, LearnerState]:
        """Read what :meth:`save` wrote: the mapping and the source learner state (its random
        generator state is not kept: a warm start draws from its own)."""
        with np.load(file) as data:
            mapping = cls(
                column=data["column"],
                levels=data["levels"],
                **{k: tuple(str(n) for n in data[k]) for k in _CLASSES},
            )
            previous = None
            if "q" in data.files:
                previous = (ExplorationSpace.from_arrays(data), data["q"])
            state = LearnerState(
                completed=0,
                population=data["population"],
                rng_state={},
                previous=previous,
                elite=(np.zeros((0, data["population"].shape[1]), dtype=np.int64), None),
                elite_path=data["elite_path"] if "elite_path" in data.files else None,
            )
        return mapping, state


def nearest_levels(
    levels_rad: Sequence[float], angles_rad: Sequence[float] | np.ndarray
) -> np.ndarray:
    """The index of the level nearest each angle (the first of equally near ones), shape
    like ``angles_rad``: the level a joint of ``levels_rad`` takes for a commanded angle."""
    angles = np.asarray(angles_rad, dtype=np.float64)
    gaps = np.abs(angles[..., None] - np.asarray(levels_rad, dtype=np.float64))
    return np.argmax(gaps <= gaps.min(axis=-1, keepdims=True) + 1e-9, axis=-1).astype(np.int64)


def elite_path(state: LearnerState) -> np.ndarray:
    """``state``'s elite path, shape (k, J) (k = 0 when it kept none)."""
    if state.elite_path is None:
        return np.zeros((0, state.population.shape[1]), dtype=np.int64)
    return state.elite_path


def describe(joints: dict[str, list[str]]) -> str:
    """One line from :meth:`JointMapping.report`: how many joints of each class, and which
    were dropped, locked or added."""
    parts = [f"{len(joints['matched'])} joints matched"]
    for name in _CLASSES[1:]:
        if joints[name]:
            parts.append(f"{len(joints[name])} {name} ({', '.join(joints[name])})")
    return ", ".join(parts)
