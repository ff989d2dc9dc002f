"""``qdsega bench --quick``: every method through the whole pipeline into --out, and a
re-run that skips what finished."""

from __future__ import annotations

import argparse
import importlib.util
import json
import shutil

import pytest
from helpers import load_result, made_once, run_cli, save_result

from qdsega.bench.tasks import QUICK
from qdsega.commands import bench
from qdsega.errors import ConfigError

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        importlib.util.find_spec("stable_baselines3") is None, reason="needs qdsega[bench]"
    ),
]
RUNS = sum(len(task.methods) * task.seeds for task in QUICK)


@pytest.fixture(scope="session")
def quick(tmp_path_factory):
    """``bench --quick`` into ``out``, made once for both tests, and what it returned (one
    job at a time: a second would import torch again; tests/test_driver.py runs jobs side by
    side)."""

    def make(folder):
        result = run_cli("bench", "--quick", "--out", folder / "out", "--jobs", "1")
        save_result(result, folder / "result.json")

    folder = made_once(tmp_path_factory, "bench-quick", make)
    return folder / "out", load_result(folder / "result.json")


def test_every_method_runs_on_every_task_and_the_report_shows_it(quick):
    out, result = quick
    assert result.returncode == 0, result.stderr
    report = (out / "BENCHMARKS.md").read_text()
    sections = {part.split("\n", 1)[0]: part for part in report.split("\n## ")}
    for task in QUICK:
        assert (out / "figures" / f"{task.name}.png").stat().st_size > 10_000
        for method in task.methods:
            for seed in range(task.seeds):
                file = out / "results" / task.name / f"{method}-seed{seed}.json"
                assert json.loads(file.read_text())["steps"][-1] > 0
            # one row in the budget table, one in the cost table
            assert sections[task.name].count(f"| {method} |") == 2
    assert "Throughput on this machine" in sections and "commit " in report
    assert f"bench {RUNS}/{RUNS}: 0 failed, elapsed " in result.stderr  # the progress line


def test_a_rerun_skips_every_finished_run(quick, tmp_path):
    out = tmp_path / "out"
    shutil.copytree(quick[0], out)  # its own copy: the other test reads the shared one
    results = sorted((out / "results").rglob("*.json"))
    before = {file: file.stat().st_mtime_ns for file in results}
    again = run_cli("bench", "--quick", "--out", out, "--jobs", "1")  # nothing to run
    assert again.returncode == 0, again.stderr
    assert f"{RUNS} of {RUNS} runs finished before; running 0" in again.stdout
    assert "bench " not in again.stderr  # nothing to run: no progress line
    assert {file: file.stat().st_mtime_ns for file in results} == before


def test_ppo_without_stable_baselines3_is_refused_with_one_line(monkeypatch):
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: None)
    args = argparse.Namespace(quick=True, out=None, jobs=1, world=None, ray=None, report_only=False)
    with pytest.raises(ConfigError, match=r"pip install -e '\.\[bench\]'"):
        bench.run(args)
