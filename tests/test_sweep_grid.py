"""A sweep grid is checked whole before anything runs: its worlds too, with their lines."""

from __future__ import annotations

import re

import pytest

from qdsega.errors import ConfigError
from qdsega.sweep import read_grid


def test_worlds_are_an_axis_of_the_grid(tmp_path):
    (tmp_path / "grid.yaml").write_text("formations: [snake5, quadruped]\nworlds: [flat, stairs]\n")
    runs = read_grid(tmp_path / "grid.yaml", tmp_path / "out")
    assert [r.name for r in runs] == [
        "snake5-flat-paper-snake-default-seed0",
        "snake5-stairs-paper-snake-default-seed0",
        "quadruped-flat-memo-legged-default-seed0",
        "quadruped-stairs-memo-legged-default-seed0",
    ]


@pytest.mark.parametrize(
    ("grid", "message"),
    [
        ("formations: [snake5]\nworlds: [flat, moon]\n", "grid.yaml:2: worlds[1]: moon: no such"),
        ("formations: [quadruped]\nsim: msm\nworlds: [stairs]\n", "the MSM knows no terrain"),
    ],
)
def test_a_bad_world_in_a_grid_is_refused_with_its_line(tmp_path, grid, message):
    (tmp_path / "grid.yaml").write_text(grid)
    with pytest.raises(ConfigError, match=re.escape(message)):
        read_grid(tmp_path / "grid.yaml", tmp_path / "out")
    assert not (tmp_path / "out").exists()
