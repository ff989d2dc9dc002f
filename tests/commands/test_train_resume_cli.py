"""``qdsega train`` stopped (SIGKILL, Ctrl-C) and resumed ends exactly like an uninterrupted run."""

from __future__ import annotations

import json
import math
import os
import random
import signal
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import (
    assert_same_result,
    finished_generations,
    made_once,
    run_cli,
    start_cli,
    stop_after,
    stop_when,
)

from qdsega.description.shipped import ASSEMBLIES_DIR

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

MEMO_BUDGET = """\
workers: {workers}
local_search: 2
agent:
  learning: {{trials: 40}}
  genetic: {{population: 4, generations: 3}}
task: {{trial_steps: 4}}
"""


def _train_args(kind: str, tmp_path: Path, out: Path, workers: int = 1) -> list[str | Path]:
    if kind == "msm":
        return [
            "train", ASSEMBLIES_DIR / "legged12.yaml", "--sim", "msm", "--seed", "3",
            "--generations", "6", "--trials", "6000", "--out", out, "--quiet",
        ]  # fmt: skip
    in_world = kind == "memo in a world"
    config = tmp_path / f"budget{workers}.yaml"
    # two starts of the memo's moves, not rubble's six: the same resume, a third of the time
    config.write_text(MEMO_BUDGET.format(workers=workers) + ("memo_spots: 2\n" if in_world else ""))
    world = ["--world", "rubble"] if in_world else []
    return [
        "train", ASSEMBLIES_DIR / "snake5.yaml", "--sim", "memo", "--preset", "paper-snake",
        "--config", config, "--seed", "1", "--out", out, "--quiet", *world,
    ]  # fmt: skip


@pytest.fixture(scope="session")
def uninterrupted(tmp_path_factory: pytest.TempPathFactory) -> Callable[[str], tuple[Path, float]]:
    """The uninterrupted run of each kind, made once for all test processes
    (:func:`helpers.made_once`), and its wall time (s)."""

    def get(kind: str) -> tuple[Path, float]:
        def make(folder: Path) -> None:
            start = time.monotonic()
            result = run_cli(*_train_args(kind, folder, folder / "run"))
            assert result.returncode == 0, result.stderr
            (folder / "wall_s.txt").write_text(f"{time.monotonic() - start!r}")

        folder = made_once(tmp_path_factory, f"whole-{kind.replace(' ', '-')}", make)
        return folder / "run", float((folder / "wall_s.txt").read_text())

    return get


_MOMENTS = {
    # the formation's copy is written, the first checkpoint is not (yet)
    "before the first checkpoint": lambda run: (run / "formation.json").is_file(),
    "during the first generation": lambda run: (run / "checkpoint.npz").is_file(),
    "after two generations": lambda run: finished_generations(run) >= 2,
}


MSM_MOMENTS = (*_MOMENTS, "at a random moment")
MEMO_MOMENTS = ("during the first generation", "after two generations")
"""Where memo mode's state (the measured table, in the checkpoint) exists: killed before the
first checkpoint, a run restarts whatever its simulator, as the MSM's case shows."""


@pytest.mark.parametrize(
    ("kind", "moment"),
    [
        *(
            (kind, moment)
            for kind in ("msm", "memo")
            for moment in (MSM_MOMENTS if kind == "msm" else MEMO_MOMENTS)
        ),
        ("memo in a world", "after two generations"),
    ],
)
def test_sigkill_then_resume_equals_an_uninterrupted_run(kind, moment, uninterrupted, tmp_path):
    whole, wall_s = uninterrupted(kind)
    killed = tmp_path / "killed"
    args = _train_args(kind, tmp_path, killed)
    process = start_cli(*args)
    if moment in _MOMENTS:
        stop_when(process, lambda: _MOMENTS[moment](killed), signal.SIGKILL)
    else:
        time.sleep(random.uniform(0.0, wall_s))
        os.killpg(process.pid, signal.SIGKILL)
    process.wait(timeout=30)
    files = sorted(p.name for p in killed.iterdir()) if killed.is_dir() else []
    why = f"killed {moment} with {files}"
    if moment == "before the first checkpoint":
        assert "checkpoint.npz" not in files, f"killed too late: {why}"
    if moment == "during the first generation":
        assert "metrics.csv" not in files, f"killed too late: {why}"

    if "summary.json" in files:  # a random moment after the end
        pass
    elif "formation.json" in files:  # written with config.yaml, before anything slow
        resumed = run_cli("train", "--resume", killed)
        assert resumed.returncode == 0, f"{resumed.stderr} ({why})"
    else:  # killed before it wrote its set-up: --resume says to start it, and that works
        refused = run_cli("train", "--resume", killed)
        expected = "qdsega train FORMATION --out" if files else "run folder not found"
        assert refused.returncode == 2 and expected in refused.stderr, why
        started = run_cli(*args, "--overwrite")
        assert started.returncode == 0, f"{started.stderr} ({why})"
    assert_same_result(whole, killed, why)


