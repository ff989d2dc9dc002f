"""The main job through a subprocess with tiny budgets: ``qdsega train --sim memo``, then
``evaluate``, ``plot``, ``render`` and ``report`` on the run folder."""

import json
import re
import subprocess
import sys
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from helpers import run_cli

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

TOOLS = Path(__file__).resolve().parents[2] / "experiments" / "grid"
TINY = """\
workers: 1
local_search: 1
agent:
  learning: {trials: 20}
  genetic: {population: 4, generations: 2}
task: {trial_steps: 4}
"""


def test_memo_training_then_evaluate_plot_render_report(tmp_path):
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

    for budget in ("-5", "3"):  # negative; below one CMA-ES generation
        refused = run_cli("evaluate", run, "--reference-trials", budget)
        assert refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1
        assert "reference" in refused.stderr and not (run / "evaluation.json").exists()
    # one CMA-ES generation (11 trials for 4 joints): the search runs, small
    result = run_cli("evaluate", run, "--reference-trials", "11")
    assert result.returncode == 0, result.stderr
    evaluation = json.loads((run / "evaluation.json").read_text())
    assert evaluation["memo_prediction_m"] == summary["greedy_distance"]
    # policy.npz is the result's policy: PyBullet replays it as far as training measured
    assert evaluation["distance_m"] == pytest.approx(summary["distance_m"], abs=1e-9)
    assert len(evaluation["postures"]) == 4 or evaluation["failure"]
    kinds = [reference["kind"] for reference in evaluation["references"]]
    assert kinds == ["serpenoid travelling wave", "CPG gait searched by CMA-ES"]
    searched = evaluation["references"][1]
    assert searched["budget_trials"] == 11 and searched["budget_steps"] == 11 * 4
    best = max(evaluation["references"], key=lambda reference: reference["distance_m"])
    assert evaluation["reference"] == best and best["distance_m"] > 0.02
    assert f"best reference: {best['kind']}" in result.stdout
    assert evaluation["ratio"] == evaluation["distance_m"] / best["distance_m"]
    units = np.array(evaluation["unit_xy_m"])
    assert units.shape == (len(evaluation["postures"]) + 1, 5, 2)

    plotted = run_cli("plot", run)
    assert plotted.returncode == 0, plotted.stderr
    figures = ["learning_curve", "qtable_size", "fig11_trajectories", "fig13_snake_poses"]
    for name in [*figures, "joint_angles"]:
        image = iio.imread(run / f"{name}.png")
        assert image.shape[0] > 200 and image.shape[1] > 200, name
        assert image[..., :3].std() > 5, name  # something is drawn
    assert not (run / "fig12_gait.png").exists()  # a snake has no legs

    video = run / "gait.mp4"
    rendered = run_cli("render", run, "-o", video, "--fps", "6", "--width", "96", "--height", "64")
    assert rendered.returncode == 0, rendered.stderr
    frames = np.stack(list(iio.imiter(video, plugin="FFMPEG")))
    steps = len(evaluation["postures"])  # 0.5 s each at 6 frames/s, plus the first frame
    assert frames.shape == (1 + 3 * steps, 64, 96, 3) or evaluation["failure"]

    reported = run_cli("report", run)
    assert reported.returncode == 0, reported.stderr
    page = (run / "report.html").read_text()
    assert len(re.findall("src='data:image/png;base64,", page)) == 5
    assert page.count("src='data:video/mp4;base64,") == 1
    assert "serpenoid travelling wave" in page and "paper-snake" in page
    assert "CPG gait searched by CMA-ES, searched in 11 exact trials (m)" in page
    assert page.count("(best)") == 1

    table = subprocess.run(
        [sys.executable, TOOLS / "formation_table.py", run], capture_output=True, text=True
    )
    assert table.returncode == 0, table.stderr
    row = next(line for line in table.stdout.splitlines() if line.startswith("| snake5 | 0 |"))
    assert f"| {evaluation['distance_m']:.3f} |" in row and f"| {evaluation['ratio']:.3f} |" in row
    assert "<h2>Formation: snake5.yaml</h2>" in page and summary["formation_sha256"] in page


def test_plot_and_report_refuse_a_missing_or_unfinished_run(tmp_path):
    for command in ("plot", "report"):
        missing = run_cli(command, tmp_path / "nowhere")
        assert missing.returncode == 2 and len(missing.stderr.strip().splitlines()) == 1
        unfinished = tmp_path / "unfinished"
        unfinished.mkdir(exist_ok=True)
        (unfinished / "config.yaml").write_text("preset: paper-snake\n")
        result = run_cli(command, unfinished)
        assert result.returncode == 2 and "not a finished run folder" in result.stderr


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
        "  learning: {trials: 3}\n"
        "  genetic: {population: 4, generations: 2}\n"
        "task: {trial_steps: 3}\n"
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
