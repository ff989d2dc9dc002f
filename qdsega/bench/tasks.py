"""The benchmark's tasks: a formation, the simulator and world its learners spend their budget
in, and that budget; with the yardstick each method's distance is measured against.

* ``legged12-msm``: legged12 in the Minimal Simulation Model; every method's steps are MSM
  steps and the yardstick is the model's optimum (:func:`qdsega.msm.msm_optimum`).
* ``snake5-pybullet``: snake5 in PyBullet; a step is an upper-agent step simulated in PyBullet
  (a memo transition measured, or a command of an exact trial), and the yardstick is the
  shipped CMA-ES reference gait (:func:`qdsega.baselines.reference_search.reference_gait`,
  600 trials): not an optimum, the best gait known.

Every task uses its formation's own preset (:func:`qdsega.training.config.default_preset`)
for the rules: levels, lower agent, trial length, reward eq. (17), penalty. A PyBullet task may
walk in another world than the flat plane (:func:`in_world`, ``qdsega bench --world``): every
method learns and is judged there, and the yardstick is the reference gait found there.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from qdsega.bench.arena import Arena, MSMArena
from qdsega.description import (
    Formation,
    World,
    load_formation,
    named_world,
    resolve_formation,
)
from qdsega.locomotion.rules import ExactRules
from qdsega.msm import LegLayout, MinimalSimulationModel, msm_optimum
from qdsega.task import Task
from qdsega.training.config import TrainingConfig, resolve_config

LEARNING_SIM = {"msm": "msm", "pybullet": "memo"}
"""A task's simulator -> the table model its learners learn in (``qdsega train --sim``, and
:class:`qdsega.locomotion.table_env.TableLocomotionEnv`)."""
FLAT = "flat"
"""The world every task walks in unless told otherwise: the plane of before worlds existed."""
PYBULLET_ONLY = ("ppo-joint", "sac-joint")
"""The methods that learn under continuous control in PyBullet
(:mod:`qdsega.bench.joint_learners`): the MSM has no joints to drive."""


@dataclass(frozen=True, kw_only=True)
class BenchTask:
    """One task of the benchmark.

    Attributes:
        name: ``FORMATION-SIM``, then ``-WORLD`` outside the flat plane.
        formation: a shipped formation's name.
        sim: ``msm`` or ``pybullet``.
        world: the ground of a PyBullet task: a shipped world's name or a world file
            (:func:`read_world`); the MSM knows only ``flat``.
        budget_steps: upper-agent steps each method may spend in the world (-).
        seeds: runs of each method, seeds 0 .. seeds - 1.
        generations: QDSEGA's generations (its run ends there or at the budget) (-).
        trials: QDSEGA's trials per generation; None keeps the preset's (-).
        population: QDSEGA's population; None keeps the preset's (-).
        ppo_steps: posture steps the learners that take steps may take, at most (-): PPO's
            steps in its table, the joint learners' in physics time; they also stop at the
            budget.
        methods: the methods run, names of :data:`qdsega.bench.methods.METHODS`.
        budgets: the fixed budgets of the table (steps).
        forced: what the time available forced on this task, for the report.
    """

    name: str
    formation: str
    sim: str
    budget_steps: int
    seeds: int
    generations: int
    trials: int | None = None
    population: int | None = None
    ppo_steps: int
    methods: tuple[str, ...]
    budgets: tuple[int, ...]
    forced: str = ""
    world: str = FLAT

    def __post_init__(self) -> None:
        if self.sim not in LEARNING_SIM:
            raise ValueError(f"sim must be one of {', '.join(LEARNING_SIM)}, got {self.sim!r}")
        if self.seeds < 1 or self.budget_steps < 1 or self.generations < 1:
            raise ValueError("seeds, budget_steps and generations must be at least 1")
        if self.sim == "msm" and self.world != FLAT:
            raise ValueError(f"the MSM knows no terrain: {self.name} cannot walk in {self.world}")
        joint = [method for method in self.methods if method in PYBULLET_ONLY]
        if self.sim == "msm" and joint:
            raise ValueError(
                f"{self.name} cannot run {', '.join(joint)}: they drive joints in PyBullet "
                "(qdsega/JointLocomotion-v0), and the MSM has no joints to drive"
            )

    def load_world(self) -> World:
        """The world its learners walk in and are judged in."""
        return read_world(self.world)

    def load(self) -> Formation:
        """The formation, its light the world's where the world names one (as training and
        :class:`qdsega.locomotion.env.LocomotionEnv` light it)."""
        formation = load_formation(resolve_formation(self.formation))
        return self.load_world().lights(formation)

    def config(
        self,
        *,
        seed: int,
        learning: dict[str, Any] | None = None,
        genetic: dict[str, Any] | None = None,
    ) -> TrainingConfig:
        """QDSEGA's training configuration: the body's own preset with this task's budget and one
        worker, then ``learning`` and ``genetic`` settings (keys as in ``config.yaml``)."""
        sim = LEARNING_SIM[self.sim]
        genes: dict[str, Any] = {"generations": self.generations, **(genetic or {})}
        if self.population is not None:
            genes["population"] = self.population
        learns = dict(learning or {})
        if self.trials is not None:
            learns["trials"] = self.trials
        agent = {"genetic": genes, "learning": learns}
        return resolve_config(
            overrides={"sim": sim, "seed": seed, "workers": 1, "agent": agent},
            formation=self.load(),
        )

    def rules(self) -> Task:
        """The task's rules for this formation's light."""
        return Task(config=self.config(seed=0).task, light_xy=self.load().light.position_m)

    def exact_rules(self) -> ExactRules:
        """What exact physics judges its trials by: the preset's rules, in its world."""
        return self.config(seed=0).rules(self.load_world())

    def arena(self) -> Arena:
        """A place to play posture sequences, with one worker."""
        formation, config = self.load(), self.config(seed=0)
        if self.sim == "msm":
            return MSMArena(model=_msm(formation, config), task=self.rules())
        from qdsega.locomotion.exact_trials import ExactTrials  # starts PyBullet: only here

        return ExactTrials(formation=formation, rules=self.exact_rules(), workers=1)

    def yardstick(self) -> tuple[str, float]:
        """What distances are measured against: its name and distance (m)."""
        formation, config = self.load(), self.config(seed=0)
        if self.sim == "msm":
            optimum = msm_optimum(
                _msm(formation, config), steps=config.task.trial_steps, light_xy=_light(formation)
            )
            return "the MSM's optimum", optimum.distance_m
        from qdsega.baselines.reference_search import DEFAULT_BUDGET_TRIALS, reference_gait

        reference = reference_gait(formation, rules=self.exact_rules(), workers=1)
        return f"the CMA-ES reference gait ({DEFAULT_BUDGET_TRIALS} trials)", reference.distance_m


