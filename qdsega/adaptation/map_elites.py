"""MAP-Elites over posture cycles, ask/tell: the caller plays the gaits it is asked to and
tells what they did; nothing here runs a simulator.

The first gaits are the ``seeds`` (a finished run's verified gaits, where one is given), then
``initial`` random cycles (2 to ``cycle`` postures, every joint at a random level); after that
each gait is a neighbour of an elite drawn uniformly from the archive
(:func:`qdsega.agent.genetic.vary_gait`: one character of one posture moved, or one joint's
commands shifted a step in time), or, a quarter of the time, the elite with one posture added
or removed, so that cycles of every length compete.
"""

from __future__ import annotations

from collections.abc import Sequence

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
        cycle: the longest random cycle (default: the archive's longest gait).
        seeds: gaits (k, J) played first, as they are.
    """

    def __init__(
        self,
        *,
        archive: Archive,
        levels: np.ndarray,
        rng: np.random.Generator,
        initial: int,
        cycle: int | None = None,
        seeds: Sequence[np.ndarray] = (),
    ) -> None:
        self.levels = np.asarray(levels, dtype=np.int64)
        if self.levels.shape != archive.gaits.shape[2:] or np.any(self.levels < 1):
            raise ValueError(f"levels {self.levels} do not fit the archive's joints")
        if initial < 1:
            raise ValueError(f"initial must be at least 1, got {initial}")
        self.cycle = archive.gaits.shape[1] if cycle is None else cycle
        if not 2 <= self.cycle <= archive.gaits.shape[1]:
            raise ValueError(f"cycle must be 2..{archive.gaits.shape[1]}, got {self.cycle}")
        self.seeds = [np.asarray(g, dtype=np.int64) for g in seeds]
        for gait in self.seeds:
            if gait.ndim != 2 or not 1 <= len(gait) <= archive.gaits.shape[1]:
                raise ValueError(f"a seed is (1..{archive.gaits.shape[1]}, J), got {gait.shape}")
            if gait.shape[1] != len(self.levels) or np.any((gait < 0) | (gait >= self.levels)):
                raise ValueError("a seed's postures do not fit the body's levels")
        self.archive = archive
        self.rng = rng
        self.initial = initial
        self.told = 0
        """Gaits told so far."""

    @property
    def max_cycle(self) -> int:
        return self.archive.gaits.shape[1]

    def ask(self, count: int) -> list[np.ndarray]:
        """``count`` gaits (k, J) to play: the seeds not yet played, then random ones while fewer
        than ``initial`` were told after them or the archive is empty, else variations of its
        elites."""
        gaits = []
        for index in range(count):
            told = self.told + index
            if told < len(self.seeds):
                gaits.append(self.seeds[told].copy())
            elif told < len(self.seeds) + self.initial or not len(self.archive.filled):
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
        length = int(self.rng.integers(2, self.cycle + 1))
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
