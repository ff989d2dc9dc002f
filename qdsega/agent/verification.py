"""What a learner on a transition table asks exact physics to play each generation: exploring
trials of its Q-table, the policy the table may underrate, the greedy policy, and a (1 + lambda)
local search around the best exact trial so far. The caller plays them and tells the answers."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from qdsega.agent.genetic import vary_gait
from qdsega.agent.grounding import GroundedTransitions
from qdsega.agent.learner import QDSEGA, Generation
from qdsega.agent.policy import BoltzmannPolicy, Policy, Rollout, SequencePolicy

_SEARCH_STREAM = 1_000_000
"""Local-search trials of generation ``g`` draw from a generator seeded ``(seed, g, this)``,
a stream no exploring trial uses."""


@dataclass(kw_only=True)
class Verification:
    """The exact trials of each generation, asked in two batches: :meth:`ask` (then the
    greedy replay is told), then :meth:`neighbours` of the best trial told so far.

    Attributes:
        explore_trials: trials of the generation's Q-table drawn at ``temperature`` (with a
            grounded table only: they are there to ground it where the learner may go next).
        temperature: the Boltzmann temperature exploring trials draw actions at.
        optimism: with a grounded table, the upper confidence bound (in RMS gaps) that one more
            trial's policy is learnt on; 0 for none.
        local_search: neighbours of the best trial so far (one character of one posture
            varied, or one joint's timing: :func:`qdsega.agent.genetic.vary_gait`); 0 for none.
        phase_moves: the share of those neighbours that shift one joint's timing.
        seed: exploring trial ``k`` of generation ``g`` draws from a generator seeded
            ``(seed, g, k)``, so a resumed run draws the same, whichever worker plays it.
    """

    explore_trials: int = 0
    temperature: float = 1.0
    optimism: float = 0.0
    local_search: int = 0
    phase_moves: float = 0.0
    seed: int = 0
    _best: tuple[np.ndarray, float] | None = field(default=None, init=False, repr=False)
    """The commands (k, J) and distance (m) of the best trial told so far: the search's parent."""

    def ask(
        self, learner: QDSEGA, generation: Generation, grounded: GroundedTransitions | None
    ) -> list[Policy]:
        """The generation's policies to play, the greedy one last; with a ``grounded`` table
        (the learner's model) the exploring trials and the hopeful policy come first."""
        if grounded is None:
            return [generation.policy]
        policies: list[Policy] = [
            BoltzmannPolicy(
                greedy=generation.policy,
                temperature=self.temperature,
                rng=np.random.default_rng([self.seed, generation.index, k]),
            )
            for k in range(self.explore_trials)
        ]
        if self.optimism > 0:
            space = generation.space
            upper = grounded.transitions(space.postures, space.actions, confidence=self.optimism)
            rng = np.random.default_rng([self.seed, generation.index, self.explore_trials])
            policies.append(learner.explore(generation, upper, rng))
        return [*policies, generation.policy]

    def neighbours(self, index: int, levels: np.ndarray) -> list[Policy]:
        """Generation ``index``'s local-search gaits around the best trial told so far,
        to play open loop (``levels``: each joint's level count)."""
        if self.local_search == 0 or self._best is None:
            return []
        rng = np.random.default_rng([self.seed, index, _SEARCH_STREAM])
        return [
            SequencePolicy(
                commands=vary_gait(self._best[0], levels, rng, phase_share=self.phase_moves)
            )
            for _ in range(self.local_search)
        ]

    def tell(self, trials: Sequence[Rollout]) -> None:
        """Keep the farthest of ``trials`` as the search's parent where it beats the last."""
        for trial in trials:
            if self._best is None or trial.distance_m > self._best[1]:
                self._best = (trial.postures.copy(), trial.distance_m)

    def state(self) -> dict[str, np.ndarray]:
        """The search's parent (``search_commands`` (k, J), ``search_distance_m`` (1,)), if any."""
        if self._best is None:
            return {}
        return {
            "search_commands": self._best[0],
            "search_distance_m": np.array([self._best[1]]),
        }

    def restore(self, state: dict[str, np.ndarray]) -> None:
        """Return to :meth:`state` (other keys are ignored)."""
        self._best = None
        if "search_commands" in state:
            commands = state["search_commands"].astype(np.int64)
            self._best = (commands, float(state["search_distance_m"][0]))
