"""Reconfiguration: what a run learnt on one formation, carried onto another.

A reconfigurable robot gains, loses or breaks units; its units keep their names across the
versions of its formation, so the joints of two formations are matched by name
(:class:`JointMapping`):

* **matched**: actuated in both; each old level maps to the new level nearest in angle (the
  first of equally near ones);
* **dropped**: the old joint is not in the new formation;
* **locked**: the old joint is still there, but broken (``locked_deg``), so no action moves it;
* **added**: an actuated joint of the new formation that the old one lacks. A replayed policy
  holds it at its rest level; a warm-started learner draws its characters at random.

Two uses: a trained policy replayed on another body (:meth:`JointMapping.policy`, ``qdsega
evaluate RUN --formation OTHER``) and a learner that starts from a finished run's population,
Q-table and best verified path instead of from scratch (:func:`warm_state`, ``qdsega train
OTHER --warm-start RUN``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.agent.genetic import random_population
from qdsega.agent.learner import LearnerState, elite_postures
from qdsega.agent.policy import GreedyPolicy
from qdsega.agent.space import ExplorationSpace
from qdsega.atomic import replaced_atomically
from qdsega.description import Formation

_CLASSES = ("matched", "dropped", "locked", "added")

KEPT_SHARE = 0.5
"""Share of a warm-started population drawn from the old run's; the rest is random (-).

A changed body needs postures its old gait never used, and a converged population holds few;
half keeps what the old body knew and leaves room for what the new one needs (measured:
docs/notes/2026-12-01-reconfiguration.md)."""


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
            angles = np.asarray(joint.levels_rad)
            for level, angle in enumerate(old.joints[source].levels_rad):
                gaps = np.abs(angles - angle)
                levels[k, level] = int(np.flatnonzero(gaps <= gaps.min() + 1e-9)[0])
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
        names = {k: np.array(getattr(self, k), dtype=str) for k in _CLASSES}
        learnt = {}
        if source.previous is not None:
            space, q = source.previous
            learnt = {**space.arrays(), "q": q}
        with replaced_atomically(file) as partial:
            np.savez_compressed(
                partial,
                column=self.column,
                levels=self.levels,
                population=source.population,
                elite_path=_path(source),
                **learnt,
                **names,
            )

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


def _path(state: LearnerState) -> np.ndarray:
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


def warm_state(
    mapping: JointMapping,
    source: LearnerState,
    *,
    levels: np.ndarray,
    start: np.ndarray,
    population: int,
    rng: np.random.Generator,
) -> LearnerState:
    """A learner's state before its first generation, carried over from ``source`` (a finished
    run's last generation) through ``mapping``.

    Every old action (distinct posture) becomes one new posture: matched joints at the
    nearest level, each added joint at a level drawn from ``rng`` once per old action (so
    copies of one action stay copies, and the old Q-table carries over to them through
    ``carry_q``). :data:`KEPT_SHARE` of the population is drawn (with replacement, so an
    action keeps its weight) from the old population so mapped, the rest at random as a fresh
    run's; the old Q-table is the "previous generation" whose values the first generation
    starts from. The old run's elite path (its best verified trial's postures), mapped with
    added joints at their ``start`` level, is the elite, not yet verified on the new body
    (distance None, :attr:`qdsega.agent.learner.QDSEGA.untried_path`): elitism puts its
    postures into the first population, and a world with exact physics verifies it before
    the first generation learns (:meth:`qdsega.training.sims.TrainingSim.verify`),
    which then imitates it (``imitate_elite``) and searches from it (``local_search``).

    A source that learnt no generation (a gait ``qdsega adapt`` found) hands on its elite path
    alone, to a population drawn at random as a fresh run's.

    Args:
        levels: level count of each new joint, shape (J_new,).
        start: the new formation's start posture, shape (J_new,).
        population: individuals of the new run.
        rng: the new run's generator, which the learner goes on drawing from.
    """
    path = mapping.postures(_path(source), start)
    if source.previous is None:
        return LearnerState(
            completed=0,
            population=random_population(levels, population, rng),
            rng_state=rng.bit_generator.state,
            previous=None,
            elite=(elite_postures(path, population), None),
            elite_path=path,
        )
    space, q = source.previous
    added = mapping.column < 0
    draws = np.zeros((len(space.actions), len(levels)), dtype=np.int64)
    draws[:, added] = (rng.random((len(space.actions), int(added.sum()))) * levels[added]).astype(
        np.int64
    )
    actions = mapping.postures(space.actions, draws)
    of_action = {a.tobytes(): k for k, a in enumerate(space.actions)}
    genes = np.array([of_action[g.astype(np.int64).tobytes()] for g in source.population])
    kept = actions[genes][rng.integers(len(genes), size=round(KEPT_SHARE * population))]
    fresh = random_population(levels, population - len(kept), rng)
    mapped = np.vstack([kept, fresh])
    interior = np.empty((space.n_interior, len(levels)), dtype=np.int64)
    interior[space.next_interior] = actions  # interior k > 0 is the posture of its action
    interior[0] = start
    previous = ExplorationSpace(
        actions=actions,
        action_of=space.action_of,
        postures=interior,
        next_interior=space.next_interior,
    )
    return LearnerState(
        completed=0,
        population=mapped,
        rng_state=rng.bit_generator.state,
        previous=(previous, q),
        elite=(elite_postures(path, population), None),
        elite_path=path,
    )


@dataclass(frozen=True)
class WarmStart:
    """What a warm start starts from: ``warm_start.json``'s record, the joint mapping onto the
    new body, and the learner state it maps."""

    record: dict[str, Any]
    mapping: JointMapping
    source: LearnerState


def warm_record(run: Path, summary: dict[str, Any], mapping: JointMapping) -> dict[str, Any]:
    """What ``warm_start.json`` says: where the run started from and how joints matched."""
    return {
        "run": str(run.resolve()),
        "formation": summary["formation"],
        "formation_sha256": summary.get("formation_sha256"),
        "seed": summary["seed"],
        "generations": summary["generations"],
        "distance_m": summary["distance_m"],
        "joints": mapping.report(),
    }
