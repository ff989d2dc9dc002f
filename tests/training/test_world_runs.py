"""Runs in a world: the run folder keeps its own copy of the world file (and its hash), every
reader takes the world from there, the flat world trains as the plane of old, and a reference
gait's cache key names the world."""

from __future__ import annotations

import csv
import json
import shutil

import pytest
import yaml
from helpers import TINY_TRAINING, run_cli

from qdsega.baselines.reference_search import reference_key
from qdsega.description import load_formation, load_world, resolve_formation, resolve_world
from qdsega.locomotion.rules import ExactRules
from qdsega.training.config import resolve_config
from qdsega.training.formation_copy import FormationSnapshot, copy_world, load_run_world

SNAKE = load_formation(resolve_formation("snake5"))


def _train(tmp_path, out, *extra):
    (tmp_path / "tiny.yaml").write_text(TINY_TRAINING)
    return run_cli(
        "train", "snake5", "--sim", "memo", "--generations", "1",
        "--config", tmp_path / "tiny.yaml", "--out", out, "--quiet", *extra,
    )  # fmt: skip


def _metrics(run):
    with (run / "metrics.csv").open() as file:
        return [{k: v for k, v in row.items() if k != "wall_s"} for row in csv.DictReader(file)]


def test_the_cache_key_of_a_reference_names_the_world_but_not_its_name():
    flat = reference_key(SNAKE, rules=ExactRules())
    named = ExactRules(world=load_world(resolve_world("flat")))
    assert reference_key(SNAKE, rules=named) == flat
    stairs = ExactRules(world=load_world(resolve_world("stairs")))
    assert reference_key(SNAKE, rules=stairs) != flat


def test_the_msm_refuses_a_world_before_anything_is_written(tmp_path):
    result = run_cli(
        "train", "quadruped", "--sim", "msm", "--world", "stairs", "--out", tmp_path / "run"
    )
    assert result.returncode == 2 and "the MSM knows no terrain" in result.stderr
    assert not (tmp_path / "run").exists()


@pytest.mark.slow
def test_the_flat_world_trains_as_the_plane_of_old(tiny_run, tmp_path):
    assert _train(tmp_path, tmp_path / "flat", "--world", "flat").returncode == 0
    assert _metrics(tiny_run) == _metrics(tmp_path / "flat")  # the same run without --world


@pytest.mark.slow
def test_a_run_keeps_its_world_and_reads_it_from_its_copy(tmp_path):
    world = tmp_path / "hill.yaml"
    world.write_text("name: hill\nground: {slope: {angle_deg: 4}}\nlight: {distance_m: 20}\n")
    run = tmp_path / "run"
    assert _train(tmp_path, run, "--world", world).returncode == 0
    summary = json.loads((run / "summary.json").read_text())
    assert summary["world"] == "hill" and len(summary["world_sha256"]) == 64
    assert (run / "world.yaml").read_text() == world.read_text()
    assert summary["light_xy"] == [20.0, 0.0]  # the world's light
    assert summary["memo_spots"] == 1  # a slope is the same plane wherever the body stands
    moved = tmp_path / "moved"
    shutil.copytree(run, moved)
    world.unlink()  # the run needs its copy only
    assert load_run_world(moved).name == "hill"
    evaluated = run_cli("evaluate", moved, "--reference-trials", "0")
    assert evaluated.returncode == 0, evaluated.stderr
    evaluation = json.loads((moved / "evaluation.json").read_text())
    assert evaluation["distance_m"] == pytest.approx(summary["distance_m"], abs=1e-9)
    assert run_cli("report", moved).returncode == 0
    assert "qdsega run: snake5 in hill (memo" in (moved / "report.html").read_text()


def test_a_body_that_would_start_inside_an_obstacle_is_refused_before_anything_is_written(
    tmp_path,
):
    out = tmp_path / "run"
    result = run_cli("train", "quadruped", "--sim", "memo", "--world", "corridor", "--out", out)
    assert result.returncode == 2 and len(result.stderr.splitlines()) == 1, result.stderr
    assert "corridor.yaml: quadruped starts inside an obstacle of corridor" in result.stderr
    assert not out.exists()


def test_a_run_folder_whose_body_cannot_start_is_refused_on_resume(tmp_path):
    out = tmp_path / "run"  # written as train did before it checked the start
    out.mkdir()
    config = resolve_config(overrides={"sim": "memo"})
    (out / "config.yaml").write_text(yaml.safe_dump(config.to_dict(), sort_keys=False))
    FormationSnapshot.of(load_formation(resolve_formation("quadruped"))).write(out)
    copy_world(load_world(resolve_world("corridor")), out)
    before = sorted(out.rglob("*"))
    result = run_cli("train", "--resume", out)
    assert result.returncode == 2 and len(result.stderr.splitlines()) == 1, result.stderr
    assert "quadruped starts inside an obstacle of corridor" in result.stderr
    assert sorted(out.rglob("*")) == before
