"""``qdsega train --warm-start`` and ``qdsega evaluate --formation`` through a subprocess: a
changed body starts from what a run learnt; deterministic, resumable after SIGKILL, refused in
one line when nothing carries over or the input is bad."""

from __future__ import annotations

import json
import shutil
import signal

import pytest
from helpers import assert_same_result, finished_generations, run_cli, start_cli, stop_when

from qdsega.description.shipped import ASSEMBLIES_DIR

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

MSM = ["--sim", "msm", "--trials", "2000", "--quiet"]
MEMO_BUDGET = """\
workers: 1
local_search: 1
agent:
  learning: {trials: 20}
  genetic: {population: 6, generations: 2}
task: {trial_steps: 6}
"""


@pytest.fixture(scope="module")
def quadruped_run(tmp_path_factory: pytest.TempPathFactory):
    """A finished quadruped run in the MSM (the source of the warm starts)."""
    run = tmp_path_factory.mktemp("source") / "quadruped"
    result = run_cli("train", "quadruped", *MSM, "--generations", "2", "--out", run)
    assert result.returncode == 0, result.stderr
    return run


def _warm(source, out, *extra):
    return run_cli(
        "train", "quadruped_tripod", *MSM, "--generations", "3", "--seed", "4",
        "--warm-start", source, "--out", out, *extra,
    )  # fmt: skip


def test_a_warm_start_is_recorded_deterministic_and_resumes_exactly(quadruped_run, tmp_path):
    first, second = tmp_path / "first", tmp_path / "second"
    for out in (first, second):
        result = _warm(quadruped_run, out)
        assert result.returncode == 0, result.stderr
    assert_same_result(first, second, "same seed, same warm start")
    record = json.loads((first / "warm_start.json").read_text())
    assert record["formation"] == "quadruped" and record["run"] == str(quadruped_run.resolve())
    assert record["joints"]["dropped"] == ["R2_swing_joint", "R2_lift_joint"]
    assert record["joints"]["added"] == [] and len(record["joints"]["matched"]) == 6
    summary = json.loads((first / "summary.json").read_text())
    assert summary["warm_start"] == record
    killed = tmp_path / "killed"
    process = start_cli(
        "train", "quadruped_tripod", *MSM, "--generations", "3", "--seed", "4",
        "--warm-start", quadruped_run, "--out", killed,
    )  # fmt: skip
    stop_when(process, lambda: finished_generations(killed) >= 1, signal.SIGKILL)
    process.wait()
    resumed = run_cli("train", "--resume", killed, "--quiet")
    assert resumed.returncode == 0, resumed.stderr
    assert_same_result(first, killed, "warm start killed after a generation, resumed")


def test_a_warm_start_differs_from_a_fresh_run(quadruped_run, tmp_path):
    warm, fresh = tmp_path / "warm", tmp_path / "fresh"
    assert _warm(quadruped_run, warm).returncode == 0
    result = run_cli(
        "train", "quadruped_tripod", *MSM, "--generations", "3", "--seed", "4", "--out", fresh
    )
    assert result.returncode == 0, result.stderr
    assert (warm / "metrics.csv").read_text() != (fresh / "metrics.csv").read_text()
    assert json.loads((fresh / "summary.json").read_text())["warm_start"] is None
    plotted = run_cli("plot", warm)
    assert plotted.returncode == 0, plotted.stderr
    assert "no fresh run" not in plotted.stderr  # found beside it


