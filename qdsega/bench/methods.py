"""The methods the benchmark compares, each run as ``method(task, seed, folder) -> Curve``.

* ``qdsega``: QDSEGA as the paper gives it (the task's preset), a ``qdsega train`` run;
  ``qdsega-no-carry``: the same without the carried-over Q-table (``carry_q: false``);
  ``fixed-set``: Q-learning over the first generation's random postures for the whole run, no
  GA (``reproduce: false``, ``elitism: false``). Their curve is the exact distance of each
  generation's greedy policy against the run's steps: learning steps in the MSM, steps
  simulated in PyBullet (memo transitions measured, exact replays) in memo mode.
* ``ga-sequence``: a GA over whole posture sequences, fitness the distance of one trial.
* ``random-search``: uniformly random posture sequences, the best one kept.
* ``cma-cpg``: CMA-ES over a CPG gait's parameters
  (:func:`qdsega.baselines.reference_search.search_cpg`, the reference search as a learner).
* ``ppo``: :mod:`qdsega.bench.ppo`.
* ``ppo-joint``, ``sac-joint``: PPO and SAC under continuous control (joint targets), PyBullet
  tasks only; steps are posture steps' worth of physics time
  (:mod:`qdsega.bench.joint_learners`).

The sequence methods play one trial per candidate in the task's arena; their answer is the best
sequence that completed a trial so far, and its distance there is exact by construction. Every
method learns and is judged in the task's world (:meth:`BenchTask.load_world`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.baselines.reference_search import search_cpg
from qdsega.bench.arena import Arena
from qdsega.bench.curve import Curve
from qdsega.bench.tasks import BenchTask
from qdsega.description import resolve_formation
from qdsega.locomotion.env import Replay
from qdsega.training.run import train_or_resume
from qdsega.training.run_folder import RunFolder

Method = Callable[[BenchTask, int, Path], Curve]

GA_POPULATION = {"msm": 64, "pybullet": 16}
"""Sequences per GA generation, by simulator (-): fewer in PyBullet, whose budget holds about a
hundred trials."""
GA_ELITES = 2
"""Best sequences a GA generation keeps unchanged (-)."""
GA_CROSSOVER_RATE = 0.9
"""Probability that a GA child is a uniform crossover of two parents, step by step (-)."""
GA_MUTATIONS = 2.0
"""Expected characters (joint levels) a GA child has mutated (-)."""
BATCH_STEPS = {"msm": 30_000, "pybullet": 300}
"""Upper-agent steps of trials played per batch by random search (-)."""


def qdsega(task: BenchTask, seed: int, folder: Path) -> Curve:
    """QDSEGA as the paper gives it."""
    return _qdsega(task, seed, folder, {}, {})


def qdsega_no_carry(task: BenchTask, seed: int, folder: Path) -> Curve:
    """QDSEGA, every generation's Q-table starting from zeros."""
    return _qdsega(task, seed, folder, {"carry_q": False}, {})


def fixed_set(task: BenchTask, seed: int, folder: Path) -> Curve:
    """Q-learning over one random posture set of the population's size, no GA."""
    return _qdsega(task, seed, folder, {}, {"reproduce": False, "elitism": False})


def _qdsega(
    task: BenchTask,
    seed: int,
    folder: Path,
    learning: dict[str, Any],
    genetic: dict[str, Any],
) -> Curve:
    """A training run into ``folder/run`` (resumed where a crash left it), read back."""
    run = folder / "run"
    config = task.config(seed=seed, learning=learning, genetic=genetic)
    train_or_resume(resolve_formation(task.formation), config, run, world=task.load_world())
    column = RunFolder(run).read_metrics()
    steps = np.cumsum(column["steps"]) if task.sim == "msm" else column["sim_steps"]
    return Curve(steps.astype(np.int64), column["greedy_exact_m"], np.cumsum(column["wall_s"]))


class _Best:
    """The best completed trial so far, as a curve: a point at every improvement."""

    def __init__(self, arena: Arena) -> None:
        self.arena = arena
        self.start = time.perf_counter()
        self.distance_m: float | None = None
        self.points: list[tuple[int, float, float]] = []

    def play(self, sequences: Sequence[np.ndarray]) -> list[Replay]:
        """Play ``sequences`` in the arena and note any improvement."""
        before = self.arena.commands
        outcomes = self.arena.replays(sequences)
        spent = before
        for outcome in outcomes:
            spent += outcome.completed + (outcome.failure is not None)
            if outcome.failure is None and (
                self.distance_m is None or outcome.distance_m > self.distance_m
            ):
                self.distance_m = outcome.distance_m
                self.points.append((spent, outcome.distance_m, time.perf_counter() - self.start))
        return outcomes

    def curve(self, budget: int) -> Curve:
        """The curve within ``budget``, closed by a point where the budget or the run ended."""
        points = [p for p in self.points if p[0] <= budget]
        final = points[-1][1] if points else 0.0
        end = (min(self.arena.commands, budget), final, time.perf_counter() - self.start)
        return Curve.of([*points, end])


def _levels(task: BenchTask) -> np.ndarray:
    return np.array([len(joint.levels_rad) for joint in task.load().joints], dtype=np.int64)


