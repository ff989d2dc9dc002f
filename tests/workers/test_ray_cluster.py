"""Ray actors as workers (``--ray local``): the same results as local processes, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from qdsega.description import load_formation
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.locomotion.memo import MeasuredTransitions
from qdsega.training.run_folder import RunFolder

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out


def test_a_memo_table_measured_by_ray_actors_equals_the_local_one(local_ray):
    snake5 = load_formation("assemblies/snake5.yaml")
    postures = np.random.default_rng(1).integers(0, 9, size=(3, 4))
    local = MeasuredTransitions(formation=snake5, lower_agent=LowerAgentConfig(), workers=2)
    remote = MeasuredTransitions(
        formation=snake5, lower_agent=LowerAgentConfig(), workers=2, ray="local"
    )
    try:
        expected = local.transitions(postures, postures[::-1])
        measured = remote.transitions(postures, postures[::-1])
    finally:
        local.close()
        remote.close()
    assert remote.measured == 9
    for field in ("dx", "dy", "dtheta", "failed"):
        assert np.array_equal(getattr(measured, field), getattr(expected, field)), field


TINY = "agent: {learning: {trials: 20}, genetic: {population: 4, generations: 2}}\n"
TINY += "task: {trial_steps: 4}\nlocal_search: 1\n"


def test_a_run_with_ray_local_learns_what_a_run_without_ray_learns(local_ray, tmp_path):
    """Two Ray actors against one process (what worker processes measure is the same, bit for
    bit: tests/locomotion/test_memo.py)."""
    from helpers import run_cli

    (tmp_path / "tiny.yaml").write_text(TINY)
    runs = {}
    ways = {"local": ["--workers", "1"], "ray": ["--workers", "2", "--ray", "local"]}
    for name, extra in ways.items():
        runs[name] = tmp_path / name
        result = run_cli(
            "train", "snake5", "--sim", "memo", "--preset", "paper-snake",
            "--config", tmp_path / "tiny.yaml", "--out", runs[name], "--quiet", *extra,
        )  # fmt: skip
        assert result.returncode == 0, result.stderr
    memo = RunFolder.TRANSITIONS
    with np.load(runs["local"] / memo) as local, np.load(runs["ray"] / memo) as ray_:
        assert np.array_equal(local["pairs"], ray_["pairs"])
        assert np.array_equal(local["values"], ray_["values"])

    def without_wall_time(run):  # the last column, wall_s, is the only one that may differ
        return [line.rsplit(",", 1)[0] for line in (run / "metrics.csv").read_text().splitlines()]

    assert without_wall_time(runs["ray"]) == without_wall_time(runs["local"])


def test_more_ray_workers_than_cpus_are_refused_before_anything_is_written(local_ray, tmp_path):
    from helpers import run_cli

    result = run_cli(  # on the Ray instance already up in this process
        "train", "snake5", "--sim", "memo", "--ray", "local", "--workers", "64",
        "--out", tmp_path / "run",
    )  # fmt: skip
    assert result.returncode == 2, result.stderr
    assert "64 Ray workers need 64 CPUs" in result.stderr
    assert not (tmp_path / "run").exists()
