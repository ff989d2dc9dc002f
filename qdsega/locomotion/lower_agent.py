"""The lower agent (paper section 3.2.2): drives every joint to the commanded posture.

It acts like the paper's stepping motors (section 4.2.2): every joint moves toward its level at
one constant angular speed, and each upper-agent step lasts a fixed time. It fails, which ends
the trial with a penalty (section 3.2.3), when

* a joint is not within ``tolerance_rad`` of its level at the end of the step (blocked by the
  ground, another unit or its torque limit);
* the body flips: a trunk unit's up axis tilts more than ``max_tilt_rad`` from vertical;
* the trunk of a legged formation touches the ground (its legs no longer carry it);
* the physics state becomes non-finite.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from qdsega.description import Formation
from qdsega.locomotion.body_pose import BodyPose, BodyPoseEstimator

if TYPE_CHECKING:  # the configuration is usable without starting the physics engine
    from qdsega.simulation.bullet import BulletSimulation


SETTLE_S = 0.5
"""Time a body placed in its start posture rests before it is commanded (s): every trial and
every memo transition starts this way."""
STEP_GRID_S = 0.05
"""A derived step duration is rounded up to a multiple of this (s)."""


@dataclass(frozen=True, kw_only=True)
class LowerAgentConfig:
    """How postures are executed and when execution fails.

    Attributes:
        step_duration_s: duration of one upper-agent step (s); every joint must arrive within
            it. None (the default) derives it from the formation
            (:meth:`step_duration_for`), so any formation runs without a setting.
        joint_speed_rad_s: the constant angular speed of every joint (rad/s), capped by each
            unit's own speed limit.
        arrival_margin_s: time a derived step leaves after the slowest joint's sweep, for
            the position controller to settle within ``tolerance_rad`` (s). 0.03: snake5 and
            the legged bodies need 0.465 s to sweep 40 deg at 1.5 rad/s and arrive within
            0.5 s steps.
        tolerance_rad: a joint has reached its level when this close at the step's end (rad).
        max_tilt_rad: a trunk unit tilted more than this from upright means the body flipped.
        check_interval_steps: physics steps between failure checks during a step (-); 12 is
            20 Hz at PyBullet's 240 Hz, and keeps the checks under 5% of a snake5 step.
    """

    step_duration_s: float | None = None
    joint_speed_rad_s: float = 1.5
    arrival_margin_s: float = 0.03
    tolerance_rad: float = math.radians(4.0)
    max_tilt_rad: float = math.radians(60.0)
    check_interval_steps: int = 12

    def __post_init__(self) -> None:
        for name in ("joint_speed_rad_s", "tolerance_rad", "max_tilt_rad"):
            value = getattr(self, name)
            if not (value > 0 and math.isfinite(value)):
                raise ValueError(f"{name} must be positive, got {value}")
        if self.step_duration_s is not None and not (
            self.step_duration_s > 0 and math.isfinite(self.step_duration_s)
        ):
            raise ValueError(f"step_duration_s must be positive, got {self.step_duration_s}")
        if not (self.arrival_margin_s >= 0 and math.isfinite(self.arrival_margin_s)):
            raise ValueError(f"arrival_margin_s must not be negative, got {self.arrival_margin_s}")
        if self.check_interval_steps < 1:
            raise ValueError("check_interval_steps must be at least 1")

    def sweep_s(self, formation: Formation) -> tuple[float, str]:
        """The longest time a joint needs to cross its widest level span (s), and that joint:
        span over ``joint_speed_rad_s`` capped by the unit's speed limit."""
        times = [
            (
                (max(joint.levels_rad) - min(joint.levels_rad))
                / min(self.joint_speed_rad_s, joint.spec.velocity_rad_s),
                joint.name,
            )
            for joint in formation.joints
        ]
        return max(times, default=(0.0, ""))

    def step_duration_for(self, formation: Formation) -> float:
        """The step duration (s) for ``formation``: ``step_duration_s`` when set, else the
        slowest sweep plus ``arrival_margin_s``, rounded up to a multiple of 0.05 s.

        Raises:
            ValueError: a set ``step_duration_s`` is shorter than the slowest sweep; the
                message says which setting to change and to what.
        """
        sweep, joint = self.sweep_s(formation)
        derived = STEP_GRID_S * math.ceil((sweep + self.arrival_margin_s) / STEP_GRID_S - 1e-9)
        if self.step_duration_s is None:
            return max(derived, STEP_GRID_S)
        if sweep > self.step_duration_s:
            raise ValueError(
                f"{formation.name}: joint {joint} needs {sweep:.2f} s to cross its levels at "
                f"{self.joint_speed_rad_s} rad/s, more than lower_agent.step_duration_s="
                f"{self.step_duration_s}; set lower_agent.step_duration_s to at least "
                f"{derived:.2f} (or leave it unset to derive it from the formation)"
            )
        return self.step_duration_s


