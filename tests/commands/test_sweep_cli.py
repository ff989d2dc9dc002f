"""``qdsega sweep``: a grid of runs into one table, on local processes and on Ray."""

from __future__ import annotations

import csv
import json
import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest
from helpers import load_result, made_once, run_cli, save_result, start_cli, stop_when

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

GRID = """\
formations: [quadruped, snake5]   # snake5 cannot run in the MSM: the broken run
seeds: [0]
sim: msm
configs:
  tiny: {agent: {genetic: {generations: 2, population: 6}, learning: {trials: 20}}, workers: 1}
reference_trials: 0
"""


def _rows(out: Path) -> list[dict[str, str]]:
    with (out / "sweep.csv").open() as file:
        return list(csv.DictReader(file))


@pytest.fixture(scope="session")
def local_sweep(tmp_path_factory):
    """The grid swept on local processes into ``out``, made once for all test processes, and
    what the sweep returned."""

    def make(folder):
        (folder / "grid.yaml").write_text(GRID)
        result = run_cli("sweep", folder / "grid.yaml", "--out", folder / "out", "--jobs", "2")
        save_result(result, folder / "result.json")

    folder = made_once(tmp_path_factory, "local-sweep", make)
    return folder, load_result(folder / "result.json")


def test_a_broken_run_is_reported_and_the_others_finish(local_sweep):
    folder, result = local_sweep
    assert result.returncode == 1, result.stderr
    assert "1 of 2 runs finished" in result.stdout
    ok, broken = _rows(folder / "out")
    assert ok["run"] == "quadruped-paper-legged-tiny-seed0" and ok["status"] == "ok"
    assert float(ok["distance_m"]) >= 0 and ok["reference"] == "classic leg gait"
    assert broken["status"] == "failed"
    assert "Minimal Simulation Model needs a legged formation" in broken["error"]
    assert "snake5-paper-legged-tiny-seed0: train: " in result.stdout
    assert (folder / "out" / "sweep.md").read_text().count("\n") == 4  # header, rule, 2 rows
    progress = [line for line in result.stderr.splitlines() if line.startswith("sweep ")]
    assert progress[-1].startswith("sweep 2/2: 1 failed, elapsed "), result.stderr
    assert progress[-1].endswith(", ETA 0:00")


def test_a_rerun_keeps_finished_runs_and_resumes_unfinished_ones(local_sweep, tmp_path):
    folder = tmp_path / "sweep"
    shutil.copytree(local_sweep[0], folder)  # its own copy: other tests read the shared one
    first = (folder / "out" / "sweep.csv").read_text()
    run = folder / "out" / "quadruped-paper-legged-tiny-seed0"
    kept = (run / "evaluation.json").stat().st_mtime_ns
    again = run_cli("sweep", folder / "grid.yaml", "--out", folder / "out")
    assert (run / "evaluation.json").stat().st_mtime_ns == kept
    assert (folder / "out" / "sweep.csv").read_text() == first, again.stderr
    assert again.stderr.count("sweep 2/2: ") == 1, again.stderr  # a kept run adds no line
    (run / "summary.json").unlink()  # as if the run had crashed before its end
    (run / "evaluation.json").unlink()
    resumed = run_cli("sweep", folder / "grid.yaml", "--out", folder / "out")
    assert (run / "summary.json").is_file(), resumed.stdout + resumed.stderr
    assert (folder / "out" / "sweep.csv").read_text() == first


def test_ray_local_gives_the_same_table(local_sweep, local_ray, tmp_path):
    folder, _ = local_sweep
    out = tmp_path / "out"
    result = run_cli("sweep", folder / "grid.yaml", "--out", out, "--ray", "local")
    assert result.returncode == 1, result.stderr
    local = {row["run"]: row for row in _rows(folder / "out")}
    for row in _rows(out):
        assert row == local[row["run"]]


