"""The rules exact physics judges a body's trials by: one object, so that training, evaluation,
the reference search and the benchmark hand the same rules on together."""

from __future__ import annotations

from dataclasses import dataclass, field

from qdsega.description.world import World
from qdsega.locomotion.lower_agent import LowerAgentConfig
from qdsega.simulation.settings import PhysicsSettings
from qdsega.task import TaskConfig


@dataclass(frozen=True, kw_only=True)
class ExactRules:
    """Everything but the body that a trial's outcome depends on.

    Attributes:
        task: trial length, reward (eq. 17), penalty, exterior bins.
        lower_agent: how a posture is executed, and when that fails.
        physics: the engine's settings.
        world: the ground and what stands on it (its light is the formation's business:
            :meth:`qdsega.description.world.World.light`).
    """

    task: TaskConfig = field(default_factory=TaskConfig)
    lower_agent: LowerAgentConfig = field(default_factory=LowerAgentConfig)
    physics: PhysicsSettings = field(default_factory=PhysicsSettings)
    world: World = field(default_factory=World)