def test_a_second_train_is_refused_while_the_first_writes_and_a_dead_ones_lock_is_not(tmp_path):
    run = tmp_path / "run"
    args = _train_args("msm", tmp_path, run)
    first = start_cli(*args)
    stop_when(first, lambda: (run / "formation.json").is_file(), signal.SIGSTOP)
    try:
        for second in (["train", "--resume", run], [*args, "--overwrite"]):
            refused = run_cli(*second)
            assert refused.returncode == 2, refused.stderr
            assert f"another qdsega train (pid {first.pid}) is writing" in refused.stderr
            assert len(refused.stderr.strip().splitlines()) == 1
        assert (run / "config.yaml").is_file() and (run / "formation.json").is_file()
    finally:
        os.killpg(first.pid, signal.SIGKILL)
    first.wait(timeout=30)
    assert (run / "train.lock").read_text() == f"{first.pid}\n"  # its holder is gone
    resumed = run_cli("train", "--resume", run)
    assert resumed.returncode == 0, resumed.stderr
    assert (run / "summary.json").is_file()


def test_ctrl_c_saves_and_resume_finishes(tmp_path):
    run = tmp_path / "run"
    # two generations: one finished before Ctrl-C, one for the resume
    process = start_cli(*_train_args("memo", tmp_path, run, workers=2), "--generations", "2")
    stop_after(process, run, 1, signal.SIGINT)
    out, err = process.communicate(timeout=60)
    assert process.returncode == 130, err
    assert "Traceback" not in err and "Traceback" not in out
    assert f"qdsega train --resume {run}" in out
    assert not [p.name for p in run.iterdir() if "partial" in p.name]

    resumed = run_cli("train", "--resume", run)
    assert resumed.returncode == 0, resumed.stderr
    assert finished_generations(run) == 2 and (run / "summary.json").is_file()
    again = run_cli("train", "--resume", run)
    assert again.returncode == 0 and "already finished, nothing to resume" in again.stdout


def test_an_existing_run_folder_is_never_overwritten(tmp_path):
    run = tmp_path / "run"
    run.mkdir()
    (run / "keep.txt").write_text("mine")
    args = ["train", ASSEMBLIES_DIR / "quadruped.yaml", "--generations", "1", "--trials", "10"]
    for overwrite in ([], ["--overwrite"]):
        refused = run_cli(*args, "--out", run, "--quiet", *overwrite)
        assert refused.returncode == 2 and "not a run folder" in refused.stderr
        assert [p.name for p in run.iterdir()] == ["keep.txt"]
    (run / "keep.txt").unlink()
    first = run_cli(*args, "--out", run, "--quiet")
    assert first.returncode == 0, first.stderr
    again = run_cli(*args, "--out", run, "--quiet")
    assert again.returncode == 2 and "continue it with --resume" in again.stderr
    (run / "keep.txt").write_text("old run")
    replaced = run_cli(*args, "--out", run, "--quiet", "--overwrite")
    assert replaced.returncode == 0, replaced.stderr
    assert not (run / "keep.txt").exists() and (run / "summary.json").is_file()


