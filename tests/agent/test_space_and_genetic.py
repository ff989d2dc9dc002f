"""Fig. 8's table construction and the GA operators' rates."""

from __future__ import annotations

import numpy as np
import pytest

from qdsega.agent.config import GeneticConfig
from qdsega.agent.genetic import (
    mutate,
    one_point_crossover,
    random_population,
    reproduce,
    roulette,
    roulette_weights,
    uniform_crossover,
    vary_gait,
)
from qdsega.agent.space import ExplorationSpace


def test_same_phenotype_is_one_action_and_initial_posture_is_state_0():
    population = np.array([[1, 0], [0, 1], [1, 0], [0, 0], [0, 1]])
    space = ExplorationSpace.from_population(population, np.array([0, 0]))
    assert space.actions.tolist() == [[0, 0], [0, 1], [1, 0]]
    assert space.action_of.tolist() == [2, 1, 2, 0, 1]
    assert space.postures.tolist() == [[0, 0], [0, 1], [1, 0]]  # [0,0] not repeated
    assert space.next_interior.tolist() == [0, 1, 2]
    other = ExplorationSpace.from_population(population[:2], np.array([1, 1]))
    assert other.postures.tolist() == [[1, 1], [0, 1], [1, 0]]
    assert other.next_interior.tolist() == [1, 2]


def test_roulette_rates():
    rng = np.random.default_rng(0)
    picks = roulette(np.array([1.0, 3.0, 0.0, 6.0]), 100000, rng)
    assert np.bincount(picks, minlength=4) / 1e5 == pytest.approx([0.1, 0.3, 0.0, 0.6], abs=0.01)
    uniform = np.bincount(roulette(np.zeros(4), 40000, rng), minlength=4) / 4e4
    assert uniform == pytest.approx([0.25] * 4, abs=0.01)


def test_crossover_and_mutation_rates():
    rng = np.random.default_rng(1)
    a, b = np.zeros(1000, dtype=np.int64), np.ones(1000, dtype=np.int64)
    child, other = uniform_crossover(a, b, rng)
    assert child.mean() == pytest.approx(0.5, abs=0.05)
    assert np.all(child + other == 1)
    cuts = []
    for _ in range(2000):
        c, _ = one_point_crossover(a[:5], b[:5], rng)
        assert np.all(np.diff(c) >= 0)  # a head of a's, a tail of b's
        cuts.append(int(np.argmax(c)))
    assert np.bincount(cuts, minlength=5)[1:] / 2000 == pytest.approx([0.25] * 4, abs=0.03)
    levels = np.array([2, 9])
    pop = np.zeros((50000, 2), dtype=np.int64)
    mutated = mutate(pop, levels, 0.02, rng)
    assert (mutated != pop).mean(axis=0) == pytest.approx([0.02, 0.02], abs=0.003)
    assert set(np.unique(mutated[:, 1])) <= set(range(9))


def test_pair_crossover_rate():
    rng = np.random.default_rng(2)
    levels = np.full(30, 2)
    pop = np.vstack([np.zeros((1, 30), dtype=np.int64), np.ones((1, 30), dtype=np.int64)] * 5000)
    config = GeneticConfig(population=10000, crossover_rate=0.2, mutation_rate=0.0)
    children = reproduce(pop, np.ones(10000), levels, config, rng)
    mixed = np.mean([0 < row.sum() < 30 for row in children])
    # A pair is crossed with prob 0.2 and has different parents with prob 0.5.
    assert mixed == pytest.approx(0.1, abs=0.015)


def test_random_population_covers_levels():
    pop = random_population(np.array([2, 9]), 5000, np.random.default_rng(0))
    assert pop[:, 0].max() == 1 and pop[:, 1].max() == 8 and pop.min() == 0


def test_roulette_over_actions_or_individuals():
    # Action 0 has 3 copies, action 1 one; fitness 1 and 2.
    action_of = np.array([0, 0, 1, 0])
    fit = np.array([1.0, 2.0])
    per_action = roulette_weights(fit, action_of, "actions")
    assert per_action.tolist() == pytest.approx([1 / 3, 1 / 3, 2.0, 1 / 3])
    assert roulette_weights(fit, action_of, "individuals").tolist() == [1.0, 1.0, 2.0, 1.0]
    # Over actions, action 1 is drawn 2/3 of the time however many copies action 0 has.
    picks = action_of[roulette(per_action, 30000, np.random.default_rng(0))]
    assert np.mean(picks == 1) == pytest.approx(2 / 3, abs=0.01)
    with pytest.raises(ValueError, match="selection"):
        roulette_weights(fit, action_of, "genes")


_GAIT_LEVELS = np.array([9, 2, 1, 9])
_CYCLE = np.array([[0, 0, 0, 8], [4, 1, 0, 4], [8, 0, 0, 0]])
"""Three postures of four joints, the third joint with a single level."""


def test_a_varied_gait_changes_one_character_of_one_posture_wherever_it_occurs():
    levels = _GAIT_LEVELS
    gait = _CYCLE[[0, 1, 2, 1, 0, 1, 2, 1]]
    rng = np.random.default_rng(0)
    changed_joints = set()
    for _ in range(200):
        varied = vary_gait(gait, levels, rng)
        diff = varied != gait
        rows, joints = np.nonzero(diff)
        assert len(set(joints)) == 1 and joints[0] != 2  # one joint, never the one-level one
        assert len({gait[r].tobytes() for r in rows}) == 1  # one posture ...
        assert np.all(np.all(gait == gait[rows[0]], axis=1) == diff.any(axis=1))  # ... everywhere
        step = abs(int(varied[rows[0], joints[0]]) - int(gait[rows[0], joints[0]]))
        assert 1 <= step <= 2 and np.all((varied >= 0) & (varied < levels))
        changed_joints.add(int(joints[0]))
    assert changed_joints == {0, 1, 3}
    with pytest.raises(ValueError, match="no joint has more than one level"):
        vary_gait(gait[:, 2:3], levels[2:3], rng)


def test_a_phase_move_shifts_one_joints_commands_one_step_in_time():
    levels = _GAIT_LEVELS
    gait = _CYCLE[[0, 1, 2, 0, 1, 2, 0, 1]]
    rng = np.random.default_rng(1)
    shifts = set()
    for _ in range(100):
        varied = vary_gait(gait, levels, rng, phase_share=1.0)
        joints = np.flatnonzero((varied != gait).any(axis=0))
        assert len(joints) == 1 and joints[0] != 2
        j = int(joints[0])
        others = np.delete(np.arange(4), j)
        assert np.array_equal(varied[:, others], gait[:, others])
        if np.array_equal(varied[:-1, j], gait[1:, j]) and varied[-1, j] == gait[-1, j]:
            shifts.add("earlier")
        else:
            assert np.array_equal(varied[1:, j], gait[:-1, j]) and varied[0, j] == gait[0, j]
            shifts.add("later")
    assert shifts == {"earlier", "later"}
