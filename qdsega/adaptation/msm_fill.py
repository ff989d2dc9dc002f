"""A legged body's archive filled in the Minimal Simulation Model, for exact physics to verify.

The MSM moves a body by its legs' strokes alone, in microseconds a gait, so MAP-Elites plays
tens of thousands of gaits in seconds and fills every cell of a large archive, each with a gait
that strokes its legs in some pattern. Exact physics then plays each elite once
(:func:`qdsega.adaptation.repertoire.build_repertoire`) and keeps the ones that walk, at their
exact distance. A search in exact physics alone plays a few thousand gaits in the same time,
and its cells keep what walks farthest on the intact body; the MSM's archive holds many more
leg patterns, among them the ones a body still walks with once a leg no longer works.

The descriptor is each leg's commanded duty factor, the share of the cycle's postures with the
leg down: the MSM has no contact to measure.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from qdsega.adaptation.archive import Archive
from qdsega.adaptation.map_elites import MapElites
from qdsega.description import Formation
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters
from qdsega.progress import ProgressFactory
from qdsega.task import Task, TaskConfig, move_pose

DESCRIPTOR = "commanded duty factor per leg (filled in the MSM)"
BATCH = 1000
"""Gaits played in the MSM between two progress updates (-)."""


def commanded_duty(legs: LegLayout, cycle: np.ndarray) -> np.ndarray:
    """Each leg's share of the cycle's postures (k, J) with its lift joint down, (n_legs,)."""
    cycle = np.asarray(cycle)
    return (cycle[:, list(legs.lift)] == 0).mean(axis=0)


def msm_distance(model: MinimalSimulationModel, task: Task, cycle: np.ndarray) -> float:
    """How far toward the light the MSM walks a trial of ``cycle`` (k, J) repeated from its start
    posture (m); NaN where a posture falls (such a gait is not kept)."""
    postures = np.resize(np.asarray(cycle, dtype=np.int64), (task.trial_steps, model.n_joints))
    before = np.vstack([model.start_posture()[None, :], postures[:-1]])
    dx, dtheta, failed = model.moves(before, postures)
    if failed.any():
        return float("nan")
    pose = (0.0, 0.0, 0.0)
    for step in range(task.trial_steps):
        pose = move_pose(*pose, float(dx[step]), 0.0, float(dtheta[step]))
    return task.covered((0.0, 0.0, 0.0), pose)


def fill_in_msm(
    formation: Formation,
    archive: Archive,
    *,
    task: TaskConfig,
    evaluations: int,
    initial: int,
    max_cycle: int,
    rng: np.random.Generator,
    seeds: Sequence[np.ndarray] = (),
    progress: ProgressFactory | None = None,
) -> None:
    """Fill ``archive`` (in place) by MAP-Elites over ``evaluations`` gaits played in the MSM
    (``seeds`` first, then ``initial`` random ones, then variations of elites).

    Raises:
        FormationError: the MSM cannot model the body (no legs, or none on one side).
    """
    legs = LegLayout.from_formation(formation)
    model = MinimalSimulationModel(legs=legs, params=MSMParameters())
    rules = Task(config=task, light_xy=formation.light.position_m)
    levels = np.array([len(j.levels_rad) for j in formation.joints], dtype=np.int64)
    emitter = MapElites(
        archive=archive, levels=levels, rng=rng, initial=initial, cycle=max_cycle, seeds=seeds
    )
    line = None if progress is None else progress("MSM fill", evaluations)
    try:
        while emitter.told < evaluations:
            gaits = emitter.ask(min(BATCH, evaluations - emitter.told))
            descriptors = np.array([commanded_duty(legs, g) for g in gaits])
            distances = np.array([msm_distance(model, rules, g) for g in gaits])
            emitter.tell(gaits, descriptors, distances)
            if line is not None:
                line.update(emitter.told, f"{len(archive.filled)} cells filled")
    finally:
        if line is not None:
            line.close()