@pytest.mark.parametrize(
    ("grid", "message"),
    [
        ("formations: [quadruped]\nseed: [0]\n", "unknown key 'seed'"),
        ("formations: [nosuch]\n", "no such file, nor a shipped formation"),
        ("formations: [quadruped]\nconfigs: {a: {agent: {nope: 1}}}\n", "configs.a: agent.nope"),
        ("formations: [quadruped]\nconfigs: {a: {seed: 3}}\n", "seed is the grid's to set"),
        ("formations: [quadruped]\nsim: mujoco\n", "sim must be one of"),
    ],
)
def test_a_bad_grid_exits_2_with_one_line_and_runs_nothing(tmp_path, grid, message):
    (tmp_path / "grid.yaml").write_text(grid)
    result = run_cli("sweep", tmp_path / "grid.yaml", "--out", tmp_path / "out")
    assert result.returncode == 2
    assert message in result.stderr and len(result.stderr.splitlines()) == 1
    assert not list((tmp_path / "out").glob("*-seed*"))


def test_a_grid_of_worlds_trains_each_body_in_each_world(tmp_path):
    (tmp_path / "grid.yaml").write_text(
        "formations: [quadruped]\nworlds: [flat, ice]\nsim: memo\nreference_trials: 0\n"
        "configs:\n  tiny: {agent: {genetic: {generations: 1, population: 6}, "
        "learning: {trials: 20}}, task: {trial_steps: 4}, workers: 1, local_search: 1}\n"
    )
    result = run_cli("sweep", tmp_path / "grid.yaml", "--out", tmp_path / "out", "--jobs", "2")
    assert result.returncode == 0, result.stderr
    rows = {row["run"]: row for row in _rows(tmp_path / "out")}
    assert set(rows) == {
        "quadruped-flat-memo-legged-tiny-seed0",
        "quadruped-ice-memo-legged-tiny-seed0",
    }
    assert [rows[r]["world"] for r in sorted(rows)] == ["flat", "ice"]
    summary = json.loads(
        (tmp_path / "out" / "quadruped-ice-memo-legged-tiny-seed0" / "summary.json").read_text()
    )
    assert summary["world"] == "ice"


def _slow_sweep(tmp_path: Path, seeds: str) -> tuple[subprocess.Popen[str], Path, Path]:
    """A sweep of long quadruped runs started in its own process group: the process, its
    output folder and the first run's checkpoint."""
    grid = tmp_path / "grid.yaml"
    grid.write_text(
        f"formations: [quadruped]\nseeds: [{seeds}]\nsim: msm\n"
        "configs:\n  slow: {agent: {genetic: {generations: 200, population: 6}}, workers: 1}\n"
        "reference_trials: 0\n"
    )
    out = tmp_path / "out"
    process = start_cli("sweep", grid, "--out", out, "--jobs", "1")
    return process, out, out / "quadruped-paper-legged-slow-seed0" / "checkpoint.npz"


def test_ctrl_c_stops_the_sweep_and_the_runs_not_started_never_start(tmp_path):
    process, out, first = _slow_sweep(tmp_path, "0, 1, 2")
    stop_when(process, first.is_file, signal.SIGINT)
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stderr
    assert "qdsega sweep: interrupted" in stderr
    for queued in ("seed1", "seed2"):  # seed1 was queued on the run's process: it never starts
        assert not (out / f"quadruped-paper-legged-slow-{queued}").exists()


def test_a_killed_sweep_takes_its_runs_with_it(tmp_path):
    process, _, first = _slow_sweep(tmp_path, "0")
    deadline = time.monotonic() + 120
    while not first.is_file():
        assert process.poll() is None and time.monotonic() < deadline, "the run did not start"
        time.sleep(0.01)
    process.kill()  # the sweep alone, not its process group: its run's process is orphaned
    process.wait()
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:  # the orphaned run stops as Ctrl-C would stop it
        try:
            os.killpg(process.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        os.killpg(process.pid, signal.SIGKILL)
        pytest.fail("the run went on after its sweep was killed")
    assert first.is_file()  # its checkpoint is kept for the next sweep to resume
