"""Learning dynamics on a step-by-step :class:`~qdsega.agent.world.World`, in Python.

The same algorithm as the compiled table loop (:mod:`qdsega.agent.qlearning`), step for step:
Boltzmann roulette at eq. (18)'s temperature with one uniform draw per step, eq. (1) updates,
a failed command terminal with the world's penalty. Only the world differs: here every command
goes to the world (exact physics), so this loop serves budgets of hundreds of steps, not the
paper's millions. The greedy trial is :func:`qdsega.agent.policy.rollout`, in any world.
"""

from __future__ import annotations

import numpy as np

from qdsega.agent.boltzmann import boltzmann_select, temperature
from qdsega.agent.qlearning import q_update
from qdsega.agent.world import World


def learn_on_world(
    q: np.ndarray,
    world: World,
    actions: np.ndarray,
    next_interior: np.ndarray,
    *,
    n_exterior: int,
    trials: int,
    trial_steps: int,
    alpha: float,
    gamma: float,
    temperature_params: np.ndarray,
    rng: np.random.Generator,
    uses: np.ndarray,
    distances: np.ndarray,
    fell: np.ndarray,
) -> int:
    """One generation of Q-learning in ``world``; updates ``q`` (states, A) in place.

    Args:
        actions: the action postures, shape (A, J).
        next_interior: interior state each action leads to, shape (A,).
        n_exterior: exterior states per interior state; ``q`` row = interior * n + exterior.
        (others as :func:`qdsega.agent.qlearning.learn_on_table`)

    Returns:
        The number of steps (commands) taken.
    """
    weights = np.empty(q.shape[1])
    steps = 0
    for trial in range(trials):
        temp = temperature(trial, *temperature_params)
        exterior = world.start_trial()
        interior = 0
        fell[trial] = False
        for _ in range(trial_steps):
            s = interior * n_exterior + exterior
            a = boltzmann_select(q[s], temp, rng.random(), weights)
            uses[a] += 1
            steps += 1
            result = world.command(actions[a])
            if result.failed:
                q[s, a] = (1.0 - alpha) * q[s, a] + alpha * result.reward
                fell[trial] = True
                break
            interior = int(next_interior[a])
            exterior = result.exterior
            best_next = float(q[interior * n_exterior + exterior].max())
            q[s, a] = q_update(q[s, a], result.reward, best_next, alpha, gamma)
        distances[trial] = world.distance_covered()
    return steps
