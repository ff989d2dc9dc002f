"""Self-imitation: a Q-table raised along a trial to what that trial earned.

The best verified trial of a run (often a local search's open-loop gait in exact physics) is a
path the learner may never draw on its own: its postures are in the population (elitism), but
eq. (18)'s roulette rarely strings them together in the right order. Walking that path through
the generation's table gives the discounted return of every step on it, a lower bound on what
the step is worth (Oh et al., "Self-Imitation Learning", 2018: learn from one's own past
successes, max(Q, return)). Raising Q to that bound before learning lets the roulette and the
greedy policy take the path wherever nothing better is known; learning then goes on as usual.
"""

from __future__ import annotations

import numpy as np

from qdsega.agent.policy import Rollout
from qdsega.task import Task


def imitate(
    q: np.ndarray, trial: Rollout, next_interior: np.ndarray, *, task: Task, gamma: float
) -> None:
    """Raise ``q`` (n_interior * n_exterior, A), in place, along ``trial`` (a walk of the same
    space's actions from its start state): each step's entry becomes at least the step's
    discounted return, eq. (17)'s rewards plus ``gamma`` times the next, the last step
    bootstrapping from its state's best value as the learning loop does (a failed step: the
    penalty alone)."""
    n_exterior = task.n_exterior
    taken = trial.actions[trial.actions >= 0]
    rows = np.empty(len(taken) + 1, dtype=np.int64)
    interior = 0
    for t, a in enumerate(taken):
        rows[t] = interior * n_exterior + task.exterior(tuple(trial.poses[t]))
        interior = int(next_interior[a])
    rows[-1] = interior * n_exterior + task.exterior(tuple(trial.poses[len(taken)]))
    future = float(q[rows[-1]].max())
    for t in range(len(taken) - 1, -1, -1):
        if trial.failed and t == len(taken) - 1:
            value = task.penalty
        else:
            value = task.reward(tuple(trial.poses[t]), tuple(trial.poses[t + 1])) + gamma * future
        q[rows[t], taken[t]] = max(q[rows[t], taken[t]], value)
        future = value