def read_world(world: str) -> World:
    """The world ``world`` names: for ``flat`` the plane of before worlds existed, which no
    file describes (so flat runs are as they were, no copy of a world in their folders); else
    a shipped world's name or a world file.

    Raises:
        WorldError: no shipped world of that name, or a file that does not read as a world.
    """
    return World() if world == FLAT else named_world(world)


def in_world(
    tasks: Sequence[BenchTask], world: str
) -> tuple[tuple[BenchTask, ...], tuple[BenchTask, ...]]:
    """``tasks`` in ``world`` (a shipped world's name or a world file): the tasks kept and
    those left out. On a flat plane with no light of its own every task is kept as it is (its
    name, and so its results' folder, unchanged); elsewhere the PyBullet tasks of the flat
    plane walk there, named ``FORMATION-pybullet-WORLD``, and the MSM tasks, which know no
    terrain, and the tasks of a world of their own are left out.

    Raises:
        WorldError: as :func:`read_world`.
    """
    found = read_world(world)
    if found.is_flat and found.light is None:
        return tuple(tasks), ()
    moved = [task.sim != "msm" and task.world == FLAT for task in tasks]
    kept = tuple(
        replace(task, name=task.name + suffix(world), world=world)
        for task, move in zip(tasks, moved, strict=True)
        if move
    )
    return kept, tuple(task for task, move in zip(tasks, moved, strict=True) if not move)


def suffix(world: str) -> str:
    """What a task's name, and the benchmark's default folder, gain outside the flat plane:
    ``-NAME``, a shipped world's name or a world file's stem."""
    return f"-{Path(world).stem}"


