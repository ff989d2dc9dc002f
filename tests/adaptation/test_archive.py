"""The MAP-Elites archive keeps the better elite per cell, places a descriptor in its nearest
cell, and round-trips through its arrays; a corrupt archive is refused."""

import numpy as np
import pytest

from qdsega.adaptation.archive import Archive, cvt_centroids, grid_centroids


def _archive(cells_per_dim: int = 2) -> Archive:
    return Archive.empty(grid_centroids(2, cells_per_dim), max_cycle=3, n_joints=2)


def test_a_grid_has_its_cells_centres():
    centres = grid_centroids(2, 2)
    assert centres.tolist() == [[0.25, 0.25], [0.25, 0.75], [0.75, 0.25], [0.75, 0.75]]


def test_insertion_keeps_the_better_elite_of_each_cell():
    archive = _archive()
    slow, fast = np.array([[0, 1]]), np.array([[1, 0], [0, 1]])
    assert archive.insert(slow, np.array([0.1, 0.1]), 0.5)
    assert not archive.insert(fast, np.array([0.2, 0.3]), 0.4)  # same cell, worse
    assert not archive.insert(fast, np.array([0.2, 0.3]), 0.5)  # equal: the first stays
    assert archive.gait(0).tolist() == [[0, 1]]
    assert archive.insert(fast, np.array([0.2, 0.3]), 0.9)
    assert archive.gait(0).tolist() == [[1, 0], [0, 1]] and archive.fitness[0] == 0.9
    assert archive.insert(slow, np.array([0.9, 0.9]), -0.1)  # another cell, empty before
    assert archive.filled.tolist() == [0, 3] and archive.coverage == 0.5
    assert archive.best() == 0


def test_a_descriptor_outside_the_cube_counts_at_its_edge():
    archive = _archive()
    assert archive.cell_of(np.array([-3.0, 7.0])) == 1


def test_bad_gaits_are_refused():
    archive = _archive()
    with pytest.raises(ValueError, match="postures"):
        archive.insert(np.zeros((4, 2)), np.array([0.5, 0.5]), 1.0)  # longer than max_cycle
    with pytest.raises(ValueError, match="joints"):
        archive.insert(np.zeros((1, 3)), np.array([0.5, 0.5]), 1.0)
    with pytest.raises(ValueError, match="finite"):
        archive.insert(np.zeros((1, 2)), np.array([0.5, 0.5]), float("nan"))


def test_the_archive_round_trips_and_a_corrupt_one_is_refused():
    archive = _archive()
    archive.insert(np.array([[1, 1], [0, 0]]), np.array([0.6, 0.2]), 1.5)
    again = Archive.from_state(archive.state())
    assert again.gait(2).tolist() == [[1, 1], [0, 0]] and np.array_equal(
        again.fitness, archive.fitness, equal_nan=True
    )
    broken = archive.state()
    broken["fitness"] = broken["fitness"][:2]
    with pytest.raises(ValueError, match="not an archive: fitness"):
        Archive.from_state(broken)
    with pytest.raises(ValueError, match="not an archive: no gaits"):
        Archive.from_state({k: v for k, v in archive.state().items() if k != "gaits"})


def test_a_cvt_spreads_its_cells_and_depends_on_the_seed_alone():
    first = cvt_centroids(3, 20, np.random.default_rng(1))
    assert np.array_equal(first, cvt_centroids(3, 20, np.random.default_rng(1)))
    assert first.shape == (20, 3) and np.all((first >= 0) & (first <= 1))
    gaps = np.linalg.norm(first[:, None] - first[None], axis=2) + np.eye(20)
    assert gaps.min() > 0.1  # no two cells on top of each other
