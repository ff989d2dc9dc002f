"""QDSEGA's outer loop (Fig. 7): build the Q-table from the population, learn, rate, reproduce.

Each generation's Q-table starts from the previous one's values where the interior posture
and the action posture both persist, zeros elsewhere (``carry_q``; zeros everywhere without
it), and eq. (18)'s schedule restarts with it: a new population is a new set of actions and
states (the paper's 10000 trials per generation cool the temperature from 408 to below 1e-6,
so each generation is a full learning run). Reproduction draws parents from a roulette wheel
with one slot per action or per gene (``GeneticConfig.selection``).
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from qdsega.agent.config import QDSEGAConfig
from qdsega.agent.exterior import bin_edges_rad
from qdsega.agent.fitness import fitness
from qdsega.agent.genetic import random_population, reproduce, roulette_weights
from qdsega.agent.qlearning import greedy_on_table, learn_on_table
from qdsega.agent.space import ExplorationSpace
from qdsega.agent.world import TransitionProvider, World
from qdsega.agent.world_loop import greedy_on_world, learn_on_world


@dataclass(frozen=True)
class Generation:
    """What one generation learnt, and how its greedy policy walks.

    Attributes:
        index: generation number, from 1.
        space: the population's actions and interior states.
        q: the learnt Q-table, shape (n_interior * n_exterior, A).
        uses: times each action was chosen, shape (A,).
        fitness: eq. (6) per action, shape (A,).
        distances: distance toward the light covered by each trial (m), shape (trials,).
        fell: whether each trial ended in a fall, shape (trials,).
        steps: commands issued while learning.
        greedy_poses: the greedy trial's poses (x m, y m, theta rad), shape (steps + 1, 3).
        greedy_actions: its action per step, -1 after a fall, shape (steps,).
        greedy_fell: whether the greedy trial fell.
        greedy_distance: distance toward the light it covered (m).
        wall_s: wall time of the generation (s).
    """

    index: int
    space: ExplorationSpace
    q: np.ndarray
    uses: np.ndarray
    fitness: np.ndarray
    distances: np.ndarray
    fell: np.ndarray
    steps: int
    greedy_poses: np.ndarray
    greedy_actions: np.ndarray
    greedy_fell: bool
    greedy_distance: float
    wall_s: float

    def greedy_postures(self) -> np.ndarray:
        """The greedy trial's postures, initial one first, until it ends, shape (k + 1, J)."""
        return greedy_postures(self.space, self.greedy_actions, self.greedy_fell)


def greedy_postures(space: ExplorationSpace, taken: np.ndarray, fell: bool) -> np.ndarray:
    """The postures a greedy trial went through, initial one first, shape (k + 1, J).

    Args:
        space: the generation's space.
        taken: the trial's action per step, -1 after a fall, shape (steps,).
        fell: whether the trial ended in a fall (its last command failed: not reached).
    """
    taken = taken[taken >= 0]
    if fell:
        taken = taken[:-1]
    return np.vstack([space.postures[:1], space.actions[taken]])


@dataclass(frozen=True)
class LearnerState:
    """Where a learner stands between two generations: enough to continue exactly.

    Attributes:
        completed: generations learnt.
        population: the population the next generation learns over, shape (N, J).
        rng_state: the random generator's ``bit_generator.state`` (plain dict, JSON-safe).
        previous: the last generation's space and Q-table (``carry_q`` starts from it), or
            None before the first generation.
    """

    completed: int
    population: np.ndarray
    rng_state: dict[str, Any]
    previous: tuple[ExplorationSpace, np.ndarray] | None


