"""Learning dynamics on a step-by-step :class:`~qdsega.agent.model.StepModel`, in Python.

The same algorithm as the compiled table loop (:mod:`qdsega.agent.qlearning`), step for step:
Boltzmann roulette at eq. (18)'s temperature with one uniform draw per step, eq. (1) updates,
a failed command terminal with the model's penalty. Only the model differs: here every command
goes to the model (exact physics), so this loop serves budgets of hundreds of steps, not the
paper's millions. The greedy trial is :func:`qdsega.agent.policy.rollout`, in any model.
"""

from __future__ import annotations

import numpy as np

from qdsega.agent.boltzmann import boltzmann_select, temperature
from qdsega.agent.model import StepModel
from qdsega.agent.qlearning import q_update


def learn_on_model(
    q: np.ndarray,
    model: StepModel,
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
    """One generation of Q-learning in ``model``; updates ``q`` (states, A) in place.

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
        exterior = model.start_trial()
        interior = 0
        fell[trial] = False
        for _ in range(trial_steps):
            s = interior * n_exterior + exterior
            a = boltzmann_select(q[s], temp, rng.random(), weights)
            uses[a] += 1
            steps += 1
            result = model.command(actions[a])
            if result.failed:
                q[s, a] = (1.0 - alpha) * q[s, a] + alpha * result.reward
                fell[trial] = True
                break
            interior = int(next_interior[a])
            exterior = result.exterior
            best_next = float(q[interior * n_exterior + exterior].max())
            q[s, a] = q_update(q[s, a], result.reward, best_next, alpha, gamma)
        distances[trial] = model.distance_covered()
    return steps
