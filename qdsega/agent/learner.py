"""QDSEGA's outer loop (Fig. 7): build the Q-table from the population, learn, rate, reproduce.

Each generation's Q-table starts from the previous one's values where the interior posture
and the action posture both persist, zeros elsewhere (``carry_q``; zeros everywhere without
it), and eq. (18)'s schedule restarts with it: a new population is a new set of actions and
states (the paper's 10000 trials per generation cool the temperature from 408 to below 1e-6,
so each generation is a full learning run). Reproduction draws parents from a roulette wheel
with one slot per action or per gene (``GeneticConfig.selection``). With
``GeneticConfig.elitism`` the postures of the best greedy trial verified so far
(:meth:`QDSEGA.verify`) are put back into a population that lost them before it learns; with
``LearningConfig.imitate_elite`` the Q-table is raised along that trial's path before it learns
(:mod:`qdsega.agent.imitation`).
"""

from __future__ import annotations

import copy
import time
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from qdsega.agent.config import QDSEGAConfig
from qdsega.agent.fitness import fitness
from qdsega.agent.genetic import random_population, reproduce, roulette_weights, with_elite
from qdsega.agent.imitation import imitate
from qdsega.agent.model import StepModel, TransitionProvider, Transitions
from qdsega.agent.policy import GreedyPolicy, Rollout, SequencePolicy, rollout
from qdsega.agent.qlearning import learn_on_table
from qdsega.agent.space import ExplorationSpace
from qdsega.agent.step_loop import learn_on_model
from qdsega.agent.table_model import TableModel
from qdsega.task import Task


@dataclass(frozen=True)
class Generation:
    """What one generation learnt, and how its greedy policy walks in the learner's model.

    Attributes:
        index: generation number, from 1.
        space: the population's actions and interior states.
        q: the learnt Q-table, shape (n_interior * n_exterior, A).
        uses: times each action was chosen, shape (A,).
        fitness: eq. (6) per action, shape (A,).
        distances: distance toward the light covered by each trial (m), shape (trials,).
        fell: whether each trial ended in a fall, shape (trials,).
        steps: commands issued while learning.
        greedy: the greedy policy's trial in the learner's model (for a table model: what the
            table predicts).
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
    greedy: Rollout
    wall_s: float

    @property
    def policy(self) -> GreedyPolicy:
        """The generation's greedy policy."""
        return GreedyPolicy.of(self.space, self.q)


@dataclass(frozen=True)
class LearnerState:
    """Where a learner stands between two generations: enough to continue exactly.

    Attributes:
        completed: generations learnt.
        population: the population the next generation learns over, shape (N, J).
        rng_state: the random generator's ``bit_generator.state`` (plain dict, JSON-safe).
        previous: the last generation's space and Q-table (``carry_q`` starts from it), or
            None before the first generation.
        elite: the postures of the best verified greedy trial, shape (k, J) (k = 0 before
            any), and its distance toward the light (m; None before any).
        elite_path: that trial's reached postures in the order commanded, shape (k', J)
            (k' = 0 before any, and in a state saved before paths were kept).
    """

    completed: int
    population: np.ndarray
    rng_state: Mapping[str, Any]
    previous: tuple[ExplorationSpace, np.ndarray] | None
    elite: tuple[np.ndarray, float | None]
    elite_path: np.ndarray | None = None