class QDSEGA:
    """The learner on a posture-transition world.

    Args:
        config: every hyperparameter.
        levels: level count of each gene character (actuated joint), shape (J,).
        world: a transition table (learning runs compiled) or a step-by-step world such as
            exact physics (the same algorithm in Python, :mod:`qdsega.agent.world_loop`).
        light_xy: light position (m); trials start at the origin heading +x.
        rng: the only source of randomness.
    """

    def __init__(
        self,
        *,
        config: QDSEGAConfig,
        levels: np.ndarray,
        world: TransitionProvider | World,
        light_xy: tuple[float, float],
        rng: np.random.Generator,
    ) -> None:
        levels = np.asarray(levels, dtype=np.int64)
        if levels.shape != (world.n_joints,):
            raise ValueError(f"levels must be ({world.n_joints},), got {levels.shape}")
        self.config = config
        self.levels = levels
        self.world = world
        self.light = np.asarray(light_xy, dtype=np.float64)
        self.rng = rng
        self.edges = bin_edges_rad(config.learning.exterior_bin_edges_deg)
        self.population = random_population(levels, config.genetic.population, rng)
        self.completed = 0
        """Generations learnt so far."""
        self._previous: tuple[ExplorationSpace, np.ndarray] | None = None

    @property
    def n_exterior(self) -> int:
        return len(self.edges)

    def run(self) -> Iterator[Generation]:
        """Yield every remaining generation in turn (see :meth:`step`)."""
        while self.completed < self.config.genetic.generations:
            yield self.step()

    def step(self) -> Generation:
        """Learn the next generation, then (unless it was the last) reproduce the population,
        so that :meth:`state` afterwards is where the following generation starts."""
        generation = self._learn_generation(self.completed + 1)
        self.completed += 1
        if self.completed < self.config.genetic.generations:
            weights = roulette_weights(
                generation.fitness, generation.space.action_of, self.config.genetic.selection
            )
            self.population = reproduce(
                self.population, weights, self.levels, self.config.genetic, self.rng
            )
        return generation

    def state(self) -> LearnerState:
        """A copy of everything the rest of the run depends on."""
        previous = None
        if self._previous is not None:
            space, q = self._previous
            previous = (space, q.copy())
        return LearnerState(
            completed=self.completed,
            population=self.population.copy(),
            rng_state=copy.deepcopy(self.rng.bit_generator.state),
            previous=previous,
        )

    def restore(self, state: LearnerState) -> None:
        """Continue from ``state`` (of a learner with the same configuration and levels): the
        generations that follow are those an uninterrupted run would have learnt."""
        if state.population.shape != self.population.shape:
            raise ValueError(
                f"state population {state.population.shape} does not fit this learner's "
                f"{self.population.shape}"
            )
        if not 0 <= state.completed <= self.config.genetic.generations:
            raise ValueError(
                f"state completed {state.completed} generations of "
                f"{self.config.genetic.generations}"
            )
        self.completed = state.completed
        self.population = state.population.copy()
        self.rng.bit_generator.state = copy.deepcopy(state.rng_state)
        self._previous = None
        if state.previous is not None:
            space, q = state.previous
            self._previous = (space, q.copy())

    def _initial_q(self, space: ExplorationSpace) -> np.ndarray:
        """Zeros, or with ``carry_q`` the previous generation's values where the interior
        posture and the action posture both persist (any exterior state)."""
        n_exterior = self.n_exterior
        q = np.zeros((space.n_interior, n_exterior, space.n_actions))
        if self.config.learning.carry_q and self._previous is not None:
            old_space, old_q = self._previous
            old_q = old_q.reshape(old_space.n_interior, n_exterior, old_space.n_actions)
            rows = _match(space.postures, old_space.postures)
            cols = _match(space.actions, old_space.actions)
            new_i, new_a = np.flatnonzero(rows >= 0), np.flatnonzero(cols >= 0)
            q[np.ix_(new_i, np.arange(n_exterior), new_a)] = old_q[
                np.ix_(rows[new_i], np.arange(n_exterior), cols[new_a])
            ]
        return q.reshape(space.n_interior * n_exterior, space.n_actions)

    def _learn_generation(self, index: int) -> Generation:
        """Q-learning over the current population's space, then fitness of its actions."""
        start = time.perf_counter()
        learning, fit = self.config.learning, self.config.fitness
        space = ExplorationSpace.from_population(self.population, self.world.start_posture())
        q = self._initial_q(space)
        uses = np.zeros(space.n_actions, dtype=np.int64)
        distances = np.zeros(learning.trials)
        fell = np.zeros(learning.trials, dtype=np.bool_)
        poses = np.zeros((learning.trial_steps + 1, 3))
        actions = np.zeros(learning.trial_steps, dtype=np.int64)
        if isinstance(self.world, World):
            steps, greedy_fell, greedy_distance = self._learn_in_world(
                space, q, uses, distances, fell, poses, actions
            )
        else:
            steps, greedy_fell, greedy_distance = self._learn_on_table(
                space, q, uses, distances, fell, poses, actions
            )
        self._previous = (space, q)
        return Generation(
            index=index,
            space=space,
            q=q,
            uses=uses,
            fitness=fitness(q, uses, p=fit.p, w_first=fit.w_first, w_last=fit.w_last, k_f=fit.k_f),
            distances=distances,
            fell=fell,
            steps=int(steps),
            greedy_poses=poses,
            greedy_actions=actions,
            greedy_fell=bool(greedy_fell),
            greedy_distance=greedy_distance,
            wall_s=time.perf_counter() - start,
        )

    def _schedule(self) -> np.ndarray:
        learning = self.config.learning
        return np.array(
            [learning.temperature_scale, learning.temperature_rate, learning.temperature_offset]
        )

    def _learn_on_table(
        self,
        space: ExplorationSpace,
        q: np.ndarray,
        uses: np.ndarray,
        distances: np.ndarray,
        fell: np.ndarray,
        poses: np.ndarray,
        actions: np.ndarray,
    ) -> tuple[int, bool, float]:
        """Compiled learning and greedy trial on the world's transition table."""
        learning = self.config.learning
        table = self.world.transitions(space.postures, space.actions)  # type: ignore[union-attr]
        dx, dy, dtheta = (
            np.ascontiguousarray(a, dtype=np.float64) for a in (table.dx, table.dy, table.dtheta)
        )
        failed = np.ascontiguousarray(table.failed, dtype=np.bool_)
        common = (dx, dy, dtheta, failed, space.next_interior, self.light, self.edges)
        steps = learn_on_table(
            q,
            *common,
            learning.trials,
            learning.trial_steps,
            learning.alpha,
            learning.gamma,
            self._schedule(),
            learning.reward_scale,
            learning.penalty,
            self.rng,
            uses,
            distances,
            fell,
        )
        greedy_fell = greedy_on_table(q, *common, learning.trial_steps, poses, actions)
        lx, ly = self.light
        greedy_distance = math.hypot(lx, ly) - math.hypot(lx - poses[-1, 0], ly - poses[-1, 1])
        return int(steps), bool(greedy_fell), greedy_distance

    def _learn_in_world(
        self,
        space: ExplorationSpace,
        q: np.ndarray,
        uses: np.ndarray,
        distances: np.ndarray,
        fell: np.ndarray,
        poses: np.ndarray,
        actions: np.ndarray,
    ) -> tuple[int, bool, float]:
        """The same learning and greedy trial, every command sent to a step-by-step world."""
        learning = self.config.learning
        world: World = self.world  # type: ignore[assignment]
        steps = learn_on_world(
            q,
            world,
            space.actions,
            space.next_interior,
            n_exterior=self.n_exterior,
            trials=learning.trials,
            trial_steps=learning.trial_steps,
            alpha=learning.alpha,
            gamma=learning.gamma,
            temperature_params=self._schedule(),
            rng=self.rng,
            uses=uses,
            distances=distances,
            fell=fell,
        )
        greedy_fell = greedy_on_world(
            q,
            world,
            space.actions,
            space.next_interior,
            n_exterior=self.n_exterior,
            trial_steps=learning.trial_steps,
            poses=poses,
            taken=actions,
        )
        return steps, greedy_fell, world.distance_covered()


def _match(postures: np.ndarray, old: np.ndarray) -> np.ndarray:
    """Row of ``old`` (m, J) equal to each row of ``postures`` (n, J), or -1; shape (n,)."""
    index = {row.tobytes(): k for k, row in enumerate(old)}
    return np.array([index.get(row.tobytes(), -1) for row in postures], dtype=np.int64)
