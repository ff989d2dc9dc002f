"""The world a training run learns in, built from the run's configuration.

* ``msm``: the Minimal Simulation Model (section 4.1.2) of a legged formation, with its exact
  optimum as the oracle.
* ``memo``: PyBullet posture-to-posture transitions, each measured once and kept in the run
  folder (``transitions.npz``), filled on demand by worker processes
  (:mod:`qdsega.locomotion.memo`);
* ``pybullet``: exact physics, every upper-agent step simulated
  (:class:`qdsega.locomotion.env_world.EnvWorld`); the learner then runs in Python, so only
  small budgets are affordable.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from qdsega.agent.world import TransitionProvider, World
from qdsega.description import Formation
from qdsega.errors import FormationError
from qdsega.msm import LegLayout, MinimalSimulationModel, Optimum, msm_optimum
from qdsega.training.config import TrainingConfig

if TYPE_CHECKING:
    from qdsega.locomotion.env import TaskConfig

MEMO_FILE = "transitions.npz"
"""The memo table in a run folder."""


@dataclass
class TrainingWorld:
    """A world and what the run needs to know about it.

    Attributes:
        provider: the world the learner runs in: a posture-transition table, or a
            step-by-step world (exact physics).
        optimum: the exact optimum where one is known (the MSM), else None.
        layout: the legs, for gait figures; None for a legless formation.
    """

    provider: TransitionProvider | World
    optimum: Optimum | None
    layout: LegLayout | None

    def save(self, run: Path) -> None:
        """Keep what the world measured (memo mode) in the run folder."""
        save = getattr(self.provider, "save", None)
        if save is not None:
            save(run / MEMO_FILE)

    def close(self) -> None:
        close = getattr(self.provider, "close", None)
        if close is not None:
            close()


def check_world(formation: Formation, config: TrainingConfig) -> None:
    """Refuse, before anything is written, a formation the world ``config.sim`` cannot model.

    Raises:
        FormationError: a legless formation in the MSM; a formation the lower agent cannot
            drive in PyBullet.
    """
    if config.sim == "msm":
        LegLayout.from_formation(formation)
        return
    try:
        config.lower_agent.check_formation(formation)
    except ValueError as exc:
        raise FormationError(f"{formation.name}: {exc}", file=formation.file) from None


def build_world(formation: Formation, config: TrainingConfig, run: Path) -> TrainingWorld:
    """The world ``config.sim`` names, for ``formation``; memo mode reuses ``run``'s table.

    Raises:
        FormationError: the formation cannot be modelled by that world (a snake in the MSM).
    """
    if config.sim == "msm":
        layout = LegLayout.from_formation(formation)  # refuses a legless formation
        model = MinimalSimulationModel(legs=layout, params=config.msm)
        steps = config.agent.learning.trial_steps
        return TrainingWorld(
            model, msm_optimum(model, steps=steps, light_xy=light_of(formation)), layout
        )
    layout = LegLayout.from_formation(formation) if formation.legs else None
    if config.sim == "pybullet":
        from qdsega.locomotion.env import LocomotionEnv  # starts PyBullet: only when needed
        from qdsega.locomotion.env_world import EnvWorld

        env = LocomotionEnv(formation=formation, task=task_of(config), physics=config.physics)
        return TrainingWorld(EnvWorld(env=env), None, layout)
    from qdsega.locomotion.memo import MeasuredTransitions

    provider = MeasuredTransitions(
        formation=formation,
        lower_agent=config.lower_agent,
        physics=config.physics,
        workers=config.workers,
    )
    if (run / MEMO_FILE).is_file():
        provider.load(run / MEMO_FILE)
    return TrainingWorld(provider, None, layout)


def task_of(config: TrainingConfig) -> TaskConfig:
    """The PyBullet task with the learner's trial length, reward, penalty and exterior bins."""
    from qdsega.locomotion.env import TaskConfig

    learning = config.agent.learning
    return TaskConfig(
        trial_steps=learning.trial_steps,
        reward_scale=learning.reward_scale,
        penalty=learning.penalty,
        exterior_bin_edges_deg=learning.exterior_bin_edges_deg,
        lower_agent=config.lower_agent,
    )


def light_of(formation: Formation) -> tuple[float, float]:
    """The light position (m) as a plain tuple."""
    x, y = formation.light.position_m
    return (float(x), float(y))


def leg_states(layout: LegLayout | None, postures: np.ndarray) -> np.ndarray:
    """Leg states 1..4 of each posture (k, J) -> (k, n_legs); empty columns without legs."""
    if layout is None:
        return np.zeros((len(postures), 0), dtype=np.int64)
    return layout.states(postures)
