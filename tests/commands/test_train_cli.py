"""``qdsega train`` and ``qdsega plot`` end to end, with tiny budgets."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
import yaml
from helpers import TINY_TRAINING, run_cli

from qdsega.cli import main
from qdsega.commands.train import prediction_warning
from qdsega.description.shipped import ASSEMBLIES_DIR


def test_train_then_plot(cli, tmp_path):
    run = tmp_path / "run"
    result = cli(
        "train", ASSEMBLIES_DIR / "hexapod.yaml", "--sim", "msm", "--preset", "paper-legged",
        "--seed", "2", "--out", run, "--generations", "3", "--trials", "200", "--quiet",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    summary = json.loads((run / "summary.json").read_text())
    for key in ("greedy_distance", "optimum", "generations", "env_steps", "wall_s", "seed"):
        assert key in summary
    assert summary["generations"] == 3 and summary["seed"] == 2 and summary["optimum_proven"]
    rows = list(csv.DictReader((run / "metrics.csv").open()))
    assert [r["generation"] for r in rows] == ["1", "2", "3"]
    exact_m = [float(r["greedy_exact_m"]) for r in rows]  # the result: the farthest, earliest
    assert summary["result_generation"] == exact_m.index(max(exact_m)) + 1
    assert summary["distance_m"] == pytest.approx(max(exact_m), abs=1e-6)
    with np.load(run / "trajectories.npz") as trajectories:
        heading = trajectories["exact_poses"][summary["result_generation"] - 1, -1, 2]
    assert summary["final_heading_deg"] == pytest.approx(math.degrees(heading))
    assert f"greedy policy of generation {summary['result_generation']} " in result.stdout
    config = yaml.safe_load((run / "config.yaml").read_text())
    assert config["agent"]["genetic"]["generations"] == 3 and config["seed"] == 2
    plotted = cli("plot", run)
    assert plotted.returncode == 0, plotted.stderr
    assert (run / "fig11_trajectories.png").stat().st_size > 0
    assert (run / "fig12_gait.png").stat().st_size > 0


def test_msm_on_a_snake_is_a_one_line_error(cli, tmp_path):
    result = cli("train", ASSEMBLIES_DIR / "snake5.yaml", "--out", tmp_path / "r", "--quiet")
    assert result.returncode == 2
    assert "legged formation" in result.stderr and len(result.stderr.strip().splitlines()) == 1


def test_ray_outside_memo_mode_is_refused_before_anything_is_written(tmp_path, cli):
    result = cli("train", "quadruped", "--sim", "msm", "--ray", "local", "--out", tmp_path / "r")
    assert result.returncode == 2
    assert "--ray measures memo transitions: it goes with --sim memo" in result.stderr
    assert not (tmp_path / "r").exists()


@pytest.mark.slow
def test_a_body_that_cannot_move_says_why(project, tmp_path):
    """Servos too weak to hold the body up: every verified trial fails at its first command,
    the progress line and summary.json say how, and train warns once."""
    weak = project / "units" / "weak_servo"
    (project / "units" / "servo").rename(weak)
    unit = weak / "unit.yaml"
    unit.write_text(unit.read_text().replace("effort_nm: 2.5", "effort_nm: 0.02"))
    text = (
        (ASSEMBLIES_DIR / "quadruped.yaml").read_text().replace("unit: servo", "unit: weak_servo")
    )
    formation = project / "assemblies" / "weak.yaml"
    formation.write_text(text + "units_dir: ../units\n")
    (tmp_path / "tiny.yaml").write_text(TINY_TRAINING)
    run = tmp_path / "run"
    result = run_cli(
        "train", formation, "--sim", "memo", "--generations", "2",
        "--config", tmp_path / "tiny.yaml", "--out", run,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    warnings = [line for line in result.stderr.splitlines() if "warning:" in line]
    assert len(warnings) == 1 and "may not be able to move" in warnings[0]
    assert "100.0% of commands failed (trunk touched the ground)" in result.stderr
    summary = json.loads((run / "summary.json").read_text())
    assert summary["failed_commands_share"] == 1.0
    assert summary["most_common_failure"] == "trunk touched the ground"


@pytest.mark.parametrize("option", ["FORMATION", "--config", "--world"])
def test_a_nul_character_in_any_yaml_is_one_line_with_the_file_and_its_line(
    option, tmp_path, capsys
):
    """Every YAML train reads (a formation, a config, a world) goes through the one reader."""
    texts = {
        "FORMATION": (ASSEMBLIES_DIR / "quadruped.yaml").read_text(),
        "--config": "seed: 3\nworkers: 1\n",
        "--world": "name: moon\nground: {friction: 0.5}\n",
    }
    first, second, *rest = texts[option].splitlines(keepends=True)
    text = "".join([first, second[:3] + "\x00" + second[3:], *rest])  # in the second line
    file = tmp_path / "bad.yaml"
    file.write_text(text)
    given = [str(file)] if option == "FORMATION" else ["quadruped", option, str(file)]
    run = tmp_path / "run"
    assert main(["train", *given, "--sim", "memo", "--out", str(run), "--quiet"]) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith(f"qdsega train: error: {file}:2: YAML syntax error: ")
    assert "unacceptable character #x0000" in line and not run.exists()


def test_resuming_a_finished_run_succeeds_and_says_where_its_result_is(tmp_path, capsys):
    run = tmp_path / "run"
    args = ["--sim", "msm", "--generations", "1", "--trials", "200", "--out", str(run)]
    assert main(["train", "quadruped", *args, "--quiet"]) == 0
    (trained,) = capsys.readouterr().out.splitlines()
    before = {p.name: p.stat().st_mtime_ns for p in run.iterdir()}
    assert main(["train", "--resume", str(run)]) == 0
    captured = capsys.readouterr()
    (line,) = captured.out.splitlines()
    prefix = "quadruped: the run is already finished, nothing to resume; its result: "
    assert line == prefix + trained.removeprefix("quadruped: ") and captured.err == ""
    assert line.endswith(f" -> {run}")
    assert {p.name: p.stat().st_mtime_ns for p in run.iterdir()} == before  # untouched


def test_a_memo_run_whose_table_missed_says_so():
    summary = {"sim": "memo", "prediction_error": 1.4}
    assert "+140% off exact physics (more than 10%)" in prediction_warning(summary)
    assert prediction_warning({**summary, "prediction_error": -0.09}) is None
    assert prediction_warning({**summary, "prediction_error": None}) is None  # 0 m exact
    assert prediction_warning({"sim": "pybullet", "prediction_error": 1.4}) is None
