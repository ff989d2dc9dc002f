"""The Python loop over a step-by-step world equals the compiled loop over the same table."""

from __future__ import annotations

import math

import numpy as np

from qdsega import ASSEMBLIES_DIR
from qdsega.agent.config import PRESETS
from qdsega.agent.exterior import bin_edges_rad, exterior_state
from qdsega.agent.genetic import random_population
from qdsega.agent.qlearning import greedy_on_table, learn_on_table
from qdsega.agent.space import ExplorationSpace
from qdsega.agent.world import StepResult
from qdsega.agent.world_loop import greedy_on_world, learn_on_world
from qdsega.description import load_formation
from qdsega.msm import LegLayout, MinimalSimulationModel, MSMParameters

LIGHT = np.array([50.0, 10.0])


class TableWorld:
    """A step-by-step world that walks a transition table, as the compiled loop does."""

    def __init__(self, space: ExplorationSpace, table, edges: np.ndarray, learning) -> None:
        self.space, self.table, self.edges, self.learning = space, table, edges, learning
        self.index = {row.tobytes(): a for a, row in enumerate(space.actions)}

    n_joints = property(lambda self: self.space.actions.shape[1])

    def start_posture(self) -> np.ndarray:
        return self.space.postures[0]

    def start_trial(self) -> int:
        self.x = self.y = self.theta = 0.0
        self.interior = 0
        return exterior_state(0.0, 0.0, 0.0, LIGHT[0], LIGHT[1], self.edges)

    def command(self, posture: np.ndarray) -> StepResult:
        a, i, t = self.index[np.asarray(posture).tobytes()], self.interior, self.table
        if t.failed[i, a]:
            return StepResult(self.learning.penalty, 0, True)
        before = math.hypot(LIGHT[0] - self.x, LIGHT[1] - self.y)
        c, s = math.cos(self.theta), math.sin(self.theta)
        self.x += t.dx[i, a] * c - t.dy[i, a] * s
        self.y += t.dx[i, a] * s + t.dy[i, a] * c
        self.theta += t.dtheta[i, a]
        self.interior = int(self.space.next_interior[a])
        after = math.hypot(LIGHT[0] - self.x, LIGHT[1] - self.y)
        exterior = exterior_state(self.x, self.y, self.theta, LIGHT[0], LIGHT[1], self.edges)
        return StepResult(self.learning.reward_scale * (before - after), exterior, False)

    def distance_covered(self) -> float:
        return math.hypot(*LIGHT) - math.hypot(LIGHT[0] - self.x, LIGHT[1] - self.y)

    def pose(self) -> tuple[float, float, float]:
        return (self.x, self.y, self.theta)


def test_python_world_loop_matches_the_compiled_table_loop():
    formation = load_formation(ASSEMBLIES_DIR / "quadruped.yaml")
    model = MinimalSimulationModel(legs=LegLayout.from_formation(formation), params=MSMParameters())
    learning = PRESETS["paper-legged"].learning
    edges = bin_edges_rad(learning.exterior_bin_edges_deg)
    population = random_population(np.full(8, 2), 12, np.random.default_rng(1))
    space = ExplorationSpace.from_population(population, model.start_posture())
    table = model.transitions(space.postures, space.actions)
    n_exterior, trials, steps = len(edges), 300, learning.trial_steps
    schedule = np.array(
        [learning.temperature_scale, learning.temperature_rate, learning.temperature_offset]
    )
    results = []
    for compiled in (True, False):
        q = np.zeros((space.n_interior * n_exterior, space.n_actions))
        uses = np.zeros(space.n_actions, dtype=np.int64)
        distances, fell = np.zeros(trials), np.zeros(trials, dtype=np.bool_)
        rng = np.random.default_rng(5)
        if compiled:
            taken = learn_on_table(
                q,
                table.dx,
                table.dy,
                table.dtheta,
                table.failed,
                space.next_interior,
                LIGHT,
                edges,
                trials,
                steps,
                learning.alpha,
                learning.gamma,
                schedule,
                learning.reward_scale,
                learning.penalty,
                rng,
                uses,
                distances,
                fell,
            )
        else:
            taken = learn_on_world(
                q,
                TableWorld(space, table, edges, learning),
                space.actions,
                space.next_interior,
                n_exterior=n_exterior,
                trials=trials,
                trial_steps=steps,
                alpha=learning.alpha,
                gamma=learning.gamma,
                temperature_params=schedule,
                rng=rng,
                uses=uses,
                distances=distances,
                fell=fell,
            )
        results.append((taken, q, uses, distances, fell))
    (steps_a, *arrays_a), (steps_b, *arrays_b) = results
    assert steps_a == steps_b > 0
    for a, b in zip(arrays_a, arrays_b, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)

    q = results[0][1]
    poses_a, poses_b = np.zeros((steps + 1, 3)), np.zeros((steps + 1, 3))
    taken_a, taken_b = np.zeros(steps, dtype=np.int64), np.zeros(steps, dtype=np.int64)
    fell_a = greedy_on_table(
        q,
        table.dx,
        table.dy,
        table.dtheta,
        table.failed,
        space.next_interior,
        LIGHT,
        edges,
        steps,
        poses_a,
        taken_a,
    )
    fell_b = greedy_on_world(
        q,
        TableWorld(space, table, edges, learning),
        space.actions,
        space.next_interior,
        n_exterior=n_exterior,
        trial_steps=steps,
        poses=poses_b,
        taken=taken_b,
    )
    assert fell_a == fell_b
    assert np.array_equal(taken_a, taken_b)
    np.testing.assert_allclose(poses_a, poses_b, atol=1e-12)