def _msm(formation: Formation, config: TrainingConfig) -> MinimalSimulationModel:
    return MinimalSimulationModel(legs=LegLayout.from_formation(formation), params=config.msm)


def _light(formation: Formation) -> tuple[float, float]:
    x, y = formation.light.position_m
    return (float(x), float(y))


ALL_METHODS = (
    "qdsega", "qdsega-no-carry", "fixed-set", "ga-sequence", "random-search", "cma-cpg", "ppo",
    "ppo-joint", "sac-joint",
)  # fmt: skip
"""Every method of :data:`qdsega.bench.methods.METHODS`, in report order."""
MSM_METHODS = tuple(method for method in ALL_METHODS if method not in PYBULLET_ONLY)
"""Every method an MSM task can run."""
STABLE_BASELINES = ("ppo", "ppo-joint", "sac-joint")
"""The methods that need stable-baselines3 (the ``bench`` extra)."""

PYBULLET_METHODS = (
    "qdsega", "ga-sequence", "random-search", "cma-cpg", "ppo", "ppo-joint", "sac-joint"
)  # fmt: skip
"""The methods of a PyBullet task: QDSEGA's ablations are measured in the MSM, where they cost
a minute a seed, not in PyBullet."""


def _pybullet_task(formation: str, world: str = FLAT) -> BenchTask:
    """``FORMATION-pybullet[-WORLD]``: 3000 PyBullet steps, 5 seeds, QDSEGA for 5 generations
    of its preset (on snake5 about 5,000 steps: past the budget, not 7 times it as its preset's
    30 would be)."""
    return BenchTask(
        name=f"{formation}-pybullet" + ("" if world == FLAT else suffix(world)),
        formation=formation,
        sim="pybullet",
        world=world,
        budget_steps=3000,
        seeds=5,
        generations=5,
        ppo_steps=50_000,
        methods=PYBULLET_METHODS,
        budgets=(300, 1000, 2000, 3000),
        forced=(
            "3000 PyBullet steps per run, about the paper's snake protocol's third; the QDSEGA "
            "ablations are measured in the MSM task only."
        ),
    )


FULL = (
    BenchTask(
        name="legged12-msm",
        formation="legged12",
        sim="msm",
        budget_steps=10_000_000,
        seeds=5,
        generations=200,
        ppo_steps=10_000_000,
        methods=MSM_METHODS,
        budgets=(10_000, 100_000, 1_000_000, 10_000_000, 60_000_000),
        forced=(
            "The QDSEGA runs (all three) are the paper's whole protocol, 200 generations of "
            "10000 trials (up to 6e7 steps). The other methods stop at 1e7 steps (PPO: 64 "
            "environments side by side)."
        ),
    ),
    _pybullet_task("snake5"),
    _pybullet_task("quadruped"),
    _pybullet_task("legged12"),
    _pybullet_task("snake5", "rubble"),
)
"""The full benchmark (``qdsega bench``): about 17 core-hours, 9 hours on 2 cores."""

QUICK = (
    BenchTask(
        name="legged12-msm",
        formation="legged12",
        sim="msm",
        budget_steps=20_000,
        seeds=1,
        generations=3,
        trials=100,
        population=20,
        ppo_steps=512,
        methods=MSM_METHODS,
        budgets=(1_000, 10_000, 20_000),
        forced="Quick mode: tiny budgets that check the pipeline, not the methods.",
    ),
    BenchTask(
        name="snake5-pybullet",
        formation="snake5",
        sim="pybullet",
        budget_steps=120,  # four trials
        seeds=1,
        generations=1,
        trials=50,
        population=6,
        ppo_steps=15,
        # one of each way into PyBullet: a learner's run, open-loop sequences, an env, and
        # joint control (both joint learners: 180 env steps each, half a trial's physics time)
        methods=("qdsega", "random-search", "ppo", "ppo-joint", "sac-joint"),
        budgets=(60, 120),
        forced="Quick mode: tiny budgets that check the pipeline, not the methods.",
    ),
)
"""``qdsega bench --quick``: every method on tiny budgets, a few minutes."""