def elite_postures(path: np.ndarray, population: int) -> np.ndarray:
    """The postures elitism puts back from an elite trial's ``path`` (k, J): its distinct
    postures, the most used first, at most half of ``population``, in sorted order, shape
    (e, J)."""
    postures, counts = np.unique(np.asarray(path, dtype=np.int64), axis=0, return_counts=True)
    keep = np.argsort(-counts, kind="stable")[: population // 2]
    return postures[np.sort(keep)]


class QDSEGA:
    """The learner on a posture-transition model.

    Args:
        config: every hyperparameter.
        levels: level count of each gene character (actuated joint), shape (J,).
        model: a transition table (learning runs compiled) or a step-by-step model such as
            exact physics (the same algorithm in Python, :mod:`qdsega.agent.step_loop`).
        task: the rules the learner is rewarded by (a step-by-step model applies them itself).
        rng: the only source of randomness.
    """

    def __init__(
        self,
        *,
        config: QDSEGAConfig,
        levels: np.ndarray,
        model: TransitionProvider | StepModel,
        task: Task,
        rng: np.random.Generator,
    ) -> None:
        levels = np.asarray(levels, dtype=np.int64)
        if levels.shape != (model.n_joints,):
            raise ValueError(f"levels must be ({model.n_joints},), got {levels.shape}")
        self.config = config
        self.levels = levels
        self.model = model
        self.task = task
        self.rng = rng
        self.population = random_population(levels, config.genetic.population, rng)
        self.completed = 0
        """Generations learnt so far."""
        self._previous: tuple[ExplorationSpace, np.ndarray] | None = None
        self._elite = np.zeros((0, len(levels)), dtype=np.int64)
        self._elite_m: float | None = None
        self._elite_path = np.zeros((0, len(levels)), dtype=np.int64)

    def run(self) -> Iterator[Generation]:
        """Yield every remaining generation in turn (see :meth:`step`)."""
        while self.completed < self.config.genetic.generations:
            yield self.step()

    def step(self) -> Generation:
        """Learn the next generation, then (unless it was the last, or ``genetic.reproduce`` is
        off) reproduce the population, so that :meth:`state` afterwards is where the following
        generation starts."""
        generation = self._learn_generation(self.completed + 1)
        self.completed += 1
        genetic = self.config.genetic
        if genetic.reproduce and self.completed < genetic.generations:
            weights = roulette_weights(
                generation.fitness, generation.space.action_of, genetic.selection
            )
            self.population = reproduce(self.population, weights, self.levels, genetic, self.rng)
        return generation

    def verify(self, trial: Rollout) -> None:
        """Tell the learner how a trial from its model's start posture walked when verified
        (with exact physics where it learns on a table): a generation's greedy policy, a local
        search's gait, a warm start's path. The best such trial so far is the elite: with
        ``genetic.elitism`` every later population that lost one of its postures gets it back
        (the most used first, at most half the population)."""
        if self._elite_m is not None and trial.distance_m <= self._elite_m:
            return
        reached = trial.reached_postures(self.model.start_posture())[1:]
        self._elite = elite_postures(reached, self.config.genetic.population)
        self._elite_m = trial.distance_m
        self._elite_path = reached.copy()

    @property
    def untried_path(self) -> np.ndarray | None:
        """The elite path a warm start handed on (:func:`qdsega.training.reconfiguration.
        warm_state`) while no trial on this body has been verified, shape (k, J); else None.
        A model that can replay it with exact physics does so before the first generation
        (the training loop, :mod:`qdsega.training.run`)."""
        if self._elite_m is None and len(self._elite_path):
            return self._elite_path.copy()
        return None

    def explore(
        self, generation: Generation, table: Transitions, rng: np.random.Generator
    ) -> GreedyPolicy:
        """The greedy policy of one more learning phase over ``generation``'s space, on
        ``table`` (an optimistic view of the model, say), from its Q-table; ``rng`` draws the
        roulette, so the learner's own generator and state are untouched."""
        q = generation.q.copy()
        uses = np.zeros(generation.space.n_actions, dtype=np.int64)
        trials = self.config.learning.trials
        distances, fell = np.zeros(trials), np.zeros(trials, dtype=np.bool_)
        self._learn_on_table(generation.space, table, q, uses, distances, fell, rng)
        return GreedyPolicy.of(generation.space, q)

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
            elite=(self._elite.copy(), self._elite_m),
            elite_path=self._elite_path.copy(),
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
            self._previous = (space, self._sensing(space, q))
        elite, self._elite_m = state.elite
        if elite.shape[1:] != (len(self.levels),) or len(elite) > len(self.population) // 2:
            raise ValueError(f"state elite {elite.shape} does not fit this learner")
        self._elite = elite.astype(np.int64)
        path = state.elite_path
        self._elite_path = np.zeros((0, len(self.levels)), dtype=np.int64)
        if path is not None and len(path):
            self._elite_path = np.asarray(path, dtype=np.int64).reshape(-1, len(self.levels))

    def _sensing(self, space: ExplorationSpace, q: np.ndarray) -> np.ndarray:
        """A copy of ``q`` with this task's exterior states: a table learnt where nothing stood
        holds for every sensed state; one learnt among obstacles gives its clear state's
        values where nothing stands (a warm start from another world)."""
        n_light, n_exterior = len(self.task.edges), self.task.n_exterior
        rows = q.reshape(space.n_interior, -1, space.n_actions)
        if rows.shape[1] == n_exterior:
            return q.copy()
        if rows.shape[1] == n_light:
            rows = np.tile(rows, (1, n_exterior // n_light, 1))
        elif n_exterior == n_light and rows.shape[1] % n_light == 0:
            rows = rows[:, :n_light]
        else:
            raise ValueError(f"state Q-table {q.shape} does not fit {n_exterior} exterior states")
        return rows.reshape(space.n_interior * n_exterior, space.n_actions).copy()

    def _initial_q(self, space: ExplorationSpace) -> np.ndarray:
        """Zeros, or with ``carry_q`` the previous generation's values where the interior
        posture and the action posture both persist (any exterior state), and for an action
        new to such a state what ``new_action_q`` says."""
        n_exterior = self.task.n_exterior
        q = np.zeros((space.n_interior, n_exterior, space.n_actions))
        if self.config.learning.carry_q and self._previous is not None:
            old_space, old_q = self._previous
            old_q = old_q.reshape(old_space.n_interior, n_exterior, old_space.n_actions)
            rows = _match(space.postures, old_space.postures)
            cols = _match(space.actions, old_space.actions)
            kept_i, kept_a = np.flatnonzero(rows >= 0), np.flatnonzero(cols >= 0)
            carried = old_q[np.ix_(rows[kept_i], np.arange(n_exterior), cols[kept_a])]
            q[np.ix_(kept_i, np.arange(n_exterior), kept_a)] = carried
            if self.config.learning.new_action_q == "row_best" and len(kept_a):
                added = np.flatnonzero(cols < 0)
                q[np.ix_(kept_i, np.arange(n_exterior), added)] = carried.max(axis=2)[..., None]
        return q.reshape(space.n_interior * n_exterior, space.n_actions)

    def _learn_generation(self, index: int) -> Generation:
        """Q-learning over the current population's space, its greedy trial, then the fitness
        of its actions."""
        start = time.perf_counter()
        trials, fit = self.config.learning.trials, self.config.fitness
        if self.config.genetic.elitism:
            self.population = with_elite(self.population, self._elite)
        space = ExplorationSpace.from_population(self.population, self.model.start_posture())
        q = self._initial_q(space)
        uses = np.zeros(space.n_actions, dtype=np.int64)
        distances = np.zeros(trials)
        fell = np.zeros(trials, dtype=np.bool_)
        if isinstance(self.model, StepModel):
            steps = self._learn_in_world(space, self.model, q, uses, distances, fell)
            greedy_world: StepModel = self.model
        else:
            table = self.model.transitions(space.postures, space.actions)
            if self.config.learning.imitate_elite:
                self._imitate_elite(space, table, q)
            steps = self._learn_on_table(space, table, q, uses, distances, fell, self.rng)
            greedy_world = TableModel(space=space, table=table, task=self.task)
        greedy = rollout(GreedyPolicy.of(space, q), greedy_world, steps=self.task.trial_steps)
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
            greedy=greedy,
            wall_s=time.perf_counter() - start,
        )

    def _imitate_elite(self, space: ExplorationSpace, table: Transitions, q: np.ndarray) -> None:
        """Raise ``q`` along the elite trial's path as ``table`` walks it, up to its first
        posture the population lost (elitism keeps at most half the population's worth)."""
        actions = {row.tobytes() for row in space.actions}
        path = self._elite_path
        lost = [t for t, row in enumerate(path) if row.tobytes() not in actions]
        path = path[: lost[0]] if lost else path
        if len(path) == 0:
            return
        walk = rollout(
            SequencePolicy(commands=path, space=space),
            TableModel(space=space, table=table, task=self.task),
            steps=min(len(path), self.task.trial_steps),
        )
        imitate(q, walk, space.next_interior, task=self.task, gamma=self.config.learning.gamma)

    def _schedule(self) -> np.ndarray:
        learning = self.config.learning
        return np.array(
            [learning.temperature_scale, learning.temperature_rate, learning.temperature_offset]
        )

    def _learn_on_table(
        self,
        space: ExplorationSpace,
        table: Transitions,
        q: np.ndarray,
        uses: np.ndarray,
        distances: np.ndarray,
        fell: np.ndarray,
        rng: np.random.Generator,
    ) -> int:
        """Compiled learning on a transition table; returns the steps taken."""
        task, learning = self.task, self.config.learning
        return int(
            learn_on_table(
                q,
                *table.compiled(),
                space.next_interior,
                task.light,
                task.edges,
                *task.map_arrays(),
                learning.trials,
                task.trial_steps,
                learning.alpha,
                learning.gamma,
                self._schedule(),
                task.config.reward_per_m,
                task.penalty,
                rng,
                uses,
                distances,
                fell,
            )
        )

    def _learn_in_world(
        self,
        space: ExplorationSpace,
        model: StepModel,
        q: np.ndarray,
        uses: np.ndarray,
        distances: np.ndarray,
        fell: np.ndarray,
    ) -> int:
        """The same learning, every command sent to a step-by-step model."""
        learning = self.config.learning
        return learn_on_model(
            q,
            model,
            space.actions,
            space.next_interior,
            n_exterior=self.task.n_exterior,
            trials=learning.trials,
            trial_steps=self.task.trial_steps,
            alpha=learning.alpha,
            gamma=learning.gamma,
            temperature_params=self._schedule(),
            rng=self.rng,
            uses=uses,
            distances=distances,
            fell=fell,
        )


def _match(postures: np.ndarray, old: np.ndarray) -> np.ndarray:
    """Row of ``old`` (m, J) equal to each row of ``postures`` (n, J), or -1; shape (n,)."""
    index = {row.tobytes(): k for k, row in enumerate(old)}
    return np.array([index.get(row.tobytes(), -1) for row in postures], dtype=np.int64)
