"""Exact trials in batches: the same outcomes in this process and spread over workers, in the
order given, and every command counted; an open-loop policy walks as its replayed sequence."""

import numpy as np
import pytest

from qdsega.agent.policy import BoltzmannPolicy, GreedyPolicy, SequencePolicy
from qdsega.description import load_formation, resolve_formation
from qdsega.locomotion.exact_trials import ExactTrials
from qdsega.locomotion.rules import ExactRules
from qdsega.task import TaskConfig


@pytest.mark.slow
def test_trials_in_workers_equal_trials_here_in_order():
    formation = load_formation(resolve_formation("snake5"))
    actions = np.array([[0, 8, 0, 8], [8, 0, 8, 0], [4, 4, 4, 4]])
    greedy = GreedyPolicy(
        q=np.random.default_rng(0).random((3 * 4, 3)),
        actions=actions,
        postures=np.vstack([formation.rest_levels(), actions[:2]]),
        next_interior=np.array([1, 2, 0]),
    )
    sequences = [actions[[0, 1, 0, 1, 2]], actions[[1, 1, 2, 0, 0]]]
    results = []
    for workers in (1, 2):
        policies = [
            BoltzmannPolicy(greedy=greedy, temperature=0.5, rng=np.random.default_rng(k))
            for k in range(3)
        ] + [greedy, SequencePolicy(commands=sequences[0])]  # new generators, policies each time
        with ExactTrials(
            formation=formation,
            rules=ExactRules(task=TaskConfig(trial_steps=5)),
            workers=workers,
        ) as trials:
            rollouts = trials.rollouts(policies, steps=5)
            replays = trials.replays(sequences)
            cycles = trials.cycles(sequences[:1], steps=5)
            assert trials.commands == sum(len(r.postures) for r in rollouts) + sum(
                r.completed + (r.failure is not None) for r in replays
            ) + len(cycles[0].rollout.postures)
        results.append((rollouts, replays, cycles))
    (here, here_replays, here_cycles), (there, there_replays, there_cycles) = results
    assert np.array_equal(here_cycles[0].contacts, there_cycles[0].contacts)
    assert here_cycles[0].contacts.shape[1] == len(formation.units)
    assert here_cycles[0].contacts.any()  # a snake lies on the ground
    assert np.array_equal(here_cycles[0].rollout.poses, here[-1].poses)  # the same gait
    for a, b in zip(here, there, strict=True):
        assert np.array_equal(a.postures, b.postures) and np.array_equal(a.poses, b.poses)
    assert here_replays == there_replays
    assert here[-1].distance_m == here_replays[0].distance_m  # the same sequence, two ways
    assert np.array_equal(here[-1].postures, sequences[0])
    assert len({r.distance_m for r in here}) > 1  # the exploring trials differ
