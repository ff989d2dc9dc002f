"""Every hyperparameter of QDSEGA, in one typed configuration, and the paper's presets.

Values the paper gives (section 4) are marked "paper"; the others are choices it leaves open,
each explained in the field's documentation and in docs/algorithm.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Literal

from qdsega.task import TaskConfig

CrossoverKind = Literal["uniform", "one-point"]
SelectionKind = Literal["individuals", "actions"]


@dataclass(frozen=True)
class LearningConfig:
    """Learning dynamics: Q-learning (eq. 1) with Boltzmann roulette selection (eq. 18).

    Attributes:
        trials: trials per generation (paper: 10000 legged, 1000 snake).
        alpha: learning rate of eq. (1) (paper: 0.5).
        gamma: discount rate of eq. (1) (paper: 0.9).
        temperature_scale: the 150.0 of eq. (18) (paper).
        temperature_rate: the 0.002 of eq. (18), per trial (paper).
        temperature_offset: the +1 in the exponent of eq. (18) (paper).
        carry_q: start each generation's Q-table from the previous one's values where the
            interior posture and the action posture both persist, zeros elsewhere; False
            starts every generation from zeros (open; True: what a generation learnt about
            the actions it hands on is kept, so a good gait is not lost to an unlucky
            exploration).
        new_action_q: with ``carry_q``, what an action new to a carried state starts at:
            ``"zero"`` (the paper's untried value) or ``"row_best"`` (the best value carried in
            that state and exterior state: optimistic, so the roulette tries it). Where
            rewards are large against eq. (18)'s temperature, as in centimetres on a snake
            (carried values of about 3000 against T = 55-408), an action at 0 has a weight of
            e^-7 to e^-50 against the carried best and is never drawn, whatever the table
            says of it (docs/algorithm.md).
        imitate_elite: on a transition table, before each generation learns, raise Q along
            the path of the best verified trial (the elite, often the local search's
            open-loop gait) to the discounted return the table gives it, so that the
            learner takes that path wherever it knows nothing better (self-imitation,
            :mod:`qdsega.agent.imitation`; open: False is the paper's learner, True in
            ``paper-snake``, where the roulette alone rarely strings a gait together;
            docs/algorithm.md).

    The task the learner is rewarded for (trial length, eq. (17), penalty, exterior states)
    is :class:`qdsega.task.TaskConfig`.
    """

    trials: int = 10000
    alpha: float = 0.5
    gamma: float = 0.9
    temperature_scale: float = 150.0
    temperature_rate: float = 0.002
    temperature_offset: float = 1.0
    carry_q: bool = True
    new_action_q: str = "zero"
    imitate_elite: bool = False

    def __post_init__(self) -> None:
        if self.new_action_q not in ("zero", "row_best"):
            raise ValueError(f"new_action_q must be zero or row_best, got {self.new_action_q!r}")
        if self.trials < 1:
            raise ValueError(f"trials must be at least 1, got {self.trials}")
        if not 0.0 < self.alpha <= 1.0:
            raise ValueError(f"alpha must be in (0, 1], got {self.alpha}")
        if not 0.0 <= self.gamma < 1.0:
            raise ValueError(f"gamma must be in [0, 1), got {self.gamma}")
        if not self.temperature_scale > 0 or not self.temperature_rate >= 0:
            raise ValueError("temperature_scale must be positive, temperature_rate >= 0")


@dataclass(frozen=True)
class FitnessConfig:
    """Fitness of an action from the learnt Q-table: eqs. (2)-(6).

    Eq. (4)'s weights are ``w_1 = w_first`` and ``w_Ns = w_last``, all others 0: the paper's
    two named terms, the action's best regulated value ("special actions") and its mean over
    all states ("general actions"); the number of states changes every generation, so only
    these two ends have a fixed meaning. With one state both add to ``w_1``.

    Attributes:
        p: eqs. (2)-(3): regulated values of rewards map into [p, 1], of penalties into
            [0, p) (open; 0.1: an action that earns nothing anywhere, or is never tried,
            scores p, so actions that earn rewards stand well above it).
        w_first: w_1 of eq. (4) (open; 0.0). The best regulated value is 1 for every action
            that is best in any one state, and most actions are, in some rarely visited state:
            in trials this term did not separate useful from useless actions.
        w_last: w_Ns of eq. (4) (open; 1.0): the mean over all states.
        k_f: weight of the frequency of use, eq. (6) (open; 1000.0). The population then
            follows what the learner uses: an action taken in 1 % of the steps weighs 10,
            ten times the largest fit_Q, and the gait's postures, each used in about a third
            of the greedy steps, are kept in proportion to their use. fit_Q (at most 1)
            still ranks the actions that were only tried while eq. (18) was hot, i.e. decides
            which of them stay as material for crossover (30 and 100 did worse;
            docs/algorithm.md).
    """

    p: float = 0.1
    w_first: float = 0.0
    w_last: float = 1.0
    k_f: float = 1000.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.p <= 1.0:
            raise ValueError(f"p must be in [0, 1], got {self.p}")
        if min(self.w_first, self.w_last, self.k_f) < 0:
            raise ValueError("w_first, w_last and k_f must not be negative")


@dataclass(frozen=True)
class GeneticConfig:
    """Structural dynamics: the genetic algorithm over postures (section 4.1.3).

    Selection is fitness-proportional roulette, with replacement; parents are paired in draw
    order and each pair is crossed with probability ``crossover_rate`` (an odd one out is
    copied). Mutation visits every character of every child and, with probability
    ``mutation_rate``, sets it to a different level drawn uniformly.

    Attributes:
        population: individuals (paper: 200 legged, 30 snake).
        generations: learning phases; the population is reproduced after every one but the
            last (paper: 200 legged, 30 snake).
        crossover: ``uniform`` (each character swapped with probability 1/2) or ``one-point``
            (paper: uniform legged, one-point snake).
        crossover_rate: probability that a pair is crossed (paper: 0.2 legged, 0.5 snake).
        mutation_rate: per-character mutation probability (paper: 0.001 legged, 0.02 snake).
        selection: what the roulette wheel's slots are (open; ``actions``). ``actions``: one
            slot per action (distinct phenotype), as large as its fitness, shared by the genes
            that express it; ``individuals``: one slot per gene, as large as its action's
            fitness. The paper rates actions (eqs. 4-6) and regards genes of one phenotype
            as one action (3.2.6), so the wheel has one slot per action. With one slot per
            gene an action's copies are multiplied by its use every generation: the posture
            used most takes over, and postures used less (the first step out of the start
            posture) or equally (the other postures of a gait, left to drift) are lost.
        elitism: put the postures of the best greedy trial verified so far
            (:meth:`qdsega.agent.learner.QDSEGA.verify`: with exact physics where the learner
            runs on a table) back into every later population that lost them, each in place
            of a copy of the most copied phenotype (open; True: a learner on a table that
            overrates other moves would otherwise breed away a gait that exact physics has
            shown to walk, and its learning curve falls below its own first generation).
        reproduce: reproduce the population after each generation (paper: True); False
            keeps the random population drawn at the start for the whole run, the ablation
            "Q-learning over a fixed random set of postures" that shows what the GA adds.
    """

    population: int = 200
    generations: int = 200
    crossover: CrossoverKind = "uniform"
    crossover_rate: float = 0.2
    mutation_rate: float = 0.001
    selection: SelectionKind = "actions"
    elitism: bool = True
    reproduce: bool = True

    def __post_init__(self) -> None:
        if self.population < 2 or self.generations < 1:
            raise ValueError("population must be at least 2 and generations at least 1")
        if self.selection not in ("actions", "individuals"):
            raise ValueError(f"selection must be actions or individuals, got {self.selection!r}")
        if self.crossover not in ("uniform", "one-point"):
            raise ValueError(f"crossover must be uniform or one-point, got {self.crossover!r}")
        for name in ("crossover_rate", "mutation_rate"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must be in [0, 1], got {getattr(self, name)}")


@dataclass(frozen=True)
class QDSEGAConfig:
    """The whole learner: learning dynamics, fitness and structural dynamics."""

    learning: LearningConfig = field(default_factory=LearningConfig)
    fitness: FitnessConfig = field(default_factory=FitnessConfig)
    genetic: GeneticConfig = field(default_factory=GeneticConfig)


@dataclass(frozen=True)
class Preset:
    """A named protocol: the learner's settings and the task's rules.

    Attributes:
        agent: the learner's hyperparameters.
        task: the task's rules (trial length, reward unit, penalty, exterior states).
    """

    agent: QDSEGAConfig
    task: TaskConfig


PRESETS: dict[str, Preset] = {
    "paper-legged": Preset(agent=QDSEGAConfig(), task=TaskConfig()),
    "paper-snake": Preset(
        agent=QDSEGAConfig(
            learning=LearningConfig(trials=1000, new_action_q="row_best", imitate_elite=True),
            genetic=GeneticConfig(
                population=30,
                generations=30,
                crossover="one-point",
                crossover_rate=0.5,
                mutation_rate=0.02,
            ),
        ),
        task=TaskConfig(distance_unit_m=0.01),
    ),
    "memo-legged": Preset(
        agent=QDSEGAConfig(genetic=GeneticConfig(population=40, generations=30)),
        task=TaskConfig(),
    ),
}
"""Section 4's settings: 4.1.3 (multi-legged robot) and 4.2.3 (snake-like robot, with new
actions starting at their state's best carried value: in its centimetres an untried action at 0
is never drawn; and with self-imitation of the best verified trial, which the roulette alone
rarely strings together; docs/algorithm.md); and ``memo-legged``, the legged settings with 40
individuals and 30 generations, for legged bodies in PyBullet, where the paper's 200 x 200
would measure hours of transitions on two cores."""


def with_budget(
    config: QDSEGAConfig, *, generations: int | None = None, trials: int | None = None
) -> QDSEGAConfig:
    """``config`` with fewer (or more) generations or trials per generation."""
    if generations is not None:
        config = replace(config, genetic=replace(config.genetic, generations=generations))
    if trials is not None:
        config = replace(config, learning=replace(config.learning, trials=trials))
    return config
