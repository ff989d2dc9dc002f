"""Self-imitation: Q raised along a trial to its discounted returns, and a learner that takes
the elite's path because of it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from qdsega.agent.config import PRESETS, with_budget
from qdsega.agent.imitation import imitate
from qdsega.agent.learner import QDSEGA
from qdsega.agent.policy import Rollout, SequencePolicy, rollout
from qdsega.agent.space import ExplorationSpace
from qdsega.agent.table_model import TableModel
from qdsega.description import load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters, msm_optimum
from qdsega.task import Task, TaskConfig


def _task() -> Task:
    # reward 100 per metre; exterior bins: edges -45, -15, 15, 45 deg -> straight ahead is 2
    return Task(config=TaskConfig(trial_steps=3), light_xy=(50.0, 0.0))


def test_imitate_raises_each_step_to_its_discounted_return_by_hand():
    task = _task()
    poses = np.array([[0.0, 0, 0], [0.1, 0, 0], [0.3, 0, 0], [0.6, 0, 0]])
    # actions 1, 0, 1 (action 0 leads to interior 1, action 1 to interior 2): the trial is in
    # interiors 0, 2, 1 and ends in 2, straight ahead (exterior 2) throughout
    trial = Rollout(np.array([1, 0, 1]), np.zeros((3, 2)), poses, False, 0.6)
    n_exterior = task.n_exterior
    q = np.zeros((3 * n_exterior, 2))
    q[2 * n_exterior + 2] = [5.0, 7.0]  # where the trial ends: the last step bootstraps from 7
    q[1 * n_exterior + 2, 1] = 1000.0  # already above its return: kept
    before = q.copy()
    imitate(q, trial, np.array([1, 2]), task=task, gamma=0.9)
    g2 = 30.0 + 0.9 * 7.0  # 0.3 m toward the light earns 30
    g1 = 20.0 + 0.9 * g2
    g0 = 10.0 + 0.9 * g1
    assert q[0 * n_exterior + 2, 1] == pytest.approx(g0)
    assert q[2 * n_exterior + 2, 0] == pytest.approx(g1)
    assert q[1 * n_exterior + 2, 1] == 1000.0
    changed = {tuple(c) for c in np.argwhere(q != before)}
    assert changed == {(2, 1), (2 * n_exterior + 2, 0)}


def test_imitate_gives_a_failed_last_step_the_penalty_alone():
    task = _task()
    poses = np.array([[0.0, 0, 0], [0.2, 0, 0], [0.2, 0, 0], [0.2, 0, 0]])
    trial = Rollout(np.array([0, 1, -1]), np.zeros((2, 2)), poses, True, 0.2)
    n_exterior = task.n_exterior
    q = np.full((2 * n_exterior, 2), -1000.0)
    imitate(q, trial, np.array([1, 1]), task=task, gamma=0.9)
    assert q[1 * n_exterior + 2, 1] == task.penalty
    assert q[0 * n_exterior + 2, 0] == pytest.approx(20.0 + 0.9 * task.penalty)


def _msm_learner(imitate_elite: bool) -> tuple[QDSEGA, MinimalSimulationModel, Task]:
    formation = load_formation(ASSEMBLIES_DIR / "quadruped.yaml")
    world = MinimalSimulationModel(legs=LegLayout.from_formation(formation), params=MSMParameters())
    preset = PRESETS["paper-legged"]
    config = with_budget(preset.agent, generations=3, trials=1)
    config = replace(
        config,
        genetic=replace(config.genetic, population=40),
        learning=replace(config.learning, imitate_elite=imitate_elite),
    )
    task = Task(config=preset.task, light_xy=formation.light.position_m)
    learner = QDSEGA(
        config=config,
        levels=np.full(len(formation.joints), 2),
        model=world,
        task=task,
        rng=np.random.default_rng(3),
    )
    return learner, world, task


def _optimum_trial(world: MinimalSimulationModel, task: Task) -> Rollout:
    optimum = msm_optimum(world, steps=task.trial_steps, light_xy=tuple(task.light))
    commands = optimum.postures[1:]
    space = ExplorationSpace.from_population(commands, world.start_posture())
    table = world.transitions(space.postures, space.actions)
    trial = rollout(
        SequencePolicy(commands=commands, space=space),
        TableModel(space=space, table=table, task=task),
        steps=task.trial_steps,
    )
    assert trial.distance_m == pytest.approx(optimum.distance_m, rel=1e-9)
    return trial


@pytest.mark.parametrize("imitate_elite", [True, False])
def test_a_learner_that_imitates_walks_the_elite_it_could_not_find(imitate_elite):
    learner, world, task = _msm_learner(imitate_elite)
    first = learner.step()
    elite = _optimum_trial(world, task)
    assert first.greedy.distance_m < 0.5 * elite.distance_m  # one learning trial finds nothing
    learner.verify(elite)
    second = learner.step()
    if imitate_elite:  # the witness ends off its cycle, which a greedy policy cannot follow
        assert second.greedy.distance_m >= 0.95 * elite.distance_m
    else:
        assert second.greedy.distance_m < 0.5 * elite.distance_m


def test_the_elite_path_is_kept_in_the_learner_state():
    learner, world, task = _msm_learner(True)
    learner.step()
    elite = _optimum_trial(world, task)
    learner.verify(elite)
    saved = learner.state()
    assert np.array_equal(saved.elite_path, elite.postures)
    other, _, _ = _msm_learner(True)
    other.restore(saved)
    assert np.array_equal(other.step().q, learner.step().q)
