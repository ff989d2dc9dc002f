"""Eq. (1), the Boltzmann roulette of eq. (18), and the compiled loop on a tiny table."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qdsega.agent.boltzmann import (
    UNDERFLOW,
    boltzmann_select,
    boltzmann_select_below,
    boltzmann_select_fast,
    greedy,
    live_actions,
    temperature,
)
from qdsega.agent.model import Transitions
from qdsega.agent.qlearning import _choose, _update_stats, learn_on_table, q_update
from qdsega.task import Task, TaskConfig, exterior_state

EDGES = np.radians([-45.0, -15.0, 15.0, 45.0])
NO_MAP = Task(config=TaskConfig(), light_xy=(1.0, 0.0)).map_arrays()
"""A world with nothing standing in it."""


def test_eq1_update():
    # (1 - 0.5) * 2 + 0.5 * (3 + 0.9 * 10) = 1 + 6 = 7
    assert q_update(2.0, 3.0, 10.0, 0.5, 0.9) == pytest.approx(7.0)


def test_eq18_temperature():
    assert temperature(0, 150.0, 0.002, 1.0) == pytest.approx(150.0 * math.e)
    assert temperature(500, 150.0, 0.002, 1.0) == pytest.approx(150.0)


def _frequencies(q: np.ndarray, temp: float, n: int = 20000) -> np.ndarray:
    rng = np.random.default_rng(0)
    w = np.empty(len(q))
    picks = [boltzmann_select(q, temp, rng.random(), w) for _ in range(n)]
    return np.bincount(picks, minlength=len(q)) / n


def test_boltzmann_matches_the_distribution_and_becomes_greedy():
    q = np.array([1.0, 2.0, 0.0, 1.5])
    for temp in (5.0, 1.0):
        expected = np.exp(q / temp) / np.exp(q / temp).sum()
        assert _frequencies(q, temp) == pytest.approx(expected, abs=0.015)
    assert _frequencies(q, 1e-3)[1] == 1.0
    assert greedy(q) == 1
    assert greedy(np.array([3.0, 3.0])) == 0  # ties: first


def _fast_and_exact(row: np.ndarray, temp: float, u: float) -> tuple[int, int]:
    top = row.max()
    best = int(row.argmax())
    second = np.delete(row, best).max(initial=-np.inf)
    w, bits = np.empty(len(row)), np.empty(len(row), dtype=np.int64)
    fast = boltzmann_select_fast(row, top, second, best, temp, u, w, bits)
    return fast, boltzmann_select_below(row, top, temp, u, w)


def test_fast_roulette_picks_the_exact_roulettes_action():
    """Same row, temperature and pointer: the same action, from near-uniform (T = 1e4) to
    greedy (T = 1e-9), with untried actions (Q = 0), ties, a single action, and pointers on
    the edge of a share (two equal weights, u = 0.5), at 0 and just below 1."""
    gen = np.random.default_rng(0)
    cases = 0
    for temp in (1e4, 30.0, 1.0, 0.05, 1e-3, 1e-9):
        for n in (1, 2, 7, 80):
            for _ in range(60):
                row = gen.normal(0.0, 20.0, n)
                row[gen.random(n) < 0.3] = 0.0
                if n > 2 and gen.random() < 0.3:
                    row[1] = row.max()  # a tie at the top
                for u in (gen.random(), 0.0, 0.5, 1.0 - 2.0**-53):
                    fast, exact = _fast_and_exact(row, temp, u)
                    assert fast == exact, (temp, row.tolist(), u)
                    cases += 1
    assert cases == 6 * 4 * 60 * 4
    assert _fast_and_exact(np.array([2.0, 2.0]), 1.0, 0.5) == (1, 1)


def test_compiled_loop_learns_a_two_action_chain():
    # One interior state besides the start; action 0 moves 1 m forward, action 1 falls.
    dx = np.array([[1.0, 0.0], [1.0, 0.0]])
    zeros = np.zeros_like(dx)
    failed = np.array([[False, True], [False, True]])
    q = np.zeros((2 * 4, 2))
    uses = np.zeros(2, dtype=np.int64)
    distances, fell = np.zeros(300), np.zeros(300, dtype=np.bool_)
    steps = learn_on_table(
        q, *Transitions(dx=dx, dy=zeros, dtheta=zeros, failed=failed).compiled(),
        np.array([1, 0]), np.array([100.0, 0.0]),
        EDGES, *NO_MAP, 300, 3, 0.5, 0.9,
        np.array([150.0, 0.002, 1.0]), 100.0, -100.0, np.random.default_rng(1),
        uses, distances, fell,
    )  # fmt: skip
    assert steps == uses.sum()
    assert q[0 * 4 + 2, 1] < 0 < q[0 * 4 + 2, 0]  # start state, straight ahead
    assert distances.max() == pytest.approx(3.0)
    assert np.all(distances[fell] < 3.0)


def test_live_actions_are_those_with_weight_and_their_roulette_is_the_rows():
    """The actions within (UNDERFLOW - slack) * T of the max, or -1 beyond the limit; where
    the row's max later falls by less than slack / 2 * T at a lower T, the roulette over their
    values alone draws the whole row's action."""
    gen = np.random.default_rng(2)
    for _ in range(300):
        row = gen.normal(0.0, 1.0, 30) * 10.0 ** gen.uniform(-6, 1)
        top, temp = row.max(), 10.0 ** gen.uniform(-7, -2)
        members = np.full(30, -1)
        m = live_actions(row, top, temp, 50.0, 30, members)
        expected = np.flatnonzero(row - top > (UNDERFLOW - 50.0) * temp)
        assert members[:m].tolist() == expected.tolist()
        assert live_actions(row, top, temp, 50.0, m - 1, members) == (-1 if m > 0 else 0)
        later = row.copy()
        later[row.argmax()] -= 25.0 * temp * gen.random()  # the max falls, a little
        later_temp = temp * gen.uniform(0.1, 1.0)
        w = np.empty(30)
        for u in (gen.random(), 0.0, 1.0 - 2.0**-53):
            live = later[members[:m]]
            j = boltzmann_select_below(live, live.max(), later_temp, u, w)
            assert members[j] == boltzmann_select_below(later, later.max(), later_temp, u, w)


