"""Every script in experiments/ and tools/ runs: ``--help``, or a budget of seconds.

The scripts are measurements that take minutes to hours; these tests only check that each one
still fits the package (imports, names, run folders), in a subprocess as a user runs it.
``tools/random_formations.py`` and ``tools/diagrams.py`` have their own tests
(tests/assembly/test_random_formations.py, tests/experiments/test_diagrams.py).
"""

from __future__ import annotations

import csv
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from qdsega.analysis.evaluation import evaluate_run
from qdsega.sweep import TABLE_COLUMNS, read_grid

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

ROOT = Path(__file__).resolve().parents[2]
TINY = """\
agent:
  learning: {trials: 20}
  genetic: {population: 4, generations: 1}
task: {trial_steps: 4}
local_search: 0
explore_trials: 0
optimism: 0
"""
OLD_RUN = "quadruped-memo-legged-default-seed0"
"""The old run reconfiguration_table.py makes in its --grid for quadruped_tripod, seed 0."""

HELP_ONLY = (
    "tools/reference_search.py",
    "experiments/scale_out/benchmark_scale.py",  # minutes, and Ray
    "experiments/gait_predictions/gait_predictions.py",  # a CMA-ES gait's exact trials
    "experiments/msm/benchmark_msm.py",  # reproduce_msm.py's training, timed
    "experiments/memo_speed/memo_mirror.py",  # physics_curve.py's measuring, mirrored
    "experiments/reform/screening_correlation.py",  # full runs of every candidate
    "experiments/reform/reform_table.py",  # reads reform folders (tests/reform covers them)
    "experiments/adaptation/blind_table.py",  # adapt and adapt_blind: tests/adaptation covers them
)
TINY_RUNS = {
    "experiments/msm/reproduce_msm.py": (
        "--seeds", "0", "--generations", "2", "--trials", "50", "--out", "{tmp}/reproduce",
    ),
    "experiments/msm/sweep_msm.py": (
        "--seeds", "0", "--generations", "2", "--trials", "50", "--set", "agent.fitness.k_f=100",
    ),
    "experiments/memo_speed/physics_curve.py": (
        "snake5", "--postures", "1", "--settings", "240:50,120:20",
    ),
    "experiments/physics_fidelity/run.py": (
        "--bodies", "snake5", "--worlds", "flat", "--hz", "240,60", "--iterations", "50",
        "--settle", "0.5,0.25", "--steps", "2", "--repeats", "1", "--copies", "1,2",
        "--copy-seconds", "0.5",
    ),
    "experiments/snake_slope/run.py": ("--quick", "--steps", "2"),
    "experiments/file_physics/run.py": ("--bodies", "quadruped", "--seconds", "0.5"),
}  # fmt: skip
ON_A_REPERTOIRE = "experiments/adaptation/adaptation_table.py"
STAND_IN = "experiments/adaptation/stand_in_robot.py"  # run below on a tiny repertoire
ON_A_RUN = (  # run below on the tiny runs reconfiguration_table.py makes
    "experiments/reconfiguration/reconfiguration_table.py",
    "experiments/memo_speed/memo_shortcuts.py",
    "experiments/grid/formation_table.py",
)


