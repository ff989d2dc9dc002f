"""A MAP-Elites archive: the best gait found in each cell of a behaviour space.

The behaviour space is the unit cube ``[0, 1]^D`` of a gait's descriptor
(:mod:`qdsega.adaptation.descriptor`). Its cells are the Voronoi regions of ``centroids``: a
regular grid's cell centres where ``cells_per_dim ** D`` stays small, else a centroidal Voronoi
tessellation (CVT, Vassiliades et al. 2018) of as many cells as asked, found by Lloyd's
algorithm on uniform samples. A small archive in numpy, not pyribs: the archive must hold
posture cycles of any length as arrays, save to one ``.npz`` for a resumable build, and keep
the core dependencies as they are; the few lines of Lloyd's algorithm are all of pyribs it
would use.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

CVT_SAMPLES_PER_CELL = 50
"""Uniform samples Lloyd's algorithm places per cell (-)."""
CVT_ITERATIONS = 30
"""Lloyd iterations of a CVT (-): the centroids move less than a cell's width by then."""
NEAREST_BLOCK = 8192
"""Points whose nearest centroid is found at once (-)."""
QD_OFFSET_M = -10.0
"""The offset subtracted from every elite's distance in the QD-score (m), pyribs'
``qd_score_offset``: a distance can be negative, and 10 m back is beyond the farthest any body
here went in a 30-command trial (snake10's 5.96 m, docs/notes/2026-12-01-agent-designs.md), so
every term is positive and the score only grows as MAP-Elites fills or improves a cell."""


def grid_centroids(dims: int, cells_per_dim: int) -> np.ndarray:
    """The centres of a regular grid over ``[0, 1]^dims``, shape (cells_per_dim ** dims, dims)."""
    if dims < 1 or cells_per_dim < 1:
        raise ValueError(f"need dims >= 1 and cells_per_dim >= 1, got {dims}, {cells_per_dim}")
    centres = (np.arange(cells_per_dim) + 0.5) / cells_per_dim
    return np.array(list(itertools.product(centres, repeat=dims)), dtype=np.float64)


def cvt_centroids(dims: int, cells: int, rng: np.random.Generator) -> np.ndarray:
    """``cells`` centroids of a centroidal Voronoi tessellation of ``[0, 1]^dims`` (cells, dims):
    Lloyd's algorithm on ``CVT_SAMPLES_PER_CELL`` uniform samples per cell."""
    if dims < 1 or cells < 1:
        raise ValueError(f"need dims >= 1 and cells >= 1, got {dims}, {cells}")
    samples = rng.random((cells * CVT_SAMPLES_PER_CELL, dims))
    centroids = samples[rng.choice(len(samples), size=cells, replace=False)].copy()
    for _ in range(CVT_ITERATIONS):
        nearest = _nearest(centroids, samples)
        counts = np.bincount(nearest, minlength=cells)
        sums = np.stack(
            [np.bincount(nearest, weights=samples[:, d], minlength=cells) for d in range(dims)],
            axis=1,
        )
        kept = counts > 0
        centroids[kept] = sums[kept] / counts[kept, None]
    return centroids