def random_search(task: BenchTask, seed: int, folder: Path) -> Curve:
    """Uniformly random posture sequences, a batch at a time, until the budget is spent."""
    rng, levels, steps = np.random.default_rng(seed), _levels(task), task.rules().trial_steps
    arena = task.arena()
    best = _Best(arena)
    batch = max(1, BATCH_STEPS[task.sim] // steps)
    try:
        while arena.commands < task.budget_steps:
            size = (_within(task, arena, batch, steps), steps, len(levels))
            best.play(list(rng.integers(0, levels, size=size)))
        return best.curve(task.budget_steps)
    finally:
        arena.close()


def ga_sequence(task: BenchTask, seed: int, folder: Path) -> Curve:
    """A generational GA over posture sequences (steps, J): binary tournaments, uniform
    crossover of whole steps, per-character mutation to another level, elitism."""
    rng, levels, steps = np.random.default_rng(seed), _levels(task), task.rules().trial_steps
    arena = task.arena()
    best = _Best(arena)
    rate = min(1.0, GA_MUTATIONS / (steps * len(levels)))
    size = GA_POPULATION[task.sim]
    population = rng.integers(0, levels, size=(size, steps, len(levels)))
    try:
        while arena.commands < task.budget_steps:
            played: list[Replay] = []
            while len(played) < size and arena.commands < task.budget_steps:
                more = population[len(played) : len(played) + _within(task, arena, size, steps)]
                played += best.play(list(more))
            if len(played) < size:
                break  # the budget ended within this generation
            scores = np.array([_score(o, steps) for o in played])
            order = np.argsort(-scores, kind="stable")
            children = [population[k] for k in order[:GA_ELITES]]
            while len(children) < size:
                a, b = (_tournament(scores, rng) for _ in range(2))
                child = population[a].copy()
                if rng.random() < GA_CROSSOVER_RATE:
                    swap = rng.random(steps) < 0.5
                    child[swap] = population[b][swap]
                mutate = rng.random(child.shape) < rate
                shift = rng.integers(1, np.broadcast_to(levels, child.shape))
                child[mutate] = ((child + shift) % levels)[mutate]
                children.append(child)
            population = np.stack(children)
        return best.curve(task.budget_steps)
    finally:
        arena.close()


def _within(task: BenchTask, arena: Arena, trials: int, steps: int) -> int:
    """How many of ``trials`` trials of ``steps`` steps to play so that the budget is not
    overrun by more than one trial."""
    left = task.budget_steps - arena.commands
    return max(1, min(trials, -(-left // steps)))


def _score(outcome: Replay, steps: int) -> float:
    """A trial's rank: its distance when it completed, else below every completed trial, by
    the steps it completed."""
    if outcome.failure is None:
        return outcome.distance_m
    return -1e6 + outcome.completed / steps


def _tournament(scores: np.ndarray, rng: np.random.Generator) -> int:
    a, b = rng.integers(0, len(scores), size=2)
    return int(a if scores[a] >= scores[b] else b)


def cma_cpg(task: BenchTask, seed: int, folder: Path) -> Curve:
    """CMA-ES over a CPG gait, ``budget_steps // trial_steps`` trials in whole iterations
    (trials that fail early leave steps unspent)."""
    steps = task.rules().trial_steps
    arena = task.arena()
    best = _Best(arena)
    try:
        search_cpg(
            task.load(),
            replay=best.play,
            trial_steps=steps,
            budget_trials=task.budget_steps // steps,
            seed=seed,
        )
        return best.curve(task.budget_steps)
    finally:
        arena.close()


def ppo(task: BenchTask, seed: int, folder: Path) -> Curve:
    """PPO from stable-baselines3 (:mod:`qdsega.bench.ppo`)."""
    from qdsega.bench.ppo import ppo_curve  # needs the bench extra: only here

    return ppo_curve(task, seed)


def ppo_joint(task: BenchTask, seed: int, folder: Path) -> Curve:
    """PPO from stable-baselines3 driving the joints (:mod:`qdsega.bench.joint_learners`)."""
    from qdsega.bench.joint_learners import joint_curve  # needs the bench extra: only here

    return joint_curve(task, seed, learner="ppo")


def sac_joint(task: BenchTask, seed: int, folder: Path) -> Curve:
    """SAC from stable-baselines3 driving the joints (:mod:`qdsega.bench.joint_learners`)."""
    from qdsega.bench.joint_learners import joint_curve  # needs the bench extra: only here

    return joint_curve(task, seed, learner="sac")


METHODS: dict[str, Method] = {
    "qdsega": qdsega,
    "qdsega-no-carry": qdsega_no_carry,
    "fixed-set": fixed_set,
    "ga-sequence": ga_sequence,
    "random-search": random_search,
    "cma-cpg": cma_cpg,
    "ppo": ppo,
    "ppo-joint": ppo_joint,
    "sac-joint": sac_joint,
}
"""Every method, by name."""
ABLATIONS = ("qdsega-no-carry", "fixed-set")
"""The methods that are QDSEGA with a part taken out."""