def _reference_loop(q, dx, dtheta, failed, next_interior, light, edges, trials, steps, rate, rng):
    """Plain Python: eq. (1) on every step, the row maximum recomputed every time."""
    weights = np.empty(q.shape[1])
    for trial in range(trials):
        temp = temperature(trial, 150.0, rate, 1.0)
        x = y = theta = 0.0
        d = math.hypot(*light)
        interior, exterior = 0, exterior_state(0.0, 0.0, 0.0, *light, edges)
        for _ in range(steps):
            s = interior * len(edges) + exterior
            a = boltzmann_select(q[s], temp, rng.random(), weights)
            if failed[interior, a]:
                q[s, a] = 0.5 * q[s, a] + 0.5 * -100.0
                break
            x += dx[interior, a] * math.cos(theta)
            y += dx[interior, a] * math.sin(theta)
            theta += dtheta[interior, a]
            d_new = math.hypot(light[0] - x, light[1] - y)
            interior = next_interior[a]
            exterior = exterior_state(x, y, theta, *light, edges)
            best = q[interior * len(edges) + exterior].max()
            q[s, a] = q_update(q[s, a], 100.0 * (d - d_new), best, 0.5, 0.9)
            d = d_new


@pytest.mark.parametrize("rate", [0.002, 0.05])
@pytest.mark.parametrize("n_actions", [5, 40])
def test_compiled_loop_equals_a_plain_reference(rate: float, n_actions: int):
    """The compiled loop keeps each row's maximum up to date instead of rescanning the row,
    and takes the fast roulette, over the row's live actions where they are few: the same
    Q-table, draw for draw, as recomputing it every step (turns and falls too), at eq. (18)'s
    rate and at one that cools to greedy (T ~ 1e-6), with 40 actions of which 30 move as
    one of the first 10 does (near-ties, as in a GA's population)."""
    gen = np.random.default_rng(5)
    n_interior = 6
    dx = gen.uniform(-0.05, 0.1, (n_interior, n_actions))
    dtheta = gen.uniform(-0.3, 0.3, (n_interior, n_actions))
    failed = gen.random((n_interior, n_actions)) < 0.15
    if n_actions > 10:
        for array in (dx, dtheta, failed):
            array[:, 10:] = array[:, np.arange(10, n_actions) % 10]
    next_interior = gen.integers(0, n_interior, n_actions)
    light, edges = np.array([3.0, 1.0]), EDGES
    start = gen.normal(0.0, 5.0, (n_interior * 4, n_actions))  # a carried-over table
    q_ref = start.copy()
    _reference_loop(q_ref, dx, dtheta, failed, next_interior, light, edges, 400, 8, rate,
                    np.random.default_rng(3))  # fmt: skip
    q = start.copy()
    uses = np.zeros(n_actions, dtype=np.int64)
    distances, fell = np.zeros(400), np.zeros(400, dtype=np.bool_)
    learn_on_table(
        q, *Transitions(dx=dx, dy=np.zeros_like(dx), dtheta=dtheta, failed=failed).compiled(),
        next_interior, light, edges, *NO_MAP, 400, 8, 0.5, 0.9, np.array([150.0, rate, 1.0]), 100.0,
        -100.0, np.random.default_rng(3), uses, distances, fell,
    )  # fmt: skip
    assert fell.any() and not fell.all()
    # Compiled and interpreted arithmetic may differ in the last bit; a different draw would
    # change whole entries by tens.
    assert q == pytest.approx(q_ref, rel=1e-12, abs=1e-9)


def test_a_rows_live_actions_are_recounted_when_its_max_falls():
    """Row: 0, -0.1, -0.8, -0.8 at T = 1e-3: actions 0 and 1 are live (the others are 800 T
    below). Then action 1 falls to -0.79 and action 0 to -2: actions 2 and 3 are now 10 T
    below the max and share the end of the roulette; the cached live actions would miss them."""
    q = np.array([[0.0, -0.1, -0.8, -0.8]])
    stats = np.zeros((1, 6))
    stats[:, 3] = -2.0
    arg = np.zeros(1, dtype=np.int64)
    members = np.empty(q.shape, dtype=np.int64)
    scratch, w, bits = np.empty(4), np.empty(4), np.empty(4, dtype=np.int64)
    temp = 1e-3

    def draw(u: float) -> int:
        return _choose(q, 0, stats, arg, members, temp, u, scratch, w, bits)

    assert draw(0.5) == 0 and stats[0, 3] == 2.0  # two live actions, counted
    for a, new in ((1, -0.79), (0, -2.0)):
        q[0, a] = new
        _update_stats(0, a, new, stats, arg)
    for u in (0.5, 1.0 - 1e-5, 1.0 - 2.0**-53):
        assert draw(u) == boltzmann_select_below(q[0], q[0].max(), temp, u, w)
    assert draw(1.0 - 1e-5) == 3
