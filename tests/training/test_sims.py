"""The training simulator plays what it is given and counts how trials failed."""

from __future__ import annotations

import numpy as np

from qdsega.agent.policy import Policy, Rollout, SequencePolicy
from qdsega.task import Task, TaskConfig
from qdsega.training.sims import Failures, TrainingSim


class _FailingTrials:
    """Stands in for exact physics: every trial flips over on its first command."""

    def rollouts(self, policies: list[Policy], *, steps: int) -> list[Rollout]:
        return [
            _trial(1, f"body flipped (tilt {90 + k} deg)", policy.actions[policy.act(0, 0)])
            for k, policy in enumerate(policies)
        ]


def _sim() -> TrainingSim:
    task = Task(config=TaskConfig(trial_steps=6), light_xy=(10.0, 0.0))
    return TrainingSim(
        provider=None, exact=None, grounded=None, task=task, optimum=None, layout=None
    )  # type: ignore[arg-type]


def _trial(commands: int, failure: str | None, posture: np.ndarray | None = None) -> Rollout:
    postures = np.zeros((commands, 3), dtype=np.int64)
    if posture is not None:
        postures[:] = posture
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
    world = _sim()
    world.failures = Failures(9, 3, {"trunk touched the ground": 2})
    again = _sim()
    again.restore(world.state())
    assert again.failures == world.failures


def test_the_sim_plays_what_it_is_given_in_order_and_counts_the_failures():
    world = _sim()
    world.exact = _FailingTrials()  # type: ignore[assignment]
    gaits = [np.array([[1, 0, 0]]), np.array([[2, 0, 0]])]
    trials = world.play([SequencePolicy(commands=g) for g in gaits])
    assert [t.postures[0, 0] for t in trials] == [1, 2]
    assert (world.failures.trials, world.failures.kinds) == (2, {"body flipped": 2})
    assert world.play([]) == []