def _nearest(centroids: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The index of the nearest centroid to each point (n,), in blocks of points so that a
    large archive's distances need little memory."""
    nearest = np.empty(len(points), dtype=np.int64)
    squared_centroids = np.sum(centroids**2, axis=1)[None, :]
    for start in range(0, len(points), NEAREST_BLOCK):
        block = points[start : start + NEAREST_BLOCK]
        squared = squared_centroids - 2.0 * block @ centroids.T  # + |point|^2: the same argmin
        nearest[start : start + NEAREST_BLOCK] = np.argmin(squared, axis=1)
    return nearest


@dataclass
class Archive:
    """Elites by cell: each cell's best gait so far, its descriptor and fitness.

    Attributes:
        centroids: the cells' centres in ``[0, 1]^D``, shape (C, D).
        fitness: each cell's elite's fitness (m; NaN where the cell is empty), shape (C,).
        descriptors: each elite's descriptor, shape (C, D).
        gaits: each elite's posture cycle, level indices padded with -1, shape (C, L, J).
        lengths: each elite's cycle length (0 where empty), shape (C,).
    """

    centroids: np.ndarray
    fitness: np.ndarray
    descriptors: np.ndarray
    gaits: np.ndarray
    lengths: np.ndarray

    @classmethod
    def empty(cls, centroids: np.ndarray, *, max_cycle: int, n_joints: int) -> Archive:
        """An archive over ``centroids`` (C, D) for cycles of at most ``max_cycle`` postures of
        ``n_joints`` joints."""
        centroids = np.asarray(centroids, dtype=np.float64)
        if centroids.ndim != 2 or len(centroids) == 0:
            raise ValueError(f"centroids must be (C >= 1, D), got {centroids.shape}")
        if max_cycle < 1 or n_joints < 1:
            raise ValueError(f"need max_cycle >= 1 and n_joints >= 1, got {max_cycle}, {n_joints}")
        cells, dims = centroids.shape
        return cls(
            centroids=centroids,
            fitness=np.full(cells, np.nan),
            descriptors=np.zeros((cells, dims)),
            gaits=np.full((cells, max_cycle, n_joints), -1, dtype=np.int64),
            lengths=np.zeros(cells, dtype=np.int64),
        )

    @property
    def filled(self) -> np.ndarray:
        """The indices of the cells that hold an elite."""
        return np.flatnonzero(~np.isnan(self.fitness))

    @property
    def coverage(self) -> float:
        """The share of cells that hold an elite."""
        return len(self.filled) / len(self.centroids)

    def cell_of(self, descriptor: np.ndarray) -> int:
        """The cell a descriptor (D,) falls in."""
        point = np.clip(np.asarray(descriptor, dtype=np.float64), 0.0, 1.0)
        if point.shape != self.centroids.shape[1:]:
            raise ValueError(f"descriptor must be ({self.centroids.shape[1]},), got {point.shape}")
        return int(_nearest(self.centroids, point[None])[0])

    def insert(self, gait: np.ndarray, descriptor: np.ndarray, fitness: float) -> bool:
        """Keep ``gait`` (k, J) as its cell's elite if the cell is empty or it is strictly
        better; returns whether it was kept."""
        gait = np.asarray(gait, dtype=np.int64)
        if gait.ndim != 2 or not 1 <= len(gait) <= self.gaits.shape[1]:
            raise ValueError(f"a gait is (1..{self.gaits.shape[1]}, J) postures, got {gait.shape}")
        if gait.shape[1] != self.gaits.shape[2]:
            raise ValueError(f"a gait needs {self.gaits.shape[2]} joints, got {gait.shape[1]}")
        if not np.isfinite(fitness):
            raise ValueError(f"fitness must be finite, got {fitness}")
        cell = self.cell_of(descriptor)
        if not np.isnan(self.fitness[cell]) and fitness <= self.fitness[cell]:
            return False
        self.fitness[cell] = fitness
        self.descriptors[cell] = np.clip(descriptor, 0.0, 1.0)
        self.gaits[cell] = -1
        self.gaits[cell, : len(gait)] = gait
        self.lengths[cell] = len(gait)
        return True

    @property
    def qd_score(self) -> float:
        """The QD-score: the sum over elites of their distance minus :data:`QD_OFFSET_M`, a
        term clipped at zero (an elite beyond the offset counts as an empty cell)."""
        return float(np.sum(np.maximum(self.fitness[self.filled] - QD_OFFSET_M, 0.0)))

    def gait(self, cell: int) -> np.ndarray:
        """The elite posture cycle of ``cell`` (k, J)."""
        if np.isnan(self.fitness[cell]):
            raise ValueError(f"cell {cell} is empty")
        return self.gaits[cell, : self.lengths[cell]].copy()

    def best(self) -> int:
        """The cell of the fittest elite."""
        if not len(self.filled):
            raise ValueError("the archive is empty")
        return int(self.filled[np.argmax(self.fitness[self.filled])])

    def state(self) -> dict[str, np.ndarray]:
        """The archive as arrays (for ``np.savez``)."""
        return {
            "centroids": self.centroids,
            "fitness": self.fitness,
            "descriptors": self.descriptors,
            "gaits": self.gaits,
            "lengths": self.lengths,
        }

    @classmethod
    def from_state(cls, state: dict[str, np.ndarray]) -> Archive:
        """The archive :meth:`state` gave.

        Raises:
            ValueError: arrays missing or of shapes that do not fit together.
        """
        try:
            archive = cls(**{k: np.array(state[k]) for k in cls.__dataclass_fields__})
        except KeyError as exc:
            raise ValueError(f"not an archive: no {exc.args[0]}") from None
        cells, dims = np.shape(archive.centroids)
        shapes = {
            "fitness": (cells,),
            "descriptors": (cells, dims),
            "lengths": (cells,),
        }
        for name, shape in shapes.items():
            if np.shape(getattr(archive, name)) != shape:
                raise ValueError(f"not an archive: {name} is {np.shape(getattr(archive, name))}")
        if np.ndim(archive.gaits) != 3 or len(archive.gaits) != cells:
            raise ValueError(f"not an archive: gaits is {np.shape(archive.gaits)}")
        if np.any(archive.lengths < 0) or np.any(archive.lengths > archive.gaits.shape[1]):
            raise ValueError("not an archive: cycle lengths out of range")
        return archive
