"""Boltzmann roulette selection of actions with the temperature schedule of eq. (18)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_UNDERFLOW = -746.0
"""Below this, ``math.exp`` returns exactly 0.0 in float64."""


@njit(cache=True)
def temperature(trial: int, scale: float, rate: float, offset: float) -> float:
    """Eq. (18): ``T = scale * exp(-rate * trial + offset)``; trials count from 0."""
    return scale * math.exp(-rate * trial + offset)


@njit(cache=True)
def boltzmann_select(q_row: np.ndarray, temp: float, u: float, weights: np.ndarray) -> int:
    """Draw an action with probability proportional to ``exp(Q(s, a) / T)``.

    Args:
        q_row: Q(s, .) of the current state, shape (A,).
        temp: temperature T (> 0).
        u: a uniform draw in [0, 1); the roulette's pointer.
        weights: scratch space, shape (>= A,).
    """
    top = q_row[0]
    for a in range(1, q_row.shape[0]):
        if q_row[a] > top:
            top = q_row[a]
    return boltzmann_select_below(q_row, top, temp, u, weights)


@njit(cache=True)
def boltzmann_select_below(
    q_row: np.ndarray, top: float, temp: float, u: float, weights: np.ndarray
) -> int:
    """:func:`boltzmann_select` given the row's maximum ``top`` (the compiled loop keeps it).

    The weights are computed as ``exp((Q - max Q) / T)`` (the same distribution, no overflow);
    once T is small they underflow to exactly 0 for all but the best actions, and the roulette
    is greedy (ties: proportional among the best).
    """
    n = q_row.shape[0]
    scale = 1.0 / temp
    # Untried actions all have Q = 0: one exponential serves them all.
    x = -top * scale
    w_zero = math.exp(x) if x > _UNDERFLOW else 0.0
    total = 0.0
    for a in range(n):
        if q_row[a] == 0.0:
            w = w_zero
        else:
            x = (q_row[a] - top) * scale
            # exp(x) is exactly 0.0 in float64 below -745.2: skip the call, same result.
            w = math.exp(x) if x > _UNDERFLOW else 0.0
        weights[a] = w
        total += w
    pointer = u * total
    acc = 0.0
    for a in range(n):
        acc += weights[a]
        if pointer < acc:
            return a
    # Rounding can leave the pointer at the very end: take the last action with weight.
    for a in range(n - 1, -1, -1):
        if weights[a] > 0.0:
            return a
    return n - 1


@njit(cache=True)
def greedy(q_row: np.ndarray) -> int:
    """The action with the largest Q(s, .); the first one on ties."""
    best = 0
    for a in range(1, q_row.shape[0]):
        if q_row[a] > q_row[best]:
            best = a
    return best
