"""Worlds as data: every shipped world loads and a body rests on it, the flat world is the plane
of old bit for bit, and a bad world file is one line with its file, line and key."""

from __future__ import annotations

import time
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from helpers import run_cli

from qdsega import ENV_ID
from qdsega.description import load_world, resolve_world, shipped_world_names
from qdsega.errors import WorldError
from qdsega.locomotion.env import LocomotionEnv, replay_postures
from qdsega.simulation.terrain import ground_height

GAIT = np.array([[0, 8, 0, 8], [8, 0, 8, 0]] * 3)
"""A few steps of snake5 that move it."""


def test_the_shipped_worlds_are_the_ones_the_docs_name():
    assert shipped_world_names() == [
        "corridor", "flat", "ice", "rubble", "slope", "stairs", "tunnel",
    ]  # fmt: skip


@pytest.mark.parametrize("name", shipped_world_names())
def test_every_shipped_world_loads_and_a_snake_rests_on_it(name):
    world = load_world(resolve_world(name))
    env = LocomotionEnv(formation="snake5", world=world)
    try:
        env.reset(seed=0)
        centres, _ = env.sim.unit_states()
        ground = ground_height(world, centres[:, 0], centres[:, 1])
        above = centres[:, 2] - ground
        assert np.all(above > 0.0) and np.all(above < 0.06), above  # on it, not in it
        replay = replay_postures(env, GAIT)
        assert replay.failure is None
    finally:
        env.close()


def test_the_flat_world_is_the_plane_every_run_had_before():
    plain = LocomotionEnv(formation="snake5")
    flat = LocomotionEnv(formation="snake5", world="flat")
    try:
        plain.reset(seed=0)
        flat.reset(seed=0)
        assert replay_postures(plain, GAIT) == replay_postures(flat, GAIT)
        assert np.array_equal(plain.sim.unit_states()[0], flat.sim.unit_states()[0])
    finally:
        plain.close()
        flat.close()


def test_a_world_changes_the_walk():
    distances = {}
    for name in ("flat", "ice", "stairs"):
        env = LocomotionEnv(formation="quadruped", world=name)
        try:
            env.reset(seed=0)
            distances[name] = replay_postures(env, np.zeros((4, 8), dtype=np.int64)).distance_m
        finally:
            env.close()
    assert len(set(distances.values())) > 1, distances


def test_a_worlds_light_replaces_the_formations(tmp_path):
    file = tmp_path / "lit.yaml"
    file.write_text("name: lit\nlight: {distance_m: 5, bearing_deg: 90}\n")
    env = LocomotionEnv(formation="snake5", world=file)
    try:
        assert env.formation.light.distance_m == 5.0
    finally:
        env.close()


def test_gym_make_takes_a_world_and_passes_check_env():
    env = gym.make(ENV_ID, formation="snake5", world="rubble")
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


BAD = [
    ("name: w\nground: {friction: .nan}\n", "w.yaml:2: ground.friction: expected a number"),
    ("name: w\nground: {slope: {angle_deg: 1.0e+9}}\n", "ground.slope.angle_deg: must be in"),
    ("name: w\ncolour: red\n", "w.yaml:2: colour: unknown key"),
    ("name: w\nboxes: [{xyz_m: [1, 0, 0], size_m: [1, 1]}]\n", "boxes[0].size_m: expected 3"),
    (
        "name: w\nground:\n  rough: {amplitude_m: 0.05, feature_m: 0.3, size_m: 90}\n",
        "w.yaml:3: ground.rough.size_m: heightfield too large",
    ),
    ("name: w\nstairs: {from_m: 1, rise_m: 0.05, run_m: 0.3, count: 100000}\n", "count"),
    ("name: w\nceiling: {height_m: 0.1, from_m: 3, to_m: 1}\n", "ceiling.to_m: must be beyond"),
]


@pytest.mark.parametrize(("text", "message"), BAD)
def test_a_bad_world_is_one_line_with_its_place_exit_2_and_nothing_written(tmp_path, text, message):
    (tmp_path / "w.yaml").write_text(text)
    (tmp_path / "wave.csv").write_text("0,8,0,8\n")
    start = time.perf_counter()
    result = run_cli(
        "render", "snake5", "--world", tmp_path / "w.yaml", "--postures", tmp_path / "wave.csv",
        "-o", tmp_path / "out.gif",
    )  # fmt: skip
    assert time.perf_counter() - start < 5.0
    assert result.returncode == 2 and message in result.stderr, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out.gif").exists()


def test_a_body_that_starts_inside_an_obstacle_is_refused(tmp_path):
    file = tmp_path / "w.yaml"
    file.write_text("name: w\nboxes: [{xyz_m: [0, 0, 0.05], size_m: [0.3, 0.3, 0.1]}]\n")
    with pytest.raises(WorldError, match="snake5 starts inside an obstacle of w"):
        LocomotionEnv(formation="snake5", world=file)


def test_an_unknown_world_name_lists_the_shipped_ones():
    with pytest.raises(WorldError, match="nor a shipped world \\(shipped: corridor, flat"):
        resolve_world("moon")


@pytest.mark.parametrize(
    ("name", "uniform", "plane"),
    [
        ("flat", True, True),
        ("ice", True, True),
        ("slope", False, True),
        ("stairs", False, False),
        ("tunnel", False, False),
        ("rubble", False, False),
    ],
)
def test_a_world_is_uniform_when_nothing_but_its_grip_differs_from_the_plane(name, uniform, plane):
    world = load_world(resolve_world(name))
    assert world.is_uniform is uniform and world.is_plane is plane


@pytest.mark.parametrize("name", ["posts", "cross_slope", "downhill"])
def test_the_worlds_of_the_experiments_load(name):
    file = Path(__file__).resolve().parents[2] / "experiments" / "worlds" / f"{name}.yaml"
    assert load_world(file).name == name
