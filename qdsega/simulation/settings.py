"""Physics settings: the one place that fixes PyBullet's time step and solver."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, kw_only=True)
class PhysicsSettings:
    """PyBullet engine parameters shared by every simulation.

    Attributes:
        time_step_s: physics time step (s); PyBullet's default 1/240 s.
        solver_iterations: constraint-solver iterations per step (-). Fewer is faster (20 runs
            legged12 about 1.5x faster) but the friction constraints then converge less: a
            snake's serpentine wave covers about 40% less ground at 20 than at 50 (PyBullet's
            default), so 50 it is.
        gravity_m_s2: downward gravitational acceleration (m/s^2).
        ground_friction: lateral friction of the ground plane (-); Bullet multiplies it with
            each link's own coefficient, so 1.0 leaves the formation's values in charge.
        self_collision: collide non-adjacent units of the same robot (parent-child pairs never
            collide: their boxes touch at the joint).
        position_gain: position-control gain ``kp`` of the joint motors (-).
        deterministic_pairs: solve contacts in a fixed order of overlapping pairs. Without it
            a pair made during a fall (a trunk touching the ground) survives ``restoreState``
            and reorders the solver's constraints, so the same snapshot replays differently
            (by about 1e-6) after a fall than before: runs would depend on what a worker
            measured earlier. It changes the solver's order, so it changes the physics
            (snake5's 4-step demo gait covers 0.71 m with it, 0.56 m without).
    """

    time_step_s: float = 1.0 / 240.0
    solver_iterations: int = 50
    gravity_m_s2: float = 9.81
    ground_friction: float = 1.0
    self_collision: bool = True
    position_gain: float = 0.3
    deterministic_pairs: bool = True

    def __post_init__(self) -> None:
        if not self.time_step_s > 0:
            raise ValueError(f"time_step_s must be positive, got {self.time_step_s}")
        if self.solver_iterations < 1:
            raise ValueError(f"solver_iterations must be >= 1, got {self.solver_iterations}")
        if not 0 < self.position_gain <= 1:
            raise ValueError(f"position_gain must be in (0, 1], got {self.position_gain}")
