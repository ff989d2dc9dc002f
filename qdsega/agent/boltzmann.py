"""Boltzmann roulette selection of actions with the temperature schedule of eq. (18)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from qdsega.jit import njit_no_refcount

UNDERFLOW = -746.0
"""Below this, ``math.exp`` returns exactly 0.0 in float64."""
_LOG2E = 1.4426950408889634
_LN2_HI, _LN2_LO = 6.93147180369123816490e-01, 1.90821492927058770002e-10
"""ln 2 in two parts (Cody and Waite): ``k * _LN2_HI`` is exact for the k used here."""
_MARGIN = 1e-10
"""How close (relative to the total weight) the roulette's pointer may come to the end of an
action's share before :func:`boltzmann_select_fast` defers to the exact roulette: far above
the approximate weights' error (below 1e-12 relative) and the rounding of 10^4 float sums."""


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


@njit_no_refcount()
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
    w_zero = math.exp(x) if x > UNDERFLOW else 0.0
    total = 0.0
    for a in range(n):
        if q_row[a] == 0.0:
            w = w_zero
        else:
            x = (q_row[a] - top) * scale
            # exp(x) is exactly 0.0 in float64 below -745.2: skip the call, same result.
            w = math.exp(x) if x > UNDERFLOW else 0.0
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


@njit_no_refcount()
def live_actions(
    q_row: np.ndarray, top: float, temp: float, slack: float, limit: int, members: np.ndarray
) -> int:
    """The actions whose weight at ``temp`` is above ``exp(UNDERFLOW - slack)``, written to
    ``members`` (increasing); how many, or -1 (nothing written) where more than ``limit``.

    Only these can have weight while the temperature does not rise, their Q values do not
    change (actions without weight are never drawn) and the row's max stays above
    ``top - slack * T`` (T the temperature of the draw); so the roulette over their values
    alone (:func:`boltzmann_select_fast` on them) draws the whole row's action.
    """
    threshold = (UNDERFLOW - slack) * temp
    count = 0
    for a in range(q_row.shape[0]):
        count += q_row[a] - top > threshold
    if count > limit:
        return -1
    m = 0
    for a in range(q_row.shape[0]):
        if q_row[a] - top > threshold:
            members[m] = a
            m += 1
    return m


@njit_no_refcount(fastmath=True)
def _approximate_weights(
    q_row: np.ndarray, top: float, scale: float, weights: np.ndarray, bits: np.ndarray
) -> float:
    """``weights[a] ~ exp((Q(s, a) - top) * scale)`` to 1e-12 relative (clamped below at
    exp(-700)), in a loop the compiler vectorises; returns their sum."""
    n = q_row.shape[0]
    for a in range(n):
        x = max((q_row[a] - top) * scale, -700.0)
        k = np.rint(x * _LOG2E)
        r = (x - k * _LN2_HI) - k * _LN2_LO  # |r| <= ln(2) / 2
        # exp(r) by its Taylor series to r^10 / 10! (truncation below 3e-13 relative).
        p = 1.0 / 3628800.0
        for c in (362880.0, 40320.0, 5040.0, 720.0, 120.0, 24.0, 6.0, 2.0, 1.0, 1.0):
            p = p * r + 1.0 / c
        weights[a] = p
        bits[a] = (np.int64(k) + 1023) << 52  # the float 2^k
    powers = bits[:n].view(np.float64)
    total = 0.0
    for a in range(n):
        weights[a] *= powers[a]
        total += weights[a]
    return total


@njit_no_refcount()
def boltzmann_select_fast(
    q_row: np.ndarray,
    top: float,
    second: float,
    best: int,
    temp: float,
    u: float,
    weights: np.ndarray,
    bits: np.ndarray,
) -> int:
    """:func:`boltzmann_select_below`'s action for the same ``u``, bit for bit, in fewer steps.

    Where every action but ``best`` has a weight that underflows to 0 the roulette can only
    return ``best``. Else the weights are computed approximately (a vectorised exponential)
    and the pointer located among them; where it falls within :data:`_MARGIN` of the end of
    an action's share, the approximation might pick a neighbour, and the exact roulette
    decides.

    Args:
        q_row: Q(s, .), shape (A,).
        top, second, best: max Q(s, .), at least the max over the other actions (``top`` on
            ties), and an action with the max.
        temp, u: as :func:`boltzmann_select_below`.
        weights, bits: scratch space, shape (>= A,), float64 and int64.
    """
    scale = 1.0 / temp
    if (second - top) * scale <= UNDERFLOW:
        return best
    total = _approximate_weights(q_row, top, scale, weights, bits)
    pointer = u * total
    margin = _MARGIN * total
    acc = 0.0
    for a in range(q_row.shape[0]):
        end = acc + weights[a]
        if pointer < end:
            if pointer - acc >= margin and end - pointer > margin:
                return a
            break
        acc = end
    return boltzmann_select_below(q_row, top, temp, u, weights)


@njit(cache=True)
def greedy(q_row: np.ndarray) -> int:
    """The action with the largest Q(s, .); the first one on ties."""
    best = 0
    for a in range(1, q_row.shape[0]):
        if q_row[a] > q_row[best]:
            best = a
    return best
