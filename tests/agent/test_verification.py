"""The exact trials a learner on a table asks for: a (1 + lambda) local search over open-loop
gaits that keeps the best trial told as its parent and draws the same on a resumed run, and
the exploring trials that come before the greedy one."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from qdsega.agent.policy import BoltzmannPolicy, Policy, Rollout, SequencePolicy
from qdsega.agent.verification import Verification

LEVELS = np.array([9, 9, 9])
STEPS = 6


def _play(policies: list[Policy]) -> list[Rollout]:
    """Stands in for exact physics: a trial covers 0.1 m per level of joint 0, on average over
    its commands."""
    out = []
    for policy in policies:
        commands = np.array([policy.actions[policy.act(0, 0)] for _ in range(STEPS)])
        distance = 0.1 * float(commands[:, 0].mean())
        poses = np.zeros((STEPS + 1, 3))
        out.append(Rollout(np.zeros(STEPS, dtype=np.int64), commands, poses, False, distance))
    return out


def _generation(index: int) -> SimpleNamespace:
    start_gait = np.array([[2, 0, 8], [3, 8, 0]])
    return SimpleNamespace(index=index, policy=SequencePolicy(commands=start_gait))


def _climb(plan: Verification, generations: range) -> list[list[Rollout]]:
    """Each generation as the training loop plays it: ask, tell the greedy replay, then the
    neighbours of the best so far."""
    out = []
    for g in generations:
        (greedy,) = _play(plan.ask(None, _generation(g), None))  # type: ignore[arg-type]
        plan.tell([greedy])
        searched = _play(plan.neighbours(g, LEVELS))
        plan.tell(searched)
        out.append([greedy, *searched])
    return out


def test_the_local_search_climbs_from_the_best_trial_and_resumes_to_the_same_draws():
    plan = Verification(local_search=4, seed=7)
    replays = _climb(plan, range(1, 13))
    assert all(len(trials) == 5 for trials in replays)  # the greedy replay first, 4 neighbours
    best = [max(t.distance_m for t in trials) for trials in replays]
    assert best[0] >= 0.25 and max(best) >= 0.6  # 0.25 m is the start gait
    state = plan.state()
    assert state["search_distance_m"][0] == max(best)  # the parent is the best so far

    resumed = Verification(local_search=4, seed=7)
    resumed.restore(state)
    ahead, again = _climb(plan, range(13, 16)), _climb(resumed, range(13, 16))
    for a, b in zip(ahead, again, strict=True):
        assert [t.distance_m for t in a] == [t.distance_m for t in b]
        assert all(np.array_equal(x.postures, y.postures) for x, y in zip(a, b, strict=True))


def test_no_local_search_asks_for_the_greedy_policy_only():
    plan = Verification(local_search=0)
    (trials,) = _climb(plan, range(1, 2))
    assert len(trials) == 1
    assert plan.neighbours(2, LEVELS) == []


def test_a_path_told_first_becomes_the_search_parent():
    plan = Verification(local_search=2, seed=7)
    path = np.array([[8, 0, 0], [7, 1, 1]])  # 0.75 m, beyond the greedy gait's 0.25 m
    (verified,) = _play([SequencePolicy(commands=path)])
    plan.tell([verified])
    trials = _climb(plan, range(1, 2))[0]
    assert trials[0].distance_m == 0.25  # the greedy replay, then neighbours of the path
    assert all((t.postures[:2] != path).sum() <= 1 for t in trials[1:])
    assert plan.state()["search_distance_m"][0] >= 0.75


def test_with_a_grounded_table_exploring_trials_come_first_and_the_greedy_one_last():
    plan = Verification(explore_trials=3, temperature=0.5, seed=7)
    generation = _generation(4)
    asked = plan.ask(None, generation, grounded=object())  # type: ignore[arg-type]
    assert len(asked) == 4 and asked[-1] is generation.policy
    assert all(isinstance(p, BoltzmannPolicy) and p.temperature == 0.5 for p in asked[:3])
