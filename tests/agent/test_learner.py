"""The outer loop: determinism from the seed, and learning on a small body."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest

from qdsega.agent.config import PRESETS, with_budget
from qdsega.agent.learner import QDSEGA
from qdsega.agent.space import ExplorationSpace
from qdsega.description import load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters, msm_optimum
from qdsega.task import Task


def _learner(seed: int, generations: int, trials: int) -> tuple[QDSEGA, float]:
    formation = load_formation(ASSEMBLIES_DIR / "quadruped.yaml")
    world = MinimalSimulationModel(legs=LegLayout.from_formation(formation), params=MSMParameters())
    preset = PRESETS["paper-legged"]
    config = with_budget(preset.agent, generations=generations, trials=trials)
    config = replace(config, genetic=replace(config.genetic, population=40))
    learner = QDSEGA(
        config=config,
        levels=np.full(len(formation.joints), 2),
        model=world,
        task=Task(config=preset.task, light_xy=formation.light.position_m),
        rng=np.random.default_rng(seed),
    )
    optimum = msm_optimum(world, steps=preset.task.trial_steps, light_xy=(50.0, 0.0))
    return learner, optimum.distance_m


def test_same_seed_same_result():
    runs = []
    for _ in range(2):
        learner, _ = _learner(7, 3, 300)
        runs.append(list(learner.run()))
    for a, b in zip(*runs, strict=True):
        assert np.array_equal(a.q, b.q) and np.array_equal(a.space.actions, b.space.actions)
        assert np.array_equal(a.fitness, b.fitness) and a.greedy.distance_m == b.greedy.distance_m
    other, _ = _learner(8, 1, 300)
    assert not np.array_equal(next(other.run()).q, runs[0][0].q)


def test_a_restored_state_continues_exactly_as_an_uninterrupted_run():
    learner, _ = _learner(5, 4, 200)
    uninterrupted = list(learner.run())
    first, _ = _learner(5, 4, 200)
    first.step()
    first.step()
    saved = first.state()
    first.step()  # moves on; the saved state must not move with it
    second, _ = _learner(99, 4, 200)
    second.restore(saved)
    resumed = list(second.run())
    assert [g.index for g in resumed] == [3, 4]
    for a, b in zip(uninterrupted[2:], resumed, strict=True):
        assert np.array_equal(a.q, b.q) and np.array_equal(a.space.actions, b.space.actions)
        assert a.greedy.distance_m == b.greedy.distance_m


def test_restore_refuses_a_state_of_another_shape():
    learner, _ = _learner(1, 2, 100)
    state = learner.state()
    other = replace(state, population=state.population[:, :3])
    with pytest.raises(ValueError, match="population"):
        learner.restore(other)


def test_a_table_carries_over_between_worlds_with_and_without_obstacles():
    """A warm start from another world: a table learnt where nothing stood holds in every
    sensed state; one learnt among obstacles gives its clear states back."""
    from qdsega.description import World
    from qdsega.description.world import Box
    from qdsega.obstacle_map import SENSED_STATES, ObstacleMap

    plain, _ = _learner(3, 2, 100)
    plain.step()
    state = plain.state()
    posts = World(name="post", boxes=(Box((1.0, 0.0, 0.1), (0.1, 0.1, 0.2), 0.0),))
    sensing, _ = _learner(3, 2, 100)
    sensing.task = Task(
        config=plain.task.config,
        light_xy=plain.task.light,
        obstacles=ObstacleMap.of(posts, outline_m=np.zeros((1, 2)), clearance_m=0.2),
    )
    sensing.restore(state)
    space, q = state.previous
    tiled = sensing.state().previous[1].reshape(space.n_interior, SENSED_STATES, 4, -1)
    for sensed in range(SENSED_STATES):
        assert np.array_equal(tiled[:, sensed], q.reshape(space.n_interior, 4, -1))
    plain.restore(sensing.state())
    assert np.array_equal(plain.state().previous[1], q)


def test_legged12_walks_near_the_optimum_on_a_reduced_budget():
    """The paper's legged preset and MSM defaults, 36 of the 200 generations: seed 4 of the
    reproduction has found its gait (0.968 of the optimum) by generation 28."""
    formation = load_formation(ASSEMBLIES_DIR / "legged12.yaml")
    world = MinimalSimulationModel(legs=LegLayout.from_formation(formation), params=MSMParameters())
    preset = PRESETS["paper-legged"]
    learner = QDSEGA(
        config=with_budget(preset.agent, generations=36),
        levels=np.array([len(j.levels_rad) for j in formation.joints]),
        model=world,
        task=Task(config=preset.task, light_xy=formation.light.position_m),
        rng=np.random.default_rng(4),
    )
    optimum = msm_optimum(world, steps=preset.task.trial_steps, light_xy=(50.0, 0.0))
    *_, last = learner.run()
    assert not last.greedy.failed
    assert last.greedy.distance_m >= 0.95 * optimum.distance_m


def test_without_reproduction_the_population_stays_as_drawn():
    """The fixed-set ablation: every generation learns over the first one's postures."""
    learner, _ = _learner(7, 3, 100)
    genetic = replace(learner.config.genetic, reproduce=False, elitism=False)
    learner.config = replace(learner.config, genetic=genetic)
    drawn = learner.population.copy()
    generations = list(learner.run())
    assert np.array_equal(learner.population, drawn)
    actions = [g.space.actions for g in generations]
    assert all(np.array_equal(a, actions[0]) for a in actions)
    # the Q-table is carried over and keeps learning
    assert not np.array_equal(generations[0].q, generations[-1].q)