def test_default_run_folder_names_formation_sim_and_seed(tmp_path):
    result = run_cli(
        "train", ASSEMBLIES_DIR / "quadruped.yaml", "--seed", "5", "--generations", "2",
        "--trials", "10", cwd=tmp_path,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    run = tmp_path / "runs" / "quadruped-msm-seed5"
    assert (run / "summary.json").is_file()
    lines = result.stderr.strip().splitlines()  # not a terminal: one log line per generation
    assert [line.split(":")[0] for line in lines] == ["generation 1/2", "generation 2/2"]
    assert "exact" in lines[0] and "Q-table" in lines[0] and "ETA" in lines[0]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--resume", "nowhere"], "run folder not found"),
        (["--resume", "nowhere", "--seed", "3"], "drop --seed"),
        ([ASSEMBLIES_DIR / "snake5.yaml", "--preset", "fastest"], "unknown preset"),
        ([ASSEMBLIES_DIR / "snake5.yaml", "--sim", "msm"], "legged formation"),
        ([], "give a FORMATION.yaml"),
    ],
)
def test_bad_input_is_one_line_and_status_2_and_writes_nothing(args, message, tmp_path):
    result = run_cli("train", *args, "--quiet", cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    assert message in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_resume_refuses_a_corrupt_checkpoint(tmp_path):
    run = tmp_path / "run"
    result = run_cli(
        "train", ASSEMBLIES_DIR / "quadruped.yaml", "--generations", "1", "--trials", "10",
        "--out", run, "--quiet",
    )  # fmt: skip
    assert result.returncode == 0
    (run / "summary.json").unlink()
    (run / "checkpoint.npz").write_bytes(b"garbage")
    resumed = run_cli("train", "--resume", run)
    assert resumed.returncode == 2 and "corrupt checkpoint.npz" in resumed.stderr


def test_a_step_too_short_for_a_joint_is_refused_with_the_key_to_change(write_formation, tmp_path):
    formation = write_formation(
        """\
        name: wide
        light: {distance_m: 50.0}
        units:
          - {name: u1, unit: servo}
          - {name: u2, unit: servo, parent: u1, connector: back, axis: yaw,
             levels_deg: [-90, 90]}
        """
    )
    config = tmp_path / "short.yaml"
    config.write_text("lower_agent: {step_duration_s: 0.5}\n")
    run = tmp_path / "run"
    result = run_cli(
        "train", formation, "--sim", "memo", "--config", config, "--out", run, "--quiet"
    )
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    # 180 deg at 1.5 rad/s is 2.09 s; with the arrival margin, 2.15 s on the 0.05 s grid.
    assert "set lower_agent.step_duration_s to at least 2.15" in result.stderr
    assert not run.exists()


def test_a_snake_with_60_deg_level_spans_trains_with_no_configuration(write_formation, tmp_path):
    formation = write_formation(
        """\
        name: wide_snake
        friction: {lateral: 0.8, anisotropic: [0.01, 1.0, 0.01]}
        light: {distance_m: 50.0}
        units:
          - {name: u1, unit: servo}
          - {name: "u{i}", repeat: [2, 4], unit: servo, parent: "u{i-1}", connector: back,
             axis: yaw, levels_deg: {min: -30, max: 30, step: 10}}
        """
    )
    budget = tmp_path / "budget.yaml"  # a small population, short trials: nothing about timing
    budget.write_text(
        "agent: {genetic: {population: 4}}\nlocal_search: 1\ntask: {trial_steps: 4}\n"
    )
    run = tmp_path / "run"
    result = run_cli(
        "train", formation, "--sim", "memo", "--preset", "paper-snake", "--config", budget,
        "--generations", "1", "--trials", "5", "--workers", "1", "--out", run, "--quiet",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    summary = json.loads((run / "summary.json").read_text())
    assert summary["generations"] == 1 and math.isfinite(summary["distance_m"])


def test_resume_refuses_a_checkpoint_that_does_not_fit_the_configuration(tmp_path):
    run = tmp_path / "run"
    result = run_cli(
        "train", ASSEMBLIES_DIR / "quadruped.yaml", "--generations", "2", "--trials", "10",
        "--out", run, "--quiet",
    )  # fmt: skip
    assert result.returncode == 0
    (run / "summary.json").unlink()
    config = (run / "config.yaml").read_text()
    (run / "config.yaml").write_text(config.replace("population: 200", "population: 10"))
    resumed = run_cli("train", "--resume", run)
    assert resumed.returncode == 2 and "does not fit config.yaml" in resumed.stderr
    assert len(resumed.stderr.strip().splitlines()) == 1
