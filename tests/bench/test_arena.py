"""The MSM arena plays posture sequences by the model's own equations."""

from __future__ import annotations

import numpy as np

from qdsega.bench.arena import MSMArena
from qdsega.description import load_formation, resolve_formation
from qdsega.locomotion.table_env import TableLocomotionEnv
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters, msm_optimum
from qdsega.task import Task, TaskConfig

FORMATION = load_formation(resolve_formation("legged12"))
MODEL = MinimalSimulationModel(legs=LegLayout.from_formation(FORMATION), params=MSMParameters())
TASK = Task(config=TaskConfig(), light_xy=FORMATION.light.position_m)


def test_the_optimums_witness_covers_the_optimum():
    optimum = msm_optimum(MODEL, steps=30, light_xy=tuple(TASK.light))
    (replay,) = MSMArena(model=MODEL, task=TASK).replays([optimum.postures[1:]])
    assert replay.failure is None and replay.completed == 30
    assert np.isclose(replay.distance_m, optimum.distance_m)


def test_a_batch_walks_as_the_table_environment_does_step_by_step():
    rng = np.random.default_rng(3)
    start = MODEL.start_posture()
    flips = [0.05, 0.5] * 10  # few flips walk, many make it fall
    sequences = [np.where(rng.random((30, 24)) < p, 1 - start, start) for p in flips]
    arena = MSMArena(model=MODEL, task=TASK)
    replays = arena.replays(sequences)
    env = TableLocomotionEnv(formation=FORMATION, sim="msm")
    commands = 0
    for sequence, replay in zip(sequences, replays, strict=True):
        env.reset(seed=0)
        for k, posture in enumerate(sequence):
            _, _, terminated, _, _ = env.step(posture)
            commands += 1
            if terminated:
                assert replay.failure == "fell" and replay.completed == k
                break
        else:
            assert replay.failure is None and replay.completed == 30
        assert np.isclose(replay.distance_m, env.distance_covered())
    assert arena.commands == commands
    assert {r.failure for r in replays} == {None, "fell"}  # both cases were seen