def test_a_warm_start_from_an_unrelated_body_needs_allow_unmatched(quadruped_run, tmp_path):
    text = (ASSEMBLIES_DIR / "quadruped.yaml").read_text()
    other = tmp_path / "other.yaml"
    other.write_text(text.replace('"L{i}"', '"P{i}"').replace('"R{i}"', '"Q{i}"'))
    out = tmp_path / "refused"
    result = run_cli("train", other, *MSM, "--generations", "1", "--warm-start", quadruped_run,
                     "--out", out)  # fmt: skip
    assert result.returncode == 2 and not out.exists()
    assert result.stderr.count("\n") == 1
    assert "shares no joint name with" in result.stderr and "--allow-unmatched" in result.stderr
    result = run_cli("train", other, *MSM, "--generations", "1", "--warm-start", quadruped_run,
                     "--out", out, "--allow-unmatched")  # fmt: skip
    assert result.returncode == 0, result.stderr
    record = json.loads((out / "warm_start.json").read_text())
    assert record["joints"]["matched"] == [] and len(record["joints"]["added"]) == 8


@pytest.mark.parametrize("case", ["missing", "unfinished", "allow without warm start"])
def test_a_bad_warm_start_is_one_line_and_writes_nothing(quadruped_run, tmp_path, case):
    source = tmp_path / "source"
    extra: list[str | object] = ["--warm-start", source]
    if case == "unfinished":
        source.mkdir()
        (source / "config.yaml").write_text("sim: msm\n")
    if case == "allow without warm start":
        extra = ["--allow-unmatched"]
    out = tmp_path / "out"
    result = run_cli("train", "quadruped_tripod", *MSM, *extra, "--out", out)
    assert result.returncode == 2 and not out.exists(), result.stderr
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("qdsega train: error:")


def test_a_locked_angle_outside_the_limits_is_one_line_and_writes_nothing(tmp_path):
    text = (ASSEMBLIES_DIR / "legged12_locked_leg.yaml").read_text()
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace("lift: {locked_deg: -35}", "lift: {locked_deg: -135}"))
    out = tmp_path / "out"
    result = run_cli("train", bad, *MSM, "--out", out)
    assert result.returncode == 2 and not out.exists()
    assert result.stderr.count("\n") == 1
    assert "locked angle -135 deg is outside the joint limits [-90, 90] deg" in result.stderr


def test_a_snake_policy_on_a_longer_snake_then_a_warm_start_in_memo_mode(tiny_run, tmp_path):
    """The whole reconfiguration path in PyBullet on tiny budgets: evaluate --formation, train
    --warm-start, the learning curve beside a fresh run, the report."""
    config = tmp_path / "tiny.yaml"
    config.write_text(MEMO_BUDGET)
    memo = ["--sim", "memo", "--preset", "paper-snake", "--config", config, "--quiet"]
    source, warm, fresh = tmp_path / "snake5", tmp_path / "warm", tmp_path / "fresh"
    shutil.copytree(tiny_run, source)  # a finished snake5 run in memo mode (4-posture trials)
    result = run_cli("evaluate", source, "--formation", "snake6")
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("snake5 policy on snake6: ")
    assert "4 joints matched, 1 added (u6_joint)" in result.stdout
    transfer = json.loads((source / "evaluation-on-snake6.json").read_text())
    assert transfer["failure"] is None and len(transfer["postures"]) == 4  # the source's trial
    assert all(len(p) == 5 for p in transfer["postures"])
    assert run_cli("train", "snake6", *memo, "--out", fresh).returncode == 0
    result = run_cli("train", "snake6", *memo, "--out", warm, "--warm-start", source)
    assert result.returncode == 0, result.stderr
    plotted = run_cli("plot", warm, "--fresh", fresh)
    assert plotted.returncode == 0, plotted.stderr
    for run in (source, warm):
        assert run_cli("report", run).returncode == 0
    report = (warm / "report.html").read_text()
    assert "<h2>Warm start</h2>" in report
    # the handed-on path, verified before generation 1, is recorded and reported
    record = json.loads((warm / "warm_start.json").read_text())
    handed_on = record["handed_on_m"]
    assert isinstance(handed_on, float) and "its best path on this body" in report
    assert 1 <= record["handed_on_steps"] <= 6  # the commands of one trial (the task's 6 at most)
    assert json.loads((warm / "summary.json").read_text())["warm_start"]["handed_on_m"] == handed_on
    assert "This policy on other bodies" in (source / "report.html").read_text()