@pytest.mark.parametrize("new_action_q", ["zero", "row_best"])
def test_an_action_new_to_a_carried_state_starts_at_zero_or_at_the_states_best(new_action_q):
    learner, _ = _learner(3, 2, 100)
    learner.config = replace(
        learner.config, learning=replace(learner.config.learning, new_action_q=new_action_q)
    )
    first = learner.step()
    population = learner.population.copy()
    seen = {a.tobytes() for a in first.space.actions}
    population[0] = next(p for p in itertools.product([0, 1], repeat=population.shape[1])
                         if np.array(p).tobytes() not in seen)  # fmt: skip
    space = ExplorationSpace.from_population(population, learner.model.start_posture())
    start = learner._initial_q(space).reshape(space.n_interior, 4, space.n_actions)
    old_q = first.q.reshape(first.space.n_interior, 4, first.space.n_actions)
    kept = np.array([np.any(np.all(space.actions == a, axis=1)) for a in first.space.actions])
    assert kept.any()  # and population[0] is new
    for i, posture in enumerate(space.postures):
        old_i = np.flatnonzero(np.all(first.space.postures == posture, axis=1))
        if len(old_i) == 0:
            assert not start[i].any()  # a state new to the space starts at zero
            continue
        best = old_q[old_i[0]][:, kept].max(axis=1)
        if new_action_q == "zero":
            best = np.zeros_like(best)
        for a, action in enumerate(space.actions):
            old_a = np.flatnonzero(np.all(first.space.actions == action, axis=1))
            if len(old_a):
                assert np.array_equal(start[i, :, a], old_q[old_i[0], :, old_a[0]])
            else:
                assert np.array_equal(
                    start[i, :, a], best if new_action_q == "row_best" else 0 * best
                )


def test_a_handed_on_path_is_untried_until_a_trial_is_verified():
    learner, _ = _learner(3, 2, 100)
    assert learner.untried_path is None  # a fresh learner has no path
    path = np.array([[0, 1] * 4, [1, 0] * 4, [0, 1] * 4])
    state = replace(learner.state(), elite=(path[:2], None), elite_path=path)
    learner.restore(state)
    assert np.array_equal(learner.untried_path, path)
    generation = learner.step()
    learner.verify(generation.greedy)
    assert learner.untried_path is None
