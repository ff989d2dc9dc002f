"""Every benchmark method on a tiny MSM task: within its budget, and the same seed gives the
same curve."""

from __future__ import annotations

import dataclasses
import importlib.util

import numpy as np
import pytest

from qdsega.bench.methods import METHODS
from qdsega.bench.tasks import ALL_METHODS, FULL, MSM_METHODS, QUICK, BenchTask

TINY = BenchTask(
    name="legged12-msm",
    formation="legged12",
    sim="msm",
    budget_steps=3000,
    seeds=1,
    generations=2,
    trials=40,
    population=10,
    ppo_steps=2048,
    methods=MSM_METHODS,
    budgets=(1000,),
)
SEQUENCE_METHODS = ("ga-sequence", "random-search", "cma-cpg")
needs_sb3 = pytest.mark.skipif(
    importlib.util.find_spec("stable_baselines3") is None, reason="needs qdsega[bench]"
)


def _same(a, b) -> bool:
    return np.array_equal(a.steps, b.steps) and np.array_equal(a.distance_m, b.distance_m)


@pytest.mark.parametrize("method", SEQUENCE_METHODS)
def test_a_sequence_method_spends_its_budget_and_depends_on_its_seed_only(method, tmp_path):
    first = METHODS[method](TINY, 0, tmp_path / "a")
    again = METHODS[method](TINY, 0, tmp_path / "b")
    other = METHODS[method](TINY, 1, tmp_path / "c")
    assert _same(first, again) and not _same(first, other)
    spent = first.steps[-1]  # to the budget (CMA-ES: whole iterations of trials), no further
    assert spent == TINY.budget_steps or (method == "cma-cpg" and spent > TINY.budget_steps / 2)
    assert np.all(np.diff(first.distance_m[:-1]) > 0)  # a point at every improvement, and
    assert first.distance_m[-1] == first.distance_m[-2]  # one where the budget ended
    assert first.distance_m[-1] > 0


@pytest.mark.parametrize("method", ["qdsega", "qdsega-no-carry", "fixed-set"])
def test_a_qdsega_run_gives_one_point_per_generation_and_resumes_to_the_same_curve(
    method, tmp_path
):
    first = METHODS[method](TINY, 0, tmp_path)
    assert len(first.steps) == TINY.generations
    assert _same(first, METHODS[method](TINY, 0, tmp_path))  # finished: read back


def test_the_ablations_differ_from_qdsega(tmp_path):
    curves = {m: METHODS[m](TINY, 0, tmp_path / m) for m in ("qdsega", "fixed-set")}
    fixed = tmp_path / "fixed-set" / "run" / "config.yaml"
    assert "reproduce: false" in fixed.read_text()
    assert not _same(curves["qdsega"], curves["fixed-set"])


@pytest.mark.slow
@needs_sb3
def test_ppo_depends_on_its_seed_only(tmp_path):
    task = dataclasses.replace(TINY, ppo_steps=512)  # one rollout, then one update
    first = METHODS["ppo"](task, 0, tmp_path)
    assert _same(first, METHODS["ppo"](task, 0, tmp_path))
    assert first.steps[-1] == task.ppo_steps


@pytest.mark.parametrize("tasks", [FULL, QUICK])
def test_every_task_names_known_methods_and_increasing_budgets(tasks):
    for task in tasks:
        assert set(task.methods) <= set(METHODS)
        assert list(task.budgets) == sorted(task.budgets)
        assert task.config(seed=0).sim == ("msm" if task.sim == "msm" else "memo")


def test_every_method_has_its_place_in_the_report_order():
    assert sorted(ALL_METHODS) == sorted(METHODS)
