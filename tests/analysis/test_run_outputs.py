"""What a finished run shows: figures, a page and a video, from the run folder alone."""

from __future__ import annotations

import shutil

import imageio.v3 as iio
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
