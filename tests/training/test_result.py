"""A run's result: the generation whose greedy policy went farthest with exact physics, kept
in the checkpoint (and read from one written before results were kept)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from qdsega.agent.learner import Generation, LearnerState
from qdsega.agent.policy import Rollout
from qdsega.agent.space import ExplorationSpace
from qdsega.training.checkpoint import Checkpoint, load_checkpoint, save_checkpoint
from qdsega.training.run import _advance, _first_checkpoint
from qdsega.training.run_folder import METRIC_COLUMNS, RunFolder

STEPS = 3
JOINTS = 2


def _space(action: int) -> ExplorationSpace:
    """One action to posture (action, action), from the start posture (0, 0)."""
    return ExplorationSpace(
        actions=np.array([[action, action]]),
        action_of=np.array([-1, 0]),
        postures=np.array([[0, 0], [action, action]]),
        next_interior=np.array([1]),
    )


def _rollout(distance_m: float, posture: int) -> Rollout:
    poses = np.zeros((STEPS + 1, 3))
    poses[-1] = (distance_m, 0.0, 0.1 * posture)
    return Rollout(
        actions=np.zeros(STEPS, dtype=np.int64),
        postures=np.full((STEPS, JOINTS), posture),
        poses=poses,
        failed=False,
        distance_m=distance_m,
    )


def _generation(index: int, distance_m: float) -> Generation:
    return Generation(
        index=index,
        space=_space(index),
        q=np.full((2, 1), float(index)),
        uses=np.ones(1, dtype=np.int64),
        fitness=np.ones(1),
        distances=np.array([distance_m]),
        fell=np.zeros(1, dtype=bool),
        steps=STEPS,
        greedy=_rollout(distance_m, index),
        wall_s=0.1,
    )


def _state(completed: int) -> LearnerState:
    return LearnerState(
        completed=completed,
        population=np.ones((2, JOINTS), dtype=np.int64),
        rng_state=np.random.default_rng(0).bit_generator.state,
        previous=(_space(completed), np.full((2, 1), float(completed))),
        elite=(np.zeros((0, JOINTS), dtype=np.int64), None),
    )


def _learn(exact_m: list[float]) -> Checkpoint:
    """The checkpoint after generations whose exact replays cover ``exact_m`` (m)."""
    formation = SimpleNamespace(joints=[None] * JOINTS)
    config = SimpleNamespace(task=SimpleNamespace(trial_steps=STEPS))
    world: dict = {}
    checkpoint = _first_checkpoint(formation, config, SimpleNamespace(state=lambda: _state(0)))
    for index, distance_m in enumerate(exact_m, start=1):
        learner = SimpleNamespace(state=lambda index=index: _state(index))
        generation = _generation(index, distance_m)
        exact = _rollout(distance_m, index)
        checkpoint = _advance(checkpoint, generation, exact, learner, world, 0, 1.0)
    return checkpoint


def test_the_result_is_the_farthest_exact_generation_and_ties_keep_the_earliest():
    checkpoint = _learn([0.2, 0.9, 0.4, 0.9, 0.5])
    assert checkpoint.result == 2
    assert np.array_equal(checkpoint.result_policy.actions, [[2, 2]])
    assert np.array_equal(checkpoint.result_policy.q, np.full((2, 1), 2.0))
    assert np.array_equal(checkpoint.gait, [[0, 0], [2, 2], [2, 2], [2, 2]])
    column = METRIC_COLUMNS.index("greedy_exact_m")
    assert checkpoint.metrics[checkpoint.result - 1, column] == 0.9
    assert checkpoint.learner.completed == 5  # learning goes on from the last generation


def test_a_later_farther_generation_becomes_the_result():
    assert _learn([0.2, 0.1, 0.3]).result == 3
    assert _learn([-0.5]).result == 1  # even a first generation that walks away


def test_the_result_survives_a_checkpoint_round_trip(tmp_path: Path):
    checkpoint = _learn([0.2, 0.9, 0.4])
    save_checkpoint(tmp_path, checkpoint)
    loaded = load_checkpoint(tmp_path)
    assert loaded.result == 2
    for name in ("q", "actions", "postures", "next_interior"):
        assert np.array_equal(
            getattr(loaded.result_policy, name), getattr(checkpoint.result_policy, name)
        )
    first = _learn([])
    save_checkpoint(tmp_path, first)
    assert load_checkpoint(tmp_path).result == 0 and load_checkpoint(tmp_path).result_policy is None


def test_a_checkpoint_from_before_results_reports_its_last_generation(tmp_path: Path):
    save_checkpoint(tmp_path, _learn([0.2, 0.9, 0.4]))
    file = tmp_path / RunFolder.CHECKPOINT
    with np.load(file) as data:
        arrays = {name: data[name] for name in data.files if not name.startswith("result_")}
    meta = json.loads(str(arrays.pop("meta")))
    del meta["result"]
    np.savez(file, meta=np.array(json.dumps(meta)), **arrays)
    loaded = load_checkpoint(file.parent)
    assert loaded.result == 3
    assert np.array_equal(loaded.result_policy.actions, [[3, 3]])


def test_the_elite_path_survives_a_checkpoint_round_trip(tmp_path: Path):
    checkpoint = _learn([0.2])
    path = np.array([[1, 2], [3, 4], [1, 2]])
    elite = (np.array([[1, 2], [3, 4]]), 0.2)
    learner = replace(checkpoint.learner, elite=elite, elite_path=path)
    save_checkpoint(tmp_path, replace(checkpoint, learner=learner))
    loaded = load_checkpoint(tmp_path).learner
    assert np.array_equal(loaded.elite_path, path) and loaded.elite[1] == 0.2
    save_checkpoint(tmp_path, checkpoint)  # a state without a path (one saved before paths)
    assert load_checkpoint(tmp_path).learner.elite_path is None