@dataclass(frozen=True)
class Outcome:
    """Result of one commanded posture.

    Attributes:
        pose: body pose at the end of the step (or when it failed).
        failure: why the lower agent failed, or None when it succeeded.
        contacts: which units touched the ground at each failure check of the step,
            (checks, units) bool, units in the formation's order: the step's footfalls.
    """

    pose: BodyPose
    failure: str | None
    contacts: np.ndarray

    @property
    def failed(self) -> bool:
        return self.failure is not None


class LowerAgent:
    """Executes postures on one simulation.

    Args:
        sim: the simulation of ``formation``.
        config: timing and failure rules.
    """

    def __init__(self, *, sim: BulletSimulation, config: LowerAgentConfig) -> None:
        self.sim = sim
        self.formation = sim.formation
        self.config = config
        self.step_duration_s = config.step_duration_for(self.formation)
        """Duration of one upper-agent step (s)."""
        self.estimator = BodyPoseEstimator(formation=self.formation)
        self.physics_steps = max(1, round(self.step_duration_s / sim.settings.time_step_s))
        # Only a legged body's trunk must stay off the ground; a snake's trunk is all of it.
        legged = bool(self.formation.legs)
        self._trunk_names = {u.name for u in self.formation.trunk_units} if legged else set()

    def pose(self) -> BodyPose:
        """The body's pose now."""
        return self.estimator.trunk_pose(*self.sim.unit_states(self.estimator.trunk_rows))

    def execute(
        self, levels: np.ndarray, *, on_physics_step: Callable[[], None] | None = None
    ) -> Outcome:
        """Move to the posture ``levels`` (J,) of level indices within one step.

        ``on_physics_step``, if given, is called after every physics step (to film it)."""
        targets = np.array(self.formation.posture_rad(levels))
        self.sim.command(targets, speed_rad_s=self.config.joint_speed_rad_s)
        interval = self.config.check_interval_steps
        contacts: list[np.ndarray] = []
        done = 0
        while done < self.physics_steps:
            chunk = min(interval, self.physics_steps - done)
            if on_physics_step is None:
                self.sim.step(chunk)
            else:
                for _ in range(chunk):
                    self.sim.step()
                    on_physics_step()
            done += chunk
            pose, failure = self.check(contacts)
            if failure is not None:
                return Outcome(pose, failure, self._stacked(contacts))
        errors = np.abs(self.sim.joint_positions() - targets)
        if np.any(errors > self.config.tolerance_rad):
            worst = int(np.argmax(errors))
            name = self.formation.joints[worst].name
            failure = f"joint {name} missed its level by {math.degrees(errors[worst]):.1f} deg"
            return Outcome(pose, failure, self._stacked(contacts))
        return Outcome(pose, None, self._stacked(contacts))

    def _stacked(self, contacts: list[np.ndarray]) -> np.ndarray:
        return np.array(contacts, dtype=bool).reshape(-1, len(self.formation.unit_index))

    def check(self, contacts: list[np.ndarray]) -> tuple[BodyPose, str | None]:
        """The body's pose now, and why it has failed, if it has (non-finite, flipped, a
        legged trunk on the ground; the joints' arrival is :meth:`execute`'s to judge);
        appends the units touching the ground now to ``contacts`` (once the body is known to
        be upright and finite)."""
        # The trunk's state only: a non-finite value anywhere in an articulated body reaches
        # every link within one step.
        pose = self.pose()
        if not all(map(math.isfinite, (pose.x_m, pose.y_m, pose.heading_rad, pose.max_tilt_rad))):
            return pose, "physics state is not finite"
        if pose.max_tilt_rad > self.config.max_tilt_rad:
            return pose, f"body flipped (tilt {math.degrees(pose.max_tilt_rad):.0f} deg)"
        touching = self.sim.ground_contacts()
        row = np.zeros(len(self.formation.unit_index), dtype=bool)
        row[[self.formation.unit_index[name] for name in touching]] = True
        contacts.append(row)
        if self._trunk_names & touching:
            return pose, "trunk touched the ground"
        return pose, None
