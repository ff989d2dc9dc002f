"""The simulator a training run learns with, built from the run's configuration: the learner's
model and its exact twin.

* ``msm``: the Minimal Simulation Model (section 4.1.2) of a legged formation, with its
  optimum as the oracle; the model is its own exact physics.
* ``memo``: PyBullet posture-to-posture transitions, each measured once and kept in the run
  folder (``transitions.npz``), filled on demand by worker processes
  (:mod:`qdsega.locomotion.memo`). Every generation's greedy policy is replayed with exact
  physics; with ``ground_table`` the table is corrected by the moves seen there
  (:mod:`qdsega.agent.grounding`).
* ``pybullet``: exact physics, every upper-agent step simulated
  (:class:`qdsega.locomotion.env_model.EnvModel`); the learner then runs in Python, so only
  small budgets are affordable.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from qdsega.agent.boltzmann import temperature
from qdsega.agent.grounding import GroundedTransitions
from qdsega.agent.model import StepModel, TransitionProvider
from qdsega.agent.policy import Policy, Rollout
from qdsega.agent.verification import Verification
from qdsega.description import Formation, World
from qdsega.errors import ConfigError, FormationError, QdsegaWarning
from qdsega.msm import LegLayout, MinimalSimulationModel, Optimum, msm_optimum
from qdsega.progress import ProgressFactory
from qdsega.task import Task
from qdsega.training.config import TrainingConfig
from qdsega.training.run_folder import RunFolder

if TYPE_CHECKING:
    from qdsega.locomotion.exact_trials import ExactTrials

_NUMBERS = re.compile(r" by -?[\d.]+ deg| \(tilt -?[\d.]+ deg\)")
"""The measured part of a failure message, left out where failures are counted by kind."""
VARIED_GROUND_SPOTS = 6
"""Places a move is measured from in memo mode where the ground varies (1.25 m of the way)."""


@dataclass(frozen=True)
class Failures:
    """How exact trials failed: commands sent, trials run, and failed trials by kind (the
    lower agent's message without its measured numbers)."""

    commands: int = 0
    trials: int = 0
    kinds: dict[str, int] = field(default_factory=dict)

    @property
    def share(self) -> float:
        """Failed commands over commands sent (a failed trial ends at its failed command)."""
        return sum(self.kinds.values()) / self.commands if self.commands else 0.0

    @property
    def most_common(self) -> str | None:
        """The commonest kind of failure (the first of equals), or None."""
        return max(self.kinds, key=self.kinds.__getitem__) if self.kinds else None

    def since(self, earlier: Failures) -> Failures:
        """What happened after ``earlier``."""
        kinds = {k: n - earlier.kinds.get(k, 0) for k, n in self.kinds.items()}
        return Failures(
            self.commands - earlier.commands,
            self.trials - earlier.trials,
            {k: n for k, n in kinds.items() if n},
        )

    def add(self, trials: list[Rollout]) -> Failures:
        """These failures and those of ``trials``."""
        kinds = dict(self.kinds)
        for trial in trials:
            if trial.failed:
                kind = _NUMBERS.sub("", trial.failure or "failed")
                kinds[kind] = kinds.get(kind, 0) + 1
        commands = self.commands + sum(len(trial.postures) for trial in trials)
        return Failures(commands, self.trials + len(trials), kinds)


@dataclass
class TrainingSim:
    """The learner's model, its exact twin, and what the run needs to know about them. It only plays
    trials: which ones is asked of the learner (:class:`qdsega.agent.verification.Verification`).

    Attributes:
        provider: the model the learner learns on: a posture-transition table, or a
            step-by-step model (exact physics).
        exact: exact-physics trials to replay what the learner asks (spread over the run's
            workers); None where ``provider`` is exact itself (the MSM, PyBullet).
        grounded: the table that exact trials correct (memo mode with ``ground_table``;
            it is also ``provider``), else None.
        task: the rules.
        optimum: the optimum where one is known (the MSM), else None.
        layout: the legs, for gait figures; None for a legless formation.
        world: the ground it walks on.
    """

    provider: TransitionProvider | StepModel
    exact: ExactTrials | None
    grounded: GroundedTransitions | None
    task: Task
    optimum: Optimum | None
    layout: LegLayout | None
    world: World = field(default_factory=World)
    failures: Failures = field(default_factory=Failures, init=False)
    """How the run's verified trials (exact, or the learner's own where its model is exact physics)
    failed so far."""

    def play(self, policies: list[Policy]) -> list[Rollout]:
        """Each of ``policies`` played once with exact physics, in order; their failures are
        counted."""
        if not policies:
            return []
        assert self.exact is not None, "only a simulator with an exact twin plays trials"
        trials = self.exact.rollouts(policies, steps=self.task.trial_steps)
        self.count(trials)
        return trials

    def count(self, trials: list[Rollout]) -> None:
        """Add ``trials``' failures to :attr:`failures`."""
        self.failures = self.failures.add(trials)

    def observe(self, trials: list[Rollout], start: np.ndarray) -> None:
        """A grounded table learns the moves of ``trials`` (in order: the last one seen
        wins), each from posture ``start``; nothing without one."""
        if self.grounded is not None:
            for trial in trials:
                self.grounded.observe(trial, start)

    def memo_spots(self) -> int | None:
        """How many places memo mode measures each move from (those the body can stand at);
        None for other simulators."""
        memo = self.grounded.base if self.grounded is not None else self.provider
        spots = getattr(memo, "spots", None)
        return None if spots is None else len(spots)

    def simulated_steps(self) -> int:
        """Upper-agent steps simulated in PyBullet by this simulator so far: memo transitions
        measured (each one move from a settled start), exact trials' commands, and every
        command to a learner whose model is exact physics; 0 in the MSM."""
        memo = self.grounded.base if self.grounded is not None else self.provider
        counters = ((memo, "measured"), (self.exact, "commands"), (self.provider, "commands"))
        return sum(getattr(part, name, 0) for part, name in counters)

    def state(self) -> dict[str, np.ndarray]:
        """What the run's history put into the simulator (grounded observations; the
        failures: ``failure_kinds``, ``failure_counts`` and ``failure_totals`` (commands,
        trials)), as arrays."""
        state = {} if self.grounded is None else self.grounded.state()
        if self.failures.trials:
            kinds = self.failures.kinds
            state["failure_kinds"] = np.array(list(kinds), dtype=str)
            state["failure_counts"] = np.array(list(kinds.values()), dtype=np.int64)
            totals = [self.failures.commands, self.failures.trials]
            state["failure_totals"] = np.array(totals, dtype=np.int64)
        return state

    def restore(self, state: dict[str, np.ndarray]) -> None:
        """Return to :meth:`state` (other keys are ignored)."""
        if self.grounded is not None and state:
            self.grounded.restore(state)
        self.failures = Failures()
        if "failure_totals" in state:
            commands, trials = (int(n) for n in state["failure_totals"])
            counts = zip(state["failure_kinds"], state["failure_counts"], strict=True)
            self.failures = Failures(commands, trials, {str(k): int(n) for k, n in counts})

    def save(self, run: Path) -> None:
        """Keep what the simulator measured (memo mode) in the run folder."""
        memo = self.grounded.base if self.grounded is not None else self.provider
        save = getattr(memo, "save", None)
        if save is not None:
            save(run / RunFolder.TRANSITIONS)

    def close(self) -> None:
        for part in (self.grounded.base if self.grounded else self.provider, self.exact):
            close = getattr(part, "close", None)
            if close is not None:
                close()


def check_sim(formation: Formation, config: TrainingConfig, world: World | None = None) -> None:
    """Refuse, before anything is written, a formation (or a world) the simulator
    ``config.sim`` cannot model.

    Raises:
        FormationError: a legless formation in the MSM; a formation the lower agent cannot
            drive in PyBullet.
        ConfigError: a world other than the flat plane in the MSM.
        WorldError: a body that would start inside one of the world's obstacles.
    """
    if config.sim == "msm":
        if world is not None and not world.is_flat:
            raise ConfigError(
                f"the MSM knows no terrain: {world.name} needs --sim memo or pybullet"
            )
        LegLayout.from_formation(formation)
        return
    try:
        config.lower_agent.step_duration_for(formation)
    except ValueError as exc:
        raise FormationError(str(exc), file=formation.file) from None
    if world is not None and not world.is_uniform:
        from qdsega.assembly import assemble  # starts PyBullet: only where obstacles may be
        from qdsega.simulation.bullet import BulletSimulation

        with BulletSimulation(
            robot=assemble(formation), settings=config.physics, world=world
        ) as sim:
            sim.reset(formation.posture_rad(formation.rest_levels()))  # refuses a start inside


def build_sim(
    formation: Formation,
    config: TrainingConfig,
    run: Path,
    *,
    world: World | None = None,
    measuring: ProgressFactory | None = None,
) -> TrainingSim:
    """The simulator ``config.sim`` names, for ``formation`` in ``world`` (default flat; the MSM
    knows none); memo mode reuses ``run``'s table and shows large batches of measuring through
    ``measuring``.

    Raises:
        FormationError: the formation cannot be modelled by that simulator (a snake in the MSM).
    """
    rules = config.rules(world)
    if config.sim == "msm":  # a flat world: the paper's task, no obstacle map
        task = Task(config=config.task, light_xy=formation.light.position_m)
        legs = LegLayout.from_formation(formation)  # refuses a legless formation
        model = MinimalSimulationModel(legs=legs, params=config.msm)
        optimum = msm_optimum(model, steps=task.trial_steps, light_xy=tuple(task.light))
        return TrainingSim(model, None, None, task, optimum, legs, world=rules.world)
    layout = LegLayout.from_formation(formation, both_sides=False) if formation.legs else None
    from qdsega.locomotion.env import rules_env  # starts PyBullet: only when needed
    from qdsega.locomotion.env_model import EnvModel

    if config.sim == "pybullet":
        env = rules_env(formation, rules)
        return TrainingSim(EnvModel(env=env), None, None, env.task, None, layout, world=rules.world)
    from qdsega.locomotion.exact_trials import ExactTrials
    from qdsega.locomotion.memo import MeasuredTransitions
    from qdsega.locomotion.surroundings import world_task

    task = world_task(formation, config.task, rules.world, config.physics)
    spots, blocked = memo_starts(formation, config, rules.world, task)
    if blocked and not (run / RunFolder.TRANSITIONS).is_file():  # said once, when it begins
        warnings.warn(_blocked(formation, rules.world, spots, blocked), QdsegaWarning, 2)
    spots = tuple(spot for spot in spots if spot not in blocked)  # no move is made there
    memo = MeasuredTransitions(
        formation=formation,
        lower_agent=config.lower_agent,
        physics=config.physics,
        workers=config.workers,
        ray=config.ray,
        progress=measuring,
        world=rules.world,
        spots=spots,
    )
    if (run / RunFolder.TRANSITIONS).is_file():
        memo.load(run / RunFolder.TRANSITIONS)
    grounded = GroundedTransitions(base=memo) if config.ground_table else None
    provider = grounded if grounded is not None else memo
    exact = ExactTrials(formation=formation, rules=rules, workers=config.workers)
    return TrainingSim(provider, exact, grounded, task, None, layout, world=rules.world)


def memo_starts(
    formation: Formation, config: TrainingConfig, world: World, task: Task | None = None
) -> tuple[tuple[tuple[float, float], ...], list[tuple[float, float]]]:
    """The places memo mode would measure each move of ``formation`` from in ``world``, and
    those of them left out: where the body cannot stand, or touches an obstacle (the table
    knows those from the obstacle map, :mod:`qdsega.obstacle_map`).

    Raises:
        WorldError: every place is left out (one line).
    """
    from qdsega.locomotion.memo import clear_spots
    from qdsega.locomotion.surroundings import world_task

    return clear_spots(
        formation,
        task=task or world_task(formation, config.task, world, config.physics),
        physics=config.physics,
        world=world,
        count=memo_spots(config, world),
    )


def build_verification(config: TrainingConfig) -> Verification:
    """The exact trials a memo run asks for each generation, as ``config`` sets them."""
    learning = config.agent.learning
    last = temperature(
        learning.trials - 1,
        learning.temperature_scale,
        learning.temperature_rate,
        learning.temperature_offset,
    )
    return Verification(
        explore_trials=config.explore_trials,
        temperature=last,
        optimism=config.optimism,
        local_search=config.local_search,
        phase_moves=config.phase_moves,
        seed=config.seed,
    )


def _blocked(
    formation: Formation,
    world: World,
    spots: tuple[tuple[float, float], ...],
    blocked: list[tuple[float, float]],
) -> str:
    """The one-line warning for a memo run with starts the body cannot stand at."""
    where = ", ".join(f"({x:.2f}, {y:.2f})" for x, y in blocked)
    return (
        f"{formation.name} cannot stand clear of obstacles at {len(blocked)} of the "
        f"{len(spots)} places memo mode measures each move from in {world.name} (x, y m: "
        f"{where}): the table measures its moves from the other {len(spots) - len(blocked)}, "
        "and exact replays show where the body is stopped"
    )


def memo_spots(config: TrainingConfig, world: World) -> int:
    """How many places memo mode measures each move from in ``world``."""
    if config.memo_spots is not None:
        return config.memo_spots
    return 1 if world.is_plane else VARIED_GROUND_SPOTS


def leg_states(layout: LegLayout | None, postures: np.ndarray) -> np.ndarray:
    """Leg states 1..4 of each posture (k, J) -> (k, n_legs); empty columns without legs."""
    if layout is None:
        return np.zeros((len(postures), 0), dtype=np.int64)
    return layout.states(postures)
