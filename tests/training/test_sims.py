"""The training simulator's local search: a (1 + lambda) strategy over open-loop gaits that
keeps the best exact trial as its parent, draws the same on a resumed run, and returns its
trials for the learner to be told."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from qdsega.agent.policy import Policy, Rollout, SequencePolicy
from qdsega.task import Task, TaskConfig
from qdsega.training.sims import Failures, TrainingSim

LEVELS = np.array([9, 9, 9])


class _ScoredTrials:
    """Stands in for exact physics: a trial covers 0.1 m per level of joint 0, on average over
    its commands."""

    def __init__(self) -> None:
        self.trials = 0

    def rollouts(self, policies: list[Policy], *, steps: int) -> list[Rollout]:
        out = []
        for policy in policies:
            commands = np.array([policy.actions[policy.act(0, 0)] for _ in range(steps)])
            distance = 0.1 * float(commands[:, 0].mean())
            poses = np.zeros((steps + 1, 3))
            out.append(Rollout(np.zeros(steps, dtype=np.int64), commands, poses, False, distance))
        self.trials += len(policies)
        return out


def _world(local_search: int) -> TrainingSim:
    task = Task(config=TaskConfig(trial_steps=6), light_xy=(10.0, 0.0))
    world = TrainingSim(
        provider=None, exact=None, grounded=None, task=task, optimum=None, layout=None
    )  # type: ignore[arg-type]
    world.exact = _ScoredTrials()  # type: ignore[assignment]
    world.local_search, world.seed = local_search, 7
    return world


def _generation(index: int) -> SimpleNamespace:
    start_gait = np.array([[2, 0, 8], [3, 8, 0]])
    return SimpleNamespace(index=index, policy=SequencePolicy(commands=start_gait))


def _climb(world: TrainingSim, generations: range) -> list[list[Rollout]]:
    return [world.replay(_generation(g), LEVELS) for g in generations]  # type: ignore[arg-type]


def test_the_local_search_climbs_from_the_best_trial_and_resumes_to_the_same_draws():
    world = _world(local_search=4)
    replays = _climb(world, range(1, 13))
    assert all(len(trials) == 5 for trials in replays)  # the greedy replay first, 4 neighbours
    assert world.exact.trials == 12 * 5
    best = [max(t.distance_m for t in trials) for trials in replays]
    assert best[0] >= 0.25 and max(best) >= 0.6  # 0.25 m is the start gait
    state = world.state()
    assert state["search_distance_m"][0] == max(best)  # the parent is the best so far

    resumed = _world(local_search=4)
    resumed.restore(state)
    ahead, again = _climb(world, range(13, 16)), _climb(resumed, range(13, 16))
    for a, b in zip(ahead, again, strict=True):
        assert [t.distance_m for t in a] == [t.distance_m for t in b]
        assert all(np.array_equal(x.postures, y.postures) for x, y in zip(a, b, strict=True))


def test_no_local_search_replays_the_greedy_policy_only():
    world = _world(local_search=0)
    (trials,) = _climb(world, range(1, 2))
    assert len(trials) == 1 and world.exact.trials == 1
    assert "search_commands" not in world.state()


def test_a_handed_on_path_is_verified_and_becomes_the_search_parent():
    world = _world(local_search=2)
    path = np.array([[8, 0, 0], [7, 1, 1]])  # 0.75 m, beyond the greedy gait's 0.25 m
    verified = world.verify(path)
    assert world.exact.trials == 1 and verified is not None and verified.distance_m == 0.75
    assert np.array_equal(verified.postures[:2], path)
    trials = world.replay(_generation(1), LEVELS)  # type: ignore[arg-type]
    assert trials[0].distance_m == 0.25  # the greedy replay, then neighbours of the path
    assert all((t.postures[:2] != path).sum() <= 1 for t in trials[1:])
    assert world.state()["search_distance_m"][0] >= 0.75


def test_without_exact_physics_nothing_is_verified():
    world = _world(local_search=2)
    world.exact = None
    assert world.verify(np.array([[8, 0, 0]])) is None


def _trial(commands: int, failure: str | None) -> Rollout:
    postures = np.zeros((commands, 3), dtype=np.int64)
    return Rollout(
        np.zeros(4, dtype=np.int64), postures, np.zeros((5, 3)), failure is not None, 0.0, failure
    )


def test_failures_are_counted_by_kind_without_their_numbers():
    failures = Failures().add(
        [
            _trial(1, "joint BL_swing_joint missed its level by 38.9 deg"),
            _trial(1, "joint BL_swing_joint missed its level by 41.2 deg"),
            _trial(4, None),
            _trial(2, "body flipped (tilt 95 deg)"),
        ]
    )
    assert failures.kinds == {"joint BL_swing_joint missed its level": 2, "body flipped": 1}
    assert failures.most_common == "joint BL_swing_joint missed its level"
    assert (failures.commands, failures.trials) == (8, 4)
    assert failures.share == 3 / 8
    later = failures.add([_trial(1, "body flipped (tilt 120 deg)")])
    assert later.since(failures) == Failures(1, 1, {"body flipped": 1})


def test_the_failures_survive_a_checkpoint():
    world = _world(local_search=0)
    world.failures = Failures(9, 3, {"trunk touched the ground": 2})
    again = _world(local_search=0)
    again.restore(world.state())
    assert again.failures == world.failures
