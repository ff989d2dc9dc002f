"""Structural dynamics: roulette selection, crossover and mutation of posture genes.

A population is an int64 array (N, J): one character per actuated joint, valued in
``0 .. levels[k] - 1``. Every draw comes from the ``np.random.Generator`` passed in.
"""

from __future__ import annotations

import numpy as np

from qdsega.agent.config import GeneticConfig


def random_population(levels: np.ndarray, size: int, rng: np.random.Generator) -> np.ndarray:
    """``size`` genes with every character uniform over its levels, shape (size, J)."""
    levels = np.asarray(levels, dtype=np.int64)
    if levels.ndim != 1 or np.any(levels < 1):
        raise ValueError(f"levels must be a (J,) array of positive counts, got {levels}")
    return (rng.random((size, len(levels))) * levels).astype(np.int64)


def roulette(fitness: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """Indices of ``count`` draws, each with probability proportional to fitness (>= 0).

    All-zero fitness selects uniformly (the limit of equal fitnesses).
    """
    fitness = np.asarray(fitness, dtype=np.float64)
    if np.any(fitness < 0) or not np.all(np.isfinite(fitness)):
        raise ValueError("fitness must be finite and non-negative")
    cumulative = np.cumsum(fitness)
    if cumulative[-1] <= 0:
        cumulative = np.arange(1.0, len(fitness) + 1.0)
    pointers = rng.random(count) * cumulative[-1]
    return np.minimum(np.searchsorted(cumulative, pointers, side="right"), len(fitness) - 1)


def roulette_weights(
    action_fitness: np.ndarray, action_of: np.ndarray, selection: str
) -> np.ndarray:
    """Each individual's share of the roulette wheel, shape (N,).

    Args:
        action_fitness: eq. (6) of each action (distinct phenotype), shape (A,).
        action_of: the action each individual expresses, shape (N,).
        selection: ``actions``: the wheel has one slot per action, as large as its fitness,
            split evenly among its copies (an action is drawn with probability proportional
            to its fitness, however many genes express it); ``individuals``: one slot per
            individual, each as large as its action's fitness (an action with ``n`` copies
            weighs ``n`` times its fitness).
    """
    action_fitness = np.asarray(action_fitness, dtype=np.float64)
    action_of = np.asarray(action_of, dtype=np.int64)
    weights = action_fitness[action_of]
    if selection == "actions":
        copies = np.bincount(action_of, minlength=len(action_fitness))
        return weights / copies[action_of]
    if selection == "individuals":
        return weights
    raise ValueError(f"selection must be actions or individuals, got {selection!r}")


def uniform_crossover(
    a: np.ndarray, b: np.ndarray, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Swap each character of two genes (J,) with probability 1/2."""
    swap = rng.random(a.shape) < 0.5
    return np.where(swap, b, a), np.where(swap, a, b)


def one_point_crossover(
    a: np.ndarray, b: np.ndarray, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Exchange the tails of two genes (J,) after a cut drawn uniformly in 1 .. J-1."""
    if len(a) < 2:
        return a.copy(), b.copy()
    cut = int(rng.integers(1, len(a)))
    return np.concatenate([a[:cut], b[cut:]]), np.concatenate([b[:cut], a[cut:]])


def mutate(
    population: np.ndarray, levels: np.ndarray, rate: float, rng: np.random.Generator
) -> np.ndarray:
    """Each character, with probability ``rate``, becomes a different level (uniform)."""
    levels = np.asarray(levels, dtype=np.int64)
    hit = (rng.random(population.shape) < rate) & (levels > 1)
    shift = 1 + (rng.random(population.shape) * (levels - 1)).astype(np.int64)
    return np.where(hit, (population + shift) % levels, population)


def vary_gait(
    commands: np.ndarray, levels: np.ndarray, rng: np.random.Generator, *, phase_share: float = 0.0
) -> np.ndarray:
    """A neighbour of a gait ``commands`` (k, J).

    A level move (the rest of the time): one character of one of its postures moved by 1 or 2
    levels (within the joint's range) wherever that posture occurs, so that a cycle stays a
    cycle. A phase move (a share ``phase_share`` of the time): one joint's column of commands
    one step earlier or later (the end held), so that joint's wave shifts against the others'
    while every cycle keeps its period.

    Raises:
        ValueError: no joint has more than one level.
    """
    commands = np.array(commands, dtype=np.int64)
    levels = np.asarray(levels, dtype=np.int64)
    joints = np.flatnonzero(levels > 1)
    if len(joints) == 0:
        raise ValueError("no joint has more than one level to vary")
    if phase_share > 0 and rng.random() < phase_share and len(commands) > 1:
        j = int(joints[rng.integers(len(joints))])
        column = commands[:, j].copy()
        if rng.random() < 0.5:  # earlier: the last command held
            commands[:-1, j] = column[1:]
        else:  # later: the first command held
            commands[1:, j] = column[:-1]
        return commands
    distinct = np.unique(commands, axis=0)
    posture = distinct[rng.integers(len(distinct))]
    j = int(joints[rng.integers(len(joints))])
    step = int(rng.choice([-2, -1, 1, 2]))
    level = posture[j] + step
    if not 0 <= level < levels[j]:
        level = posture[j] - step
    level = int(np.clip(level, 0, levels[j] - 1))
    if level == posture[j]:  # a two-level joint stepped by 2
        level = 1 - posture[j]
    commands[np.all(commands == posture, axis=1), j] = level
    return commands


def with_elite(population: np.ndarray, elite: np.ndarray) -> np.ndarray:
    """``population`` (N, J) with every posture of ``elite`` (k, J), k <= N // 2, present.

    Each missing elite posture replaces one individual, without a random draw: the last
    individual of the phenotype with the most copies, elite phenotypes spared. So the GA keeps
    its diversity, and a run continued from a saved state replaces the same individuals.
    """
    population = np.array(population, dtype=np.int64)
    elite = np.asarray(elite, dtype=np.int64).reshape(-1, population.shape[1])
    if len(elite) > len(population) // 2:
        raise ValueError(f"{len(elite)} elite postures for a population of {len(population)}")
    for posture in elite:
        if np.any(np.all(population == posture, axis=1)):
            continue
        _, action_of, counts = np.unique(
            population, axis=0, return_inverse=True, return_counts=True
        )
        copies = counts[action_of.reshape(-1)].astype(np.float64)
        spared = np.any(np.all(population[:, None, :] == elite[None], axis=2), axis=1)
        copies[spared] = -np.inf
        victim = len(population) - 1 - int(np.argmax(copies[::-1]))
        population[victim] = posture
    return population


def reproduce(
    population: np.ndarray,
    fitness: np.ndarray,
    levels: np.ndarray,
    config: GeneticConfig,
    rng: np.random.Generator,
) -> np.ndarray:
    """The next population: roulette, pairwise crossover, per-character mutation."""
    n = len(population)
    parents = population[roulette(fitness, n, rng)]
    children = parents.copy()
    cross = one_point_crossover if config.crossover == "one-point" else uniform_crossover
    for i in range(0, n - 1, 2):
        if rng.random() < config.crossover_rate:
            children[i], children[i + 1] = cross(parents[i], parents[i + 1], rng)
    return mutate(children, levels, config.mutation_rate, rng)
