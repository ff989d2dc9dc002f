"""A repertoire's results for reuse: the QD-score by hand, and the elites' CSV read back as the
archive holds them."""

import csv

import numpy as np
import pytest

from qdsega.adaptation.archive import QD_OFFSET_M, Archive, grid_centroids
from qdsega.adaptation.repertoire import archive_summary, write_elites


def _three_elites() -> Archive:
    archive = Archive.empty(grid_centroids(2, 2), max_cycle=3, n_joints=2)
    archive.insert(np.array([[0, 1], [2, 0]]), np.array([0.1, 0.2]), 0.5)  # cell 0
    archive.insert(np.array([[1, 1]]), np.array([0.2, 0.9]), -0.25)  # cell 1: walked away
    archive.insert(np.array([[2, 2], [0, 0], [1, 2]]), np.array([0.8, 0.7]), 1.0 / 3.0)  # cell 3
    return archive


def test_the_qd_score_sums_each_elites_distance_above_the_offset():
    archive = _three_elites()
    assert QD_OFFSET_M == -10.0
    assert archive.qd_score == pytest.approx((0.5 + 10) + (-0.25 + 10) + (1 / 3 + 10))
    summary = archive_summary(archive)
    assert summary["qd_score"] == archive.qd_score and summary["qd_offset_m"] == QD_OFFSET_M
    assert summary["filled"] == 3 and summary["coverage"] == 0.75 and summary["best_m"] == 0.5
    archive.insert(np.array([[0, 0]]), np.array([0.9, 0.1]), -12.0)  # beyond the offset: 0
    assert archive.qd_score == pytest.approx(30.0 + 0.5 - 0.25 + 1 / 3)
    empty = Archive.empty(grid_centroids(2, 2), max_cycle=3, n_joints=2)
    assert empty.qd_score == 0.0 and archive_summary(empty)["best_m"] is None


def test_the_elites_csv_reads_back_as_the_archive_holds_them(tmp_path):
    archive = _three_elites()
    path = tmp_path / "elites.csv"
    write_elites(archive, {"descriptor_names": ["turn", "drift"]}, path)
    with path.open(newline="") as stream:
        rows = list(csv.DictReader(stream))
    assert list(rows[0]) == [
        "cell", "distance_m", "descriptor_turn", "descriptor_drift", "postures", "gait",
    ]  # fmt: skip
    assert [int(row["cell"]) for row in rows] == [0, 3, 1]  # the farthest first
    for row in rows:
        cell = int(row["cell"])
        gait = [[int(level) for level in posture.split()] for posture in row["gait"].split(";")]
        assert gait == archive.gait(cell).tolist() and int(row["postures"]) == len(gait)
        assert float(row["distance_m"]) == archive.fitness[cell]  # exactly: full precision
        read = [float(row["descriptor_turn"]), float(row["descriptor_drift"])]
        assert read == archive.descriptors[cell].tolist()
