"""One task, three loops: the compiled table loop, the Python loop and the Gymnasium env give
the same rewards for the same postures; the Python loop equals the compiled one draw for draw."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from qdsega.agent.config import PRESETS
from qdsega.agent.genetic import random_population
from qdsega.agent.model import Paths, Transitions
from qdsega.agent.qlearning import learn_on_table
from qdsega.agent.space import ExplorationSpace
from qdsega.agent.step_loop import learn_on_model
from qdsega.agent.table_model import TableModel
from qdsega.baselines.classic_gaits import leg_gait
from qdsega.description import load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.locomotion.env import LocomotionEnv
from qdsega.locomotion.env_model import EnvModel
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters
from qdsega.task import Task, TaskConfig, relative_move

LIGHT = (50.0, 10.0)
GREEDY = np.array([1e-9, 0.0, 0.0])
"""An eq. (18) schedule so cold that the roulette always takes the best action."""


def _learn(world, q, space, task, trials, schedule, alpha, gamma, rng):
    """The compiled loop on a table, or the Python loop on a step-by-step world."""
    uses = np.zeros(space.n_actions, dtype=np.int64)
    distances, fell = np.zeros(trials), np.zeros(trials, dtype=np.bool_)
    if isinstance(world, Transitions):
        steps = learn_on_table(
            q, *world.compiled(), space.next_interior, task.light, task.edges,
            *task.map_arrays(), trials,
            task.trial_steps, alpha, gamma, schedule, task.config.reward_per_m, task.penalty,
            rng, uses, distances, fell,
        )  # fmt: skip
    else:
        steps = learn_on_model(
            q, world, space.actions, space.next_interior, n_exterior=task.n_exterior,
            trials=trials, trial_steps=task.trial_steps, alpha=alpha, gamma=gamma,
            temperature_params=schedule, rng=rng, uses=uses, distances=distances, fell=fell,
        )  # fmt: skip
    return steps, uses, distances, fell


def test_compiled_loop_python_loop_and_env_give_the_same_rewards():
    """Walk a quadruped through 4 gait postures, then lift every leg (a fall), in exact
    physics; a table holding the moves measured there must give the same rewards and penalty
    in the compiled loop and the Python loop. Each loop is forced along the sequence (a
    temperature near 0, the sequence's actions preferred) with alpha 1 and gamma 0, so that
    every visited entry of Q ends as the reward of its step."""
    formation = load_formation(ASSEMBLIES_DIR / "quadruped.yaml")
    config = TaskConfig(trial_steps=5, distance_unit_m=0.01)
    env = LocomotionEnv(formation=formation, task=config)
    all_up = np.array(formation.rest_levels())
    for leg in formation.legs:
        all_up[formation.joint_index(leg.lift_joint)] = 1
    sequence = np.vstack([leg_gait(formation, gait="wave", steps=4), all_up])
    start = env.start_levels
    assert len(np.unique(np.vstack([start, sequence]), axis=0)) == 6  # every pair once
    space = ExplorationSpace.from_population(sequence, start)
    order = [int(np.flatnonzero((space.actions == p).all(axis=1))[0]) for p in sequence]

    # Exact physics: rewards, and the body-frame move of every step.
    world = EnvModel(env=env)
    task = env.task
    exterior = world.start_trial()
    rewards, visited, moves = [], [], []
    interior = 0
    for a in order:
        before = world.pose()
        result = world.command(space.actions[a])
        rewards.append(result.reward)
        visited.append((interior * task.n_exterior + exterior, a))
        moves.append(relative_move(before, world.pose()))
        interior, exterior = int(space.next_interior[a]), result.exterior
    assert result.failed and rewards[-1] == config.penalty
    assert not any(r == config.penalty for r in rewards[:-1])

    shape = (space.n_interior, space.n_actions)
    dx, dy, dtheta = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    failed = np.zeros(shape, dtype=np.bool_)
    interior = 0
    for a, move in zip(order[:-1], moves[:-1], strict=True):
        dx[interior, a], dy[interior, a], dtheta[interior, a] = move
        interior = int(space.next_interior[a])
    failed[interior, order[-1]] = True
    table = Transitions(dx=dx, dy=dy, dtheta=dtheta, failed=failed)

    worlds = {
        "compiled loop on the table": table,
        "Python loop on the table": TableModel(space=space, table=table, task=task),
        "Python loop in exact physics": world,
    }
    for name, learner_world in worlds.items():
        q = np.zeros((space.n_interior * task.n_exterior, space.n_actions))
        for s, a in visited:
            q[s, a] = 1e6
        steps, *_ = _learn(
            learner_world, q, space, task, 1, GREEDY, 1.0, 0.0, np.random.default_rng(0)
        )
        assert steps == len(order), name
        got = [q[s, a] for s, a in visited]
        assert got == pytest.approx(rewards, rel=1e-9, abs=1e-9), name
    env.close()


def _with_context(table: Transitions, gen: np.random.Generator) -> Transitions:
    """``table`` with random in-context rows for a third of the (h, i) pairs."""
    n, m = table.dx.shape
    context = np.full((n + 1, n), -1, dtype=np.int64)
    chosen = np.flatnonzero(gen.random((n + 1) * n) < 1 / 3)
    context.flat[chosen] = np.arange(len(chosen))
    rows = len(chosen)
    in_context = Transitions(
        dx=gen.uniform(-0.05, 0.1, (rows, m)),
        dy=gen.uniform(-0.02, 0.02, (rows, m)),
        dtheta=gen.uniform(-0.2, 0.2, (rows, m)),
        failed=gen.random((rows, m)) < 0.1,
    )
    return replace(table, context=context, in_context=in_context)


def _with_paths(table: Transitions, gen: np.random.Generator) -> Transitions:
    """``table`` with a random tree of 60 remembered moves."""
    m = table.dx.shape[1]
    child = np.full((60, m), -1, dtype=np.int64)
    for node in range(1, 60):
        parent = int(gen.integers(node))
        free = np.flatnonzero(child[parent] < 0)
        if len(free):
            child[parent, gen.choice(free)] = node
    paths = Paths(
        child=child,
        dx=gen.uniform(-0.05, 0.1, 60),
        dy=gen.uniform(-0.02, 0.02, 60),
        dtheta=gen.uniform(-0.2, 0.2, 60),
        failed=gen.random(60) < 0.1,
    )
    return replace(table, paths=paths)


@pytest.mark.parametrize("extra", ["none", "context", "paths", "both"])
def test_python_world_loop_matches_the_compiled_table_loop(extra):
    formation = load_formation(ASSEMBLIES_DIR / "quadruped.yaml")
    model = MinimalSimulationModel(legs=LegLayout.from_formation(formation), params=MSMParameters())
    preset = PRESETS["paper-legged"]
    learning, task = preset.agent.learning, Task(config=preset.task, light_xy=LIGHT)
    population = random_population(np.full(8, 2), 12, np.random.default_rng(1))
    space = ExplorationSpace.from_population(population, model.start_posture())
    table = model.transitions(space.postures, space.actions)
    if extra in ("context", "both"):
        table = _with_context(table, np.random.default_rng(2))
    if extra in ("paths", "both"):
        table = _with_paths(table, np.random.default_rng(3))
    schedule = np.array(
        [learning.temperature_scale, learning.temperature_rate, learning.temperature_offset]
    )
    results = []
    for world in (table, TableModel(space=space, table=table, task=task)):
        q = np.zeros((space.n_interior * task.n_exterior, space.n_actions))
        rng = np.random.default_rng(5)
        steps, *arrays = _learn(world, q, space, task, 300, schedule, 0.5, 0.9, rng)
        results.append((steps, q, *arrays))
    (steps_a, *arrays_a), (steps_b, *arrays_b) = results
    assert steps_a == steps_b > 0
    for a, b in zip(arrays_a, arrays_b, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)