def script(path: str, *args: str | Path) -> subprocess.CompletedProcess[str]:
    """``python PATH ARGS`` from the checkout's root, as the READMEs run it."""
    return subprocess.run(
        [sys.executable, ROOT / path, *map(str, args)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
        check=False,
    )


def test_every_script_is_smoke_tested_and_has_a_usage_and_a_main():
    scripts = {
        str(p.relative_to(ROOT))
        for folder in ("experiments", "tools")
        for p in (ROOT / folder).rglob("*.py")
    }
    own_tests = {"tools/random_formations.py", "tools/diagrams.py"}
    tested = {*HELP_ONLY, *TINY_RUNS, *ON_A_RUN, ON_A_REPERTOIRE, STAND_IN, *own_tests}
    assert scripts == tested
    for path in scripts:
        text = (ROOT / path).read_text(encoding="utf-8")
        assert text.startswith('"""') and "Usage: " in text.split('"""')[1], path
        assert "def main() -> int:" in text or "def main() -> None:" in text, path
        assert "argparse.ArgumentParser" in text, path
        readme = ROOT / Path(path).parent / "README.md"
        assert path.startswith("tools/") or Path(path).name in readme.read_text(), path


HELP_ALL = """\
import runpy, sys
for path in sys.argv[1:]:
    sys.argv = [path, "--help"]
    try:
        runpy.run_path(path, run_name="__main__")
    except SystemExit as exit:
        assert exit.code in (0, None), (path, exit.code)
    else:
        raise AssertionError(f"{path}: --help did not exit")
"""
"""Runs each script's ``--help`` in turn in one process (the imports once: seconds saved)."""


def test_help():
    paths = [ROOT / path for path in HELP_ONLY]
    result = subprocess.run(
        [sys.executable, "-c", HELP_ALL, *map(str, paths)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    for path in paths:
        assert f"usage: {path.name} " in result.stdout, path


@pytest.mark.parametrize("path", sorted(TINY_RUNS))
def test_tiny_run(path, tmp_path):
    result = script(path, *(arg.format(tmp=tmp_path) for arg in TINY_RUNS[path]))
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip(), "it printed its result"


def test_the_grid_file_reads(tmp_path):
    runs = read_grid(ROOT / "experiments" / "grid" / "grid.yaml", tmp_path)
    assert len(runs) == 5 * 5 and {r.sim for r in runs} == {"memo"}
    presets = {r.formation.stem: r.preset for r in runs}
    assert presets["snake5"] == presets["snake10"] == "paper-snake"
    assert presets["quadruped"] == presets["hexapod"] == presets["legged12"] == "memo-legged"
    assert (tmp_path / "configs" / "default.yaml").is_file()
    assert "snake5-paper-snake-default-seed0" in {r.name for r in runs}


@pytest.fixture(scope="module")
def reconfigured(tmp_path_factory):
    """reconfiguration_table.py on one change and seed, every run tiny: (grid, out)."""
    tmp = tmp_path_factory.mktemp("reconfiguration")
    (tmp / "tiny.yaml").write_text(TINY)
    grid, out = tmp / "grid", tmp / "out"
    result = script(
        "experiments/reconfiguration/reconfiguration_table.py",
        "--changes", "quadruped_tripod", "--seeds", "0", "--workers", "1",
        "--config", tmp / "tiny.yaml", "--grid", grid, "--out", out,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    return grid, out


def test_reconfiguration_table_makes_the_old_fresh_and_warm_runs(reconfigured):
    grid, out = reconfigured
    table = (out / "table.md").read_text()
    assert "| a back leg lost (tripod) | 0 | " in table
    assert (grid / OLD_RUN / "evaluation-on-quadruped_tripod.json").is_file()
    assert (out / "fresh" / "quadruped_tripod-seed0" / "summary.json").is_file()
    assert (out / "warm" / "quadruped_tripod-seed0" / "warm_start.json").is_file()


def test_memo_shortcuts_reads_a_memo_run(reconfigured):
    grid, _ = reconfigured
    result = script("experiments/memo_speed/memo_shortcuts.py", grid / OLD_RUN)
    assert result.returncode == 0, result.stderr
    assert "distinct" in result.stdout and "R^2 of dx" in result.stdout


def test_formation_table_reads_a_run_and_a_sweeps_folder(reconfigured):
    grid, _ = reconfigured
    evaluate_run(grid / OLD_RUN, reference_trials=0)
    with (grid / "sweep.csv").open("w", newline="") as stream:  # as qdsega sweep writes it
        writer = csv.DictWriter(stream, TABLE_COLUMNS)
        writer.writeheader()
        writer.writerow({"run": OLD_RUN, "status": "ok"})
        writer.writerow({"run": "hexapod-memo-legged-default-seed0", "status": "failed",
                         "error": "train: boom"})  # fmt: skip
    result = script("experiments/grid/formation_table.py", grid / OLD_RUN, grid, grid / "none")
    assert result.returncode == 2 and "neither a run folder" in result.stderr
    result = script("experiments/grid/formation_table.py", grid / OLD_RUN, grid)
    assert result.returncode == 0, result.stderr
    assert result.stdout.count("| quadruped | 0 | 4 x 1 x 20 |") == 2
    assert "| quadruped-memo-legged-default | 2 |" in result.stdout
    assert "left out (train: boom)" in result.stderr


def test_adaptation_table_adapts_a_tiny_repertoire(quadruped_repertoire, tmp_path):
    repertoires = tmp_path / "repertoires"
    shutil.copytree(quadruped_repertoire, repertoires / "quadruped-seed0")
    (tmp_path / "tiny.yaml").write_text(TINY)
    result = script(ON_A_REPERTOIRE, "--repertoires", repertoires, "--seeds", "0", "--trials",
                    "2", "--oracle", "--warm", "--config", tmp_path / "tiny.yaml", "--out",
                    tmp_path / "out")  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "| a back leg lost (tripod) (`quadruped_tripod`) | 0 | " in result.stdout
    assert "skipped hexapod_lost_leg seed 0: no hexapod-seed0 repertoire" in result.stdout
    assert (tmp_path / "out" / "quadruped_tripod-seed0" / "adapt.json").is_file()
    warm = tmp_path / "out" / "quadruped_tripod-seed0-warm"
    assert (warm / "warm_start.json").is_file() and (warm / "summary.json").is_file()


def test_the_stand_in_robot_drives_an_external_adaptation_to_its_end(
    quadruped_repertoire, tmp_path
):
    out = tmp_path / "robot"
    result = script(STAND_IN, quadruped_repertoire, "--body", "quadruped_tripod", "--trials", "2",
                    "--out", out)  # fmt: skip
    assert result.returncode == 0, result.stderr
    found = json.loads((out / "adapt.json").read_text())
    assert found["mode"] == "external" and 1 <= len(found["trials"]) <= 2
    assert sorted(p.stem for p in (out / "trials").glob("*.result")) == [
        f"{k:03d}" for k in range(1, len(found["trials"]) + 1)
    ]
