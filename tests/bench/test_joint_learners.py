"""PPO and SAC under continuous control: within the budget in posture steps' worth of physics
time, a point per scoring interval and one where the budget ends, the same seed giving the same
curve; an MSM task refuses them."""

from __future__ import annotations

import dataclasses
import importlib.util

import numpy as np
import pytest

from qdsega.bench.joint_learners import joint_curve, posture_steps
from qdsega.bench.tasks import PYBULLET_ONLY, QUICK
from qdsega.locomotion import CONTROLS_PER_POSTURE

SNAKE = next(task for task in QUICK if task.sim == "pybullet")
MSM = next(task for task in QUICK if task.sim == "msm")


@pytest.mark.slow
@pytest.mark.skipif(
    importlib.util.find_spec("stable_baselines3") is None, reason="needs qdsega[bench]"
)
@pytest.mark.parametrize(
    ("learner", "budget", "every"),
    # PPO: 240 env steps, one update (rollouts of 192); SAC: 120, 20 updates (from its 100th)
    [("ppo", 20, 16), ("sac", 10, 8)],
)
def test_a_joint_learner_spends_its_budget_and_depends_on_its_seed_only(learner, budget, every):
    task = dataclasses.replace(SNAKE, budget_steps=budget, ppo_steps=budget)
    first = joint_curve(task, 0, learner=learner, score_every=every)
    again = joint_curve(task, 0, learner=learner, score_every=every)
    assert first.steps.tolist() == [every, budget]  # the interval's point, the budget's end
    assert np.all(np.isfinite(first.distance_m))
    assert np.array_equal(first.steps, again.steps)
    assert np.array_equal(first.distance_m, again.distance_m)


def test_the_budget_counts_a_posture_step_per_controls_per_posture_env_steps():
    assert posture_steps(CONTROLS_PER_POSTURE * 30) == 30
    assert posture_steps(CONTROLS_PER_POSTURE * 30 - 1) == 29  # a posture step begun: not yet


def test_an_msm_task_refuses_the_joint_methods():
    for method in PYBULLET_ONLY:
        with pytest.raises(ValueError, match=f"legged12-msm cannot run {method}: .* no joints"):
            dataclasses.replace(MSM, methods=("qdsega", method))
