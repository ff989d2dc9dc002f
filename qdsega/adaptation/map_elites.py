"""MAP-Elites over posture cycles, ask/tell: the caller plays the gaits it is asked to and
tells what they did; nothing here runs a simulator.

The first ``initial`` gaits are random cycles (2 to ``max_cycle`` postures, every joint at a
random level); after that each gait is a neighbour of an elite drawn uniformly from the
archive (:func:`qdsega.agent.genetic.vary_gait`: one character of one posture moved, or one
joint's commands shifted a step in time), or, a quarter of the time, the elite with one posture
added or removed, so that cycles of every length compete.
"""

from __future__ import annotations

import numpy as np

from qdsega.adaptation.archive import Archive
from qdsega.agent.genetic import vary_gait

RESIZE_SHARE = 0.25
"""The share of variations that add or remove a posture instead (-)."""
PHASE_SHARE = 0.25
"""The share of the other variations that shift one joint's commands in time (-)."""


class MapElites:
    """Proposes gaits and keeps the best of each cell of ``archive``.

    Args:
        archive: where elites go (filled in place).
        levels: each joint's level count (J,).
        rng: the only source of randomness.
        initial: random gaits before variation starts.
    """

    def __init__(
        self, *, archive: Archive, levels: np.ndarray, rng: np.random.Generator, initial: int
    ) -> None:
        self.levels = np.asarray(levels, dtype=np.int64)
        if self.levels.shape != archive.gaits.shape[2:] or np.any(self.levels < 1):
            raise ValueError(f"levels {self.levels} do not fit the archive's joints")
        if initial < 1:
            raise ValueError(f"initial must be at least 1, got {initial}")
        self.archive = archive
        self.rng = rng
        self.initial = initial
        self.told = 0
        """Gaits told so far."""

    @property
    def max_cycle(self) -> int:
        return self.archive.gaits.shape[1]

    def ask(self, count: int) -> list[np.ndarray]:
        """``count`` gaits (k, J) to play: random ones while fewer than ``initial`` were told or
        the archive is empty, else variations of its elites."""
        gaits = []
        for index in range(count):
            if self.told + index < self.initial or not len(self.archive.filled):
                gaits.append(self._random())
            else:
                parent = self.archive.gait(int(self.rng.choice(self.archive.filled)))
                gaits.append(self._vary(parent))
        return gaits

    def tell(self, gaits: list[np.ndarray], descriptors: np.ndarray, fitness: np.ndarray) -> int:
        """What the gaits did: descriptors (n, D) and fitness (n,) (m; NaN for a gait that
        failed, which is not kept); returns how many became elites."""
        if len(descriptors) != len(gaits) or len(fitness) != len(gaits):
            raise ValueError("one descriptor and one fitness per gait")
        kept = sum(
            self.archive.insert(g, d, float(f))
            for g, d, f in zip(gaits, descriptors, fitness, strict=True)
            if np.isfinite(f)
        )
        self.told += len(gaits)
        return kept

    def _random(self) -> np.ndarray:
        length = int(self.rng.integers(2, self.max_cycle + 1))
        return self.rng.integers(0, self.levels, size=(length, len(self.levels)))

    def _vary(self, parent: np.ndarray) -> np.ndarray:
        if self.rng.random() < RESIZE_SHARE:
            if len(parent) < self.max_cycle and (len(parent) <= 2 or self.rng.random() < 0.5):
                at = int(self.rng.integers(len(parent) + 1))
                posture = parent[int(self.rng.integers(len(parent)))]
                return np.insert(parent, at, posture, axis=0)
            if len(parent) > 2:
                return np.delete(parent, int(self.rng.integers(len(parent))), axis=0)
        if np.all(self.levels <= 1):
            return parent.copy()
        return vary_gait(parent, self.levels, self.rng, phase_share=PHASE_SHARE)
