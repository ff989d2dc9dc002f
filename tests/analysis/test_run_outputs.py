"""What a finished run shows: figures, a page and a video, from the run folder alone."""

from __future__ import annotations

import shutil

import imageio.v3 as iio
import pytest
from helpers import run_cli


def test_plot_report_and_render_read_the_run_folder_alone(tiny_run, tmp_path):
    run = tmp_path / "moved"
    shutil.copytree(tiny_run, run)  # a run folder works wherever it is
    assert run_cli("plot", run).returncode == 0
    for name in ("learning_curve", "qtable_size", "fig11_trajectories", "joint_angles"):
        assert iio.imread(run / f"{name}.png").shape[0] > 200, name
    video = run / "gait.gif"
    rendered = run_cli("render", run, "-o", video, "--width", "96", "--height", "64", "--fps", "2")
    assert rendered.returncode == 0, rendered.stderr
    assert iio.imread(video, index=None).shape[1:] == (64, 96, 3)
    reported = run_cli("report", run)
    assert reported.returncode == 0, reported.stderr
    page = (run / "report.html").read_text()
    assert "learning_curve" in page and "snake5" in page


def test_the_summary_says_how_the_verified_trials_failed(tiny_run):
    import json

    summary = json.loads((tiny_run / "summary.json").read_text())
    assert 0.0 <= summary["failed_commands_share"] <= 1.0
    assert summary["most_common_failure"] is None or isinstance(summary["most_common_failure"], str)
    assert summary["preset"] == "paper-snake"  # the body's own preset: no --preset given


@pytest.mark.slow
def test_evaluate_judges_a_run_in_another_world_and_says_which(tiny_run, tmp_path):
    """A snake learnt on flat ground, judged on ice: its own file, the world named in the line,
    the file and the report; the run's own evaluation is left as it was."""
    import json

    run = tmp_path / "run"
    shutil.copytree(tiny_run, run)
    own = (run / "evaluation.json").read_text()
    judged = run_cli("evaluate", run, "--world", "ice", "--reference-trials", "0")
    assert judged.returncode == 0, judged.stderr
    file = run / "evaluation-in-ice.json"
    (line,) = judged.stdout.splitlines()
    assert line.startswith("snake5 in ice: learnt policy ") and line.endswith(f"-> {file}")
    on_ice, on_flat = json.loads(file.read_text()), json.loads(own)
    assert (on_ice["world"], on_flat["world"]) == ("ice", "flat")
    assert on_ice["memo_prediction_m"] is None  # the table knew the flat ground only
    assert on_ice["distance_m"] != on_flat["distance_m"]  # ice is slipperier
    assert (run / "evaluation.json").read_text() == own
    moved = run_cli("evaluate", run, "--world", "ice", "--formation", "snake6")
    assert moved.returncode == 0, moved.stderr
    assert moved.stdout.startswith("snake5 policy on snake6 in ice: ")
    assert json.loads((run / "evaluation-on-snake6-in-ice.json").read_text())["world"] == "ice"
    assert run_cli("report", run).returncode == 0
    page = (run / "report.html").read_text()
    assert "snake5 in ice" in page and "snake6 in ice" in page
    refused = run_cli("evaluate", run, "--world", "moon")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1
    assert "no such file, nor a shipped world" in refused.stderr
