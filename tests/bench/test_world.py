"""``qdsega bench --world``: the PyBullet tasks walk, and are judged, in the world named; flat
keeps every task as it was; a bad world is one line and nothing written."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
from helpers import run_cli

from qdsega.baselines.reference_search import SHIPPED_DIR, reference_key
from qdsega.bench import runner
from qdsega.bench.curve import Curve
from qdsega.bench.report import Provenance, write_report
from qdsega.bench.runs import BenchRun
from qdsega.bench.tasks import FULL, QUICK, in_world
from qdsega.description import World

SNAKE = next(task for task in QUICK if task.sim == "pybullet")


def test_flat_keeps_every_task_and_its_name():
    for tasks in (FULL, QUICK):
        assert in_world(tasks, "flat") == (tasks, ())
    flat = [task for task in FULL if task.world == "flat"]
    assert [task.name for task in flat] == [
        "legged12-msm", "snake5-pybullet", "quadruped-pybullet", "legged12-pybullet"
    ]  # fmt: skip
    assert all(task.exact_rules().world == World() for task in flat)  # no file: as before


def test_a_world_leaves_out_the_tasks_of_a_world_of_their_own():
    kept, left_out = in_world(FULL, "stairs")
    assert [task.name for task in left_out] == ["legged12-msm", "snake5-pybullet-rubble"]
    assert all(task.world == "stairs" for task in kept) and len(kept) == 3


def test_a_world_moves_the_pybullet_tasks_there_and_leaves_the_msm_out():
    kept, left_out = in_world(QUICK, "stairs")
    assert [task.name for task in kept] == ["snake5-pybullet-stairs"]
    assert [task.name for task in left_out] == ["legged12-msm"]
    rules = kept[0].exact_rules()
    assert rules.world.name == "stairs" and rules.world.stairs is not None
    assert rules.task == SNAKE.exact_rules().task  # the same preset, in another world


def test_a_world_file_gives_its_light_to_the_formation(tmp_path):
    file = tmp_path / "dim.yaml"
    file.write_text(
        "name: dim\nground: {friction: 0.5}\nlight: {distance_m: 50, bearing_deg: 90}\n"
    )
    (task,), _ = in_world(QUICK, str(file))
    assert task.name == "snake5-pybullet-dim"
    x, y = task.load().light.position_m
    assert math.isclose(x, 0.0, abs_tol=1e-9) and math.isclose(y, 50.0)
    assert tuple(task.rules().light) == pytest.approx((0.0, 50.0), abs=1e-9)


def test_the_arena_plays_in_the_tasks_world():
    (ice,), _ = in_world(QUICK, "ice")
    levels = [len(joint.levels_rad) for joint in SNAKE.load().joints]
    sequence = np.random.default_rng(0).integers(
        0, levels, size=(SNAKE.rules().trial_steps, len(levels))
    )
    distances = []
    for task in (SNAKE, ice):
        arena = task.arena()
        try:
            (replay,) = arena.replays([sequence])
        finally:
            arena.close()
        assert replay.failure is None
        distances.append(replay.distance_m)
    assert distances[1] < 0.8 * distances[0]  # the same gait slips on ice


def test_the_msm_refuses_a_world():
    msm = next(task for task in QUICK if task.sim == "msm")
    with pytest.raises(ValueError, match="the MSM knows no terrain"):
        type(msm)(**{**msm.__dict__, "world": "stairs"})


@pytest.mark.parametrize("world", ["nosuch", "missing.yaml"])
def test_a_bad_world_is_one_line_and_writes_nothing(world, tmp_path):
    out = tmp_path / "out"
    result = run_cli("bench", "--quick", "--world", world, "--out", out, cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.startswith("qdsega bench: error: ") and result.stderr.count("\n") == 1
    assert world in result.stderr and result.stdout == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(
    importlib.util.find_spec("stable_baselines3") is None, reason="needs qdsega[bench]"
)
def test_the_command_runs_the_world_tasks_and_says_so(tmp_path, monkeypatch):
    given = {}

    def run_bench(tasks, out, **kwargs):
        given.update(tasks=tasks, out=out, command=kwargs["command"])
        return out / "BENCHMARKS.md", []

    monkeypatch.setattr(runner, "run_bench", run_bench)
    result = run_cli("bench", "--quick", "--world", "stairs", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "legged12-msm left out: the MSM knows no terrain" in result.stdout
    assert [task.name for task in given["tasks"]] == ["snake5-pybullet-stairs"]
    assert given["out"] == Path("runs/bench-quick-stairs")  # not the flat report's folder
    assert given["command"] == "qdsega bench --quick --world stairs --out runs/bench-quick-stairs"


def test_the_report_names_each_tasks_world(tmp_path):
    (task,), _ = in_world(QUICK, "stairs")
    curve = Curve.of([(120, 0.1, 1.0), (360, 0.2, 2.0)])
    file = write_report(
        tasks=[task],
        curves={BenchRun(task, "qdsega", 0): curve},
        yardsticks={task.name: ("a yardstick", 0.4)},
        throughput=[],
        errors=[],
        provenance=Provenance(machine="m", date="d", commit="c", command="qdsega bench"),
        out=tmp_path,
    )
    assert "snake5 in the PyBullet world stairs (" in file.read_text()


@pytest.mark.parametrize("task", [t for t in FULL if t.sim == "pybullet"], ids=lambda t: t.name)
def test_every_full_pybullet_task_ships_its_yardstick(task):
    """A report of the full benchmark never waits on a reference search (rubble's took 25
    minutes): when this fails, run ``tools/reference_search.py FORMATION --world WORLD --ship``."""
    key = reference_key(task.load(), rules=task.exact_rules())
    assert (SHIPPED_DIR / f"{task.formation}-{key[:16]}.json").is_file(), task.name
