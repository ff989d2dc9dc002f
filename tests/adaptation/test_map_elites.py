"""MAP-Elites asks for random cycles first, then for neighbours of the elites it was told of."""

import numpy as np
import pytest

from qdsega.adaptation.archive import Archive, grid_centroids
from qdsega.adaptation.map_elites import MapElites

LEVELS = np.array([3, 3, 2])


def _search(seed: int) -> MapElites:
    archive = Archive.empty(grid_centroids(2, 2), max_cycle=4, n_joints=3)
    return MapElites(archive=archive, levels=LEVELS, rng=np.random.default_rng(seed), initial=2)


def test_random_cycles_first_then_neighbours_of_elites():
    search = _search(0)
    first = search.ask(2)
    assert all(2 <= len(g) <= 4 and np.all((g >= 0) & (g < LEVELS)) for g in first)
    kept = search.tell(first, np.array([[0.1, 0.1], [0.9, 0.9]]), np.array([1.0, np.nan]))
    assert kept == 1 and search.told == 2  # the failed gait counts, and is not kept
    parent = search.archive.gait(0)
    for child in search.ask(20):
        if len(child) == len(parent):  # one posture's character, or one joint's timing
            changed = np.argwhere(child != parent)
            assert len(np.unique(changed[:, 1])) <= 1
        else:  # one posture added or removed
            assert abs(len(child) - len(parent)) == 1 and 2 <= len(child) <= 4


def test_the_same_seed_asks_for_the_same_gaits():
    a, b = _search(3), _search(3)
    for search in (a, b):
        search.tell(search.ask(2), np.array([[0.2, 0.2], [0.7, 0.7]]), np.array([1.0, 2.0]))
    assert all(np.array_equal(x, y) for x, y in zip(a.ask(5), b.ask(5), strict=True))


def test_seeds_are_played_first_as_they_are_and_draw_nothing():
    def search(seeds: list[np.ndarray]) -> MapElites:
        archive = Archive.empty(grid_centroids(2, 2), max_cycle=5, n_joints=3)
        return MapElites(archive=archive, levels=LEVELS, rng=np.random.default_rng(3),
                         initial=2, cycle=3, seeds=seeds)  # fmt: skip

    seed = np.array([[0, 1, 0], [2, 2, 1], [1, 0, 1], [0, 0, 0], [2, 1, 0]])
    first, *randoms = search([seed]).ask(3)
    assert np.array_equal(first, seed)
    plain = search([]).ask(2)  # the random gaits after it are those of an unseeded search
    assert all(np.array_equal(a, b) for a, b in zip(randoms, plain, strict=True))
    assert all(len(g) <= 3 for g in randoms)  # random cycles keep their own bound
    with pytest.raises(ValueError, match="levels"):
        search([seed + 2])
