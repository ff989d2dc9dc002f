"""The benchmark's tasks: a formation, the world its learners spend their budget in, and that
budget; with the yardstick each method's distance is measured against.

* ``legged12-msm``: legged12 in the Minimal Simulation Model; every method's steps are MSM
  steps and the yardstick is the model's exact optimum (:func:`qdsega.msm.msm_optimum`).
* ``snake5-pybullet``: snake5 in PyBullet; a step is an upper-agent step simulated in PyBullet
  (a memo transition measured, or a command of an exact trial), and the yardstick is the
  shipped CMA-ES reference gait (:func:`qdsega.baselines.reference_search.reference_gait`,
  600 trials): not an optimum, the best gait known.

Every task uses its formation's own preset (:func:`qdsega.training.config.default_preset`)
for the rules: levels, lower agent, trial length, reward eq. (17), penalty.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from qdsega.bench.arena import Arena, MSMArena
from qdsega.description import Formation, load_formation, resolve_formation
from qdsega.msm import LegLayout, MinimalSimulationModel, msm_optimum
from qdsega.task import Task
from qdsega.training.config import TrainingConfig, resolve_config

LEARNING_SIM = {"msm": "msm", "pybullet": "memo"}
"""A task's world -> the table world its learners learn in (``qdsega train --sim``, and
:class:`qdsega.locomotion.table_env.TableLocomotionEnv`)."""


@dataclass(frozen=True, kw_only=True)
class BenchTask:
    """One task of the benchmark.

    Attributes:
        name: ``FORMATION-WORLD``.
        formation: a shipped formation's name.
        sim: ``msm`` or ``pybullet``.
        budget_steps: upper-agent steps each method may spend in the world (-).
        seeds: runs of each method, seeds 0 .. seeds - 1.
        generations: QDSEGA's generations (its run ends there or at the budget) (-).
        trials: QDSEGA's trials per generation; None keeps the preset's (-).
        population: QDSEGA's population; None keeps the preset's (-).
        ppo_steps: PPO's environment steps, at most (-); PPO also stops at the budget.
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

    def __post_init__(self) -> None:
        if self.sim not in LEARNING_SIM:
            raise ValueError(f"sim must be one of {', '.join(LEARNING_SIM)}, got {self.sim!r}")
        if self.seeds < 1 or self.budget_steps < 1 or self.generations < 1:
            raise ValueError("seeds, budget_steps and generations must be at least 1")

    def load(self) -> Formation:
        """The formation."""
        return load_formation(resolve_formation(self.formation))

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

    def arena(self) -> Arena:
        """A place to play posture sequences, with one worker."""
        formation, config = self.load(), self.config(seed=0)
        if self.sim == "msm":
            return MSMArena(model=_msm(formation, config), task=self.rules())
        from qdsega.locomotion.exact_trials import ExactTrials  # starts PyBullet: only here

        return ExactTrials(formation=formation, rules=config.rules(), workers=1)

    def yardstick(self) -> tuple[str, float]:
        """What distances are measured against: its name and distance (m)."""
        formation, config = self.load(), self.config(seed=0)
        if self.sim == "msm":
            optimum = msm_optimum(
                _msm(formation, config), steps=config.task.trial_steps, light_xy=_light(formation)
            )
            return "the MSM's exact optimum", optimum.distance_m
        from qdsega.baselines.reference_search import DEFAULT_BUDGET_TRIALS, reference_gait

        reference = reference_gait(
            formation,
            rules=config.rules(),
            workers=1,
        )
        return f"the CMA-ES reference gait ({DEFAULT_BUDGET_TRIALS} trials)", reference.distance_m


def _msm(formation: Formation, config: TrainingConfig) -> MinimalSimulationModel:
    return MinimalSimulationModel(legs=LegLayout.from_formation(formation), params=config.msm)


def _light(formation: Formation) -> tuple[float, float]:
    x, y = formation.light.position_m
    return (float(x), float(y))


ALL_METHODS = (
    "qdsega", "qdsega-no-carry", "fixed-set", "ga-sequence", "random-search", "cma-cpg", "ppo"
)  # fmt: skip
"""Every method of :data:`qdsega.bench.methods.METHODS`, in report order."""

FULL = (
    BenchTask(
        name="legged12-msm",
        formation="legged12",
        sim="msm",
        budget_steps=10_000_000,
        seeds=5,
        generations=200,
        ppo_steps=100_000,
        methods=ALL_METHODS,
        budgets=(10_000, 100_000, 1_000_000, 10_000_000, 60_000_000),
        forced=(
            "The QDSEGA runs (all three) are the paper's whole protocol, 200 generations of "
            "10000 trials (up to 6e7 steps, about a minute a seed). The sequence methods stop "
            "at 1e7 steps (a seed took 171 s for CMA-ES and 254 s for the GA here; 6e7 would "
            "take 17 and 25 minutes) and PPO at 1e5 (136 s a seed: stable-baselines3 builds "
            "one distribution per joint per policy call)."
        ),
    ),
    BenchTask(
        name="snake5-pybullet",
        formation="snake5",
        sim="pybullet",
        budget_steps=3000,
        seeds=3,
        generations=5,
        ppo_steps=50_000,
        methods=("qdsega", "ga-sequence", "random-search", "cma-cpg", "ppo"),
        budgets=(300, 1000, 2000, 3000),
        forced=(
            "3 seeds, not 5, and 3000 PyBullet steps per run (about 2 minutes a run on one "
            "core; PPO 7.5 minutes, since every memo pair it asks for is settled and measured "
            "alone); the paper's snake protocol takes about 10000. Not run: the two QDSEGA "
            "ablations (about 5 minutes more) and the quadruped and legged12 in PyBullet (about "
            "25 minutes each)."
        ),
    ),
)
"""The full benchmark (``qdsega bench``): about an hour on 2 cores."""

QUICK = (
    BenchTask(
        name="legged12-msm",
        formation="legged12",
        sim="msm",
        budget_steps=20_000,
        seeds=2,
        generations=3,
        trials=100,
        population=20,
        ppo_steps=512,
        methods=ALL_METHODS,
        budgets=(1_000, 10_000, 20_000),
        forced="Quick mode: tiny budgets that check the pipeline, not the methods.",
    ),
    BenchTask(
        name="snake5-pybullet",
        formation="snake5",
        sim="pybullet",
        budget_steps=360,  # one CMA-ES iteration: 11 trials
        seeds=1,
        generations=1,
        trials=50,
        population=6,
        ppo_steps=30,
        methods=("qdsega", "ga-sequence", "random-search", "cma-cpg", "ppo"),
        budgets=(120, 360),
        forced="Quick mode: tiny budgets that check the pipeline, not the methods.",
    ),
)
"""``qdsega bench --quick``: every method on tiny budgets, a few minutes."""
