"""Eqs. (2)-(6) on small Q-tables computed by hand, and their division guards."""

from __future__ import annotations

import numpy as np
import pytest

from qdsega.agent.fitness import end_weights, fitness, fitness_q, fitness_use, regulate

# 3 states x 2 actions. State 0: mixed; state 1: all negative; state 2: never visited.
Q = np.array([[4.0, -2.0], [-1.0, -4.0], [0.0, 0.0]])


def test_eqs_2_and_3_by_hand():
    p = 0.2
    r = regulate(Q, p)
    # state 0: Vmax 4, Vmin -2. 4 -> (0.8/4)*4 + 0.2 = 1; -2 -> -(0.2/-2)*-2 + 0.2 = 0.
    # state 1: Vmin -4. -1 -> -(0.2/-4)*-1 + 0.2 = 0.15; -4 -> 0.
    # state 2: all zero (Vmax 0): 0 maps to p.
    assert r == pytest.approx(np.array([[1.0, 0.0], [0.15, 0.0], [0.2, 0.2]]))


def test_eq4_weighted_prefix_means_by_hand():
    r = np.array([[1.0, 0.0], [0.15, 0.0], [0.2, 0.2]])
    w = np.array([0.5, 0.3, 0.2])
    # action 0 sorted: 1, 0.2, 0.15 -> means 1, 0.6, 0.45 -> 0.5 + 0.18 + 0.09 = 0.77
    # action 1 sorted: 0.2, 0, 0 -> means 0.2, 0.1, 0.0667 -> 0.1 + 0.03 + 0.01333 = 0.14333
    assert fitness_q(r, w) == pytest.approx([0.77, 0.1 + 0.03 + 0.2 * 0.2 / 3])


def test_eq5_and_eq6():
    uses = np.array([30, 10])
    assert fitness_use(uses) == pytest.approx([0.75, 0.25])
    assert fitness_use(np.array([0, 0])).tolist() == [0.0, 0.0]  # no use: no share
    fit = fitness(Q, uses, p=0.2, w_first=0.5, w_last=0.2, k_f=2.0)
    fq = fitness_q(regulate(Q, 0.2), end_weights(3, 0.5, 0.2))
    assert fit == pytest.approx(fq + 2.0 * np.array([0.75, 0.25]))


def test_end_weights():
    assert end_weights(3, 1.0, 2.0).tolist() == [1.0, 0.0, 2.0]
    assert end_weights(1, 1.0, 2.0).tolist() == [3.0]


def test_guards_all_zero_all_negative_unvisited():
    r = regulate(np.zeros((2, 3)), 0.3)
    assert np.all(r == 0.3) and np.all(np.isfinite(r))
    neg = regulate(np.array([[-1.0, -3.0]]), 0.3)
    assert neg[0] == pytest.approx([0.2, 0.0])
    assert np.all(regulate(np.random.default_rng(0).normal(size=(5, 4)), 0.4) >= 0)
