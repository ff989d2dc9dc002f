"""Fitness of actions from the learnt Q-table and their use: eqs. (2)-(6), section 3.2.8-10.

Division guards, each the value the equations imply:

* eq. (2) divides by ``V_max(s)``; it is used only for ``Q >= 0``, and ``V_max(s) = 0`` then
  means the value is 0 too (a state whose values are all zero, e.g. never visited, or all
  non-positive). Eq. (2) maps 0 to ``p`` for every positive ``V_max``, so 0 maps to ``p``.
* eq. (3) divides by ``V_min(s)``; it is used only for ``Q < 0``, so ``V_min(s) <= Q < 0``
  and never 0. An all-negative state maps into [0, p), its worst action to 0.
* eq. (5) divides by the total use; with no use at all (no step taken), every ``fit_u`` is 0.

Every state of the table counts in eq. (4) (``N_s`` = interior x exterior states), visited or
not; an unvisited state gives every action ``p``.
"""

from __future__ import annotations

import numpy as np


def regulate(q: np.ndarray, p: float) -> np.ndarray:
    """Eqs. (2)-(3): the regulated table Q', same shape (N_s, A), values in [0, 1]."""
    q = np.asarray(q, dtype=np.float64)
    v_max = q.max(axis=1, keepdims=True)
    v_min = q.min(axis=1, keepdims=True)
    positive = np.divide(q, v_max, out=np.zeros_like(q), where=(q >= 0) & (v_max > 0))
    negative = np.divide(q, v_min, out=np.zeros_like(q), where=q < 0)
    return np.where(q >= 0, (1.0 - p) * positive + p, -p * negative + p)


def fitness_q(regulated: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Eq. (4): per action, the weighted means of its top-j regulated values.

    Args:
        regulated: Q' of shape (N_s, A).
        weights: w_1 .. w_Ns, shape (N_s,).

    Returns:
        fit_Q per action, shape (A,).
    """
    regulated = np.asarray(regulated, dtype=np.float64)
    n_states = regulated.shape[0]
    if np.shape(weights) != (n_states,):
        raise ValueError(f"need {n_states} weights, got shape {np.shape(weights)}")
    sorted_desc = -np.sort(-regulated, axis=0)
    prefix_means = np.cumsum(sorted_desc, axis=0) / np.arange(1, n_states + 1)[:, None]
    return np.asarray(weights, dtype=np.float64) @ prefix_means


def end_weights(n_states: int, w_first: float, w_last: float) -> np.ndarray:
    """Weights of eq. (4) with ``w_1 = w_first``, ``w_Ns = w_last`` and 0 between."""
    if n_states < 1:
        raise ValueError(f"need at least one state, got {n_states}")
    weights = np.zeros(n_states)
    weights[0] += w_first
    weights[-1] += w_last
    return weights


def fitness_use(uses: np.ndarray) -> np.ndarray:
    """Eq. (5): each action's share of all uses this generation, shape (A,)."""
    uses = np.asarray(uses, dtype=np.float64)
    total = uses.sum()
    return uses / total if total > 0 else np.zeros_like(uses)


def fitness(
    q: np.ndarray, uses: np.ndarray, *, p: float, w_first: float, w_last: float, k_f: float
) -> np.ndarray:
    """Eq. (6): ``fit_Q + k_f fit_u`` per action, from the Q-table (N_s, A) and uses (A,)."""
    q = np.asarray(q)
    weights = end_weights(q.shape[0], w_first, w_last)
    return fitness_q(regulate(q, p), weights) + k_f * fitness_use(uses)
