"""Reconfiguration: what a run learnt on one formation, carried onto another by a
:class:`~qdsega.training.joint_mapping.JointMapping`: a learner that starts from a finished
run's population, Q-table and best verified path instead of from scratch (:func:`warm_state`,
``qdsega train OTHER --warm-start RUN``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.agent.genetic import random_population
from qdsega.agent.learner import LearnerState, elite_postures
from qdsega.agent.space import ExplorationSpace
from qdsega.training.joint_mapping import JointMapping, elite_path

KEPT_SHARE = 0.5
"""Share of a warm-started population drawn from the old run's; the rest is random (-).

A changed body needs postures its old gait never used, and a converged population holds few;
half keeps what the old body knew and leaves room for what the new one needs (measured:
docs/notes/2026-12-01-reconfiguration.md)."""


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
    the first generation learns (the training loop, :mod:`qdsega.training.run`),
    which then imitates it (``imitate_elite``) and searches from it (``local_search``).

    A source that learnt no generation (a gait ``qdsega adapt`` found) hands on its elite path
    alone, to a population drawn at random as a fresh run's.

    Args:
        levels: level count of each new joint, shape (J_new,).
        start: the new formation's start posture, shape (J_new,).
        population: individuals of the new run.
        rng: the new run's generator, which the learner goes on drawing from.
    """
    path = mapping.postures(elite_path(source), start)
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
