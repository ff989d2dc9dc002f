"""Which body for which world: the matrix from a sweep's rows, the best body of each world,
and qdsega match end to end on a tiny budget."""

from __future__ import annotations

import base64

import imageio.v3 as iio
import pytest
from helpers import TINY_TRAINING, run_cli

from qdsega.match import Cell, best_bodies, matrix, write_matrix


def _row(formation, world, seed, distance, status="ok", error=None):
    return {
        "run": f"{formation}-{world}-seed{seed}", "formation": formation, "world": world,
        "status": status, "distance_m": distance, "ratio": None if distance is None else distance,
        "error": error,
    }  # fmt: skip


def test_a_cell_is_the_median_of_its_seeds_and_a_failed_cell_keeps_its_reason():
    rows = [
        _row("snake", "flat", 0, 1.0), _row("snake", "flat", 1, 3.0), _row("snake", "flat", 2, 2.0),
        _row("legs", "flat", 0, 2.5),
        _row("legs", "corridor", 0, None, "failed", "train: legs starts inside an obstacle"),
        _row("snake", "corridor", 0, 0.4),
    ]  # fmt: skip
    cells = matrix(rows)
    assert cells["snake", "flat"] == Cell(2.0, 2.0, "snake-flat-seed2", None)
    assert cells["legs", "corridor"].distance_m is None
    assert "inside an obstacle" in cells["legs", "corridor"].error
    assert best_bodies(cells) == {"flat": "legs", "corridor": "snake"}


def test_a_cell_keeps_its_worst_prediction_and_the_table_counts_the_cells_that_held(tmp_path):
    rows = [
        {**_row("snake", "flat", 0, 1.0), "memo_prediction_m": 1.05},
        {**_row("snake", "flat", 1, 2.0), "memo_prediction_m": 1.6},
        {**_row("legs", "flat", 0, 2.0), "memo_prediction_m": 2.0},
        {**_row("legs", "stairs", 0, 0.0), "memo_prediction_m": 0.3},  # 0 m: no relative error
    ]
    cells = matrix(rows)
    assert cells["snake", "flat"].prediction_error == pytest.approx(-0.2)
    assert cells["legs", "stairs"].prediction_error is None
    markdown, _, _ = write_matrix(cells, ["snake", "legs"], ["flat", "stairs"], tmp_path, {})
    text = markdown.read_text()
    assert "within 10% in 1 of 2 cells" in text and "| snake | -20% |" in text


@pytest.mark.slow
def test_match_writes_the_matrix_the_best_bodies_and_a_page_with_stills(tmp_path):
    tiny = TINY_TRAINING.replace("{population: 6}", "{population: 6, generations: 1}")
    (tmp_path / "tiny.yaml").write_text(tiny)
    out = tmp_path / "m"
    result = run_cli(
        "match", "quadruped", "--world", "flat", "corridor",
        "--config", tmp_path / "tiny.yaml", "--reference-trials", "0", "--out", out,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "flat: quadruped" in result.stdout
    assert "corridor: no body moved" in result.stdout  # it cannot start between the walls
    table = (out / "match.md").read_text()
    assert "| quadruped |" in table and "cannot start" in table
    page = (out / "match.html").read_text()
    assert page.count("data:image/png;base64,") == 2  # one still and the heatmap
    still = page.split("data:image/png;base64,")[1].split('"')[0]
    assert iio.imread(base64.b64decode(still)).shape[:2] == (480, 640)  # the usual picture size
    assert (out / "match.png").stat().st_size > 5000
