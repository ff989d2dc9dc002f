"""How hard a reform looks: apart from the search, so that the command line offers its
defaults without loading it."""

from __future__ import annotations

from dataclasses import dataclass

from qdsega.errors import ConfigError
from qdsega.training.config import SCREENING_GENERATIONS


@dataclass(frozen=True, kw_only=True)
class ReformSettings:
    """How hard a reform looks, and whether it lets blocked levels through.

    Attributes:
        seed: every run's seed.
        screen: generations each candidate learns before they are ranked.
        rounds: rounds of moves; each after the first moves on from the ``widen`` best.
        widen: candidates each later round moves on from.
        top: candidates learnt to the end besides the body as it is.
        reference_trials: the CMA-ES reference search of each learnt run's evaluation
            (``qdsega evaluate --reference-trials``; 0: the classic gaits only).
        allow_blocked: a body with a level a joint cannot reach without hitting itself goes
            on, the body as it is with a warning, instead of being refused or dropped
            (:func:`qdsega.simulation.reach.check_reach`).
    """

    seed: int = 0
    screen: int = SCREENING_GENERATIONS
    rounds: int = 2
    widen: int = 2
    top: int = 3
    reference_trials: int = 0
    allow_blocked: bool = False

    def __post_init__(self) -> None:
        for name in ("screen", "rounds", "widen", "top"):
            if getattr(self, name) < 1:
                raise ConfigError(f"{name} must be at least 1, got {getattr(self, name)}")
        if self.reference_trials < 0:
            raise ConfigError(f"reference_trials must be 0 or more, got {self.reference_trials}")
