"""``qdsega train --sim memo`` and ``qdsega evaluate`` through a subprocess, tiny budgets."""

import json

import numpy as np
from helpers import run_cli

TINY = """\
workers: 1
agent:
  learning: {trials: 20, trial_steps: 4}
  genetic: {population: 4, generations: 2}
"""


def test_memo_training_then_exact_evaluation(tmp_path):
    config = tmp_path / "tiny.yaml"
    config.write_text(TINY)
    run = tmp_path / "run"
    result = run_cli(
        "train",
        "assemblies/snake5.yaml",
        "--sim",
        "memo",
        "--preset",
        "paper-snake",
        "--config",
        config,
        "--out",
        run,
        "--quiet",
    )
    assert result.returncode == 0, result.stderr
    for name in ("config.yaml", "metrics.csv", "summary.json", "policy.npz", "transitions.npz"):
        assert (run / name).is_file(), name
    summary = json.loads((run / "summary.json").read_text())
    assert summary["sim"] == "memo" and summary["optimum"] is None
    with np.load(run / "transitions.npz") as table:
        assert table["pairs"].shape[1] == 8 and len(table["values"]) >= 4

    result = run_cli("evaluate", run)
    assert result.returncode == 0, result.stderr
    evaluation = json.loads((run / "evaluation.json").read_text())
    assert evaluation["memo_prediction_m"] == summary["greedy_distance"]
    assert len(evaluation["postures"]) == 4 or evaluation["failure"]
    assert evaluation["reference"]["kind"] == "serpenoid travelling wave"
    assert evaluation["reference"]["distance_m"] > 0.02
    assert evaluation["ratio"] == evaluation["distance_m"] / evaluation["reference"]["distance_m"]


def test_evaluate_refuses_a_missing_or_corrupt_run(tmp_path):
    missing = run_cli("evaluate", tmp_path / "nowhere")
    assert missing.returncode == 2 and "run folder not found" in missing.stderr
    corrupt = tmp_path / "corrupt"
    corrupt.mkdir()
    for name in ("summary.json", "config.yaml"):
        (corrupt / name).write_text("{}")
    (corrupt / "policy.npz").write_bytes(b"not a zip")
    result = run_cli("evaluate", corrupt)
    assert result.returncode == 2
    assert "corrupt run folder" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_exact_mode_trains_with_every_step_in_pybullet(tmp_path):
    config = tmp_path / "tiny.yaml"
    config.write_text(
        "agent:\n"
        "  learning: {trials: 3, trial_steps: 3}\n"
        "  genetic: {population: 4, generations: 2}\n"
    )
    run = tmp_path / "run"
    result = run_cli(
        "train",
        "assemblies/quadruped.yaml",
        "--sim",
        "pybullet",
        "--config",
        config,
        "--out",
        run,
        "--quiet",
    )
    assert result.returncode == 0, result.stderr
    summary = json.loads((run / "summary.json").read_text())
    assert summary["sim"] == "pybullet" and summary["env_steps"] >= 2 * 3
    assert not (run / "transitions.npz").exists()
    with np.load(run / "trajectories.npz") as data:
        assert data["gait_legs"].shape[1] == 4  # the quadruped's legs
