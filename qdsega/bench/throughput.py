"""Throughput figures for the benchmark's report: how fast each world steps on this machine.

* raw physics: ``stepSimulation`` calls per second while the exact environment walks a
  reference gait (a stopwatch around the engine's step, so physics and overhead are measured on
  the same states);
* exact environment: upper-agent steps per second of
  :class:`qdsega.locomotion.env.LocomotionEnv` (lower agent, checks, pose, reward);
* table environment: steps per second of ``qdsega/TableLocomotion-v0`` in the MSM, and over a
  memo table whose pairs are already measured; the memo speed-up is that rate over the exact
  environment's.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from qdsega.baselines import classic_gaits
from qdsega.description import load_formation, resolve_formation
from qdsega.locomotion.table_env import TableLocomotionEnv


class PhysicsStopwatch:
    """Wraps a simulation's ``step(steps)``: the physics time and steps it has spent."""

    def __init__(self, step: Callable[[int], None]) -> None:
        self._step = step
        self.reset()

    def reset(self) -> None:
        self.seconds, self.steps = 0.0, 0

    def __call__(self, steps: int = 1) -> None:
        start = time.perf_counter()
        self._step(steps)
        self.seconds += time.perf_counter() - start
        self.steps += steps


def exact_rates(formation_name: str, *, steps: int = 30) -> tuple[float, float]:
    """Raw physics steps/s and exact-environment upper-agent steps/s of the formation walking
    its default reference gait for ``steps`` upper-agent steps."""
    from qdsega.locomotion.env import LocomotionEnv  # starts PyBullet: only here

    formation = load_formation(resolve_formation(formation_name))
    env = LocomotionEnv(formation=formation)
    stopwatch = PhysicsStopwatch(env.sim.step)
    # the stopwatch wraps this instance's step, so that every physics step is timed
    env.sim.step = stopwatch  # type: ignore[method-assign]
    try:
        env.reset(seed=0)
        stopwatch.reset()
        start = time.perf_counter()
        for posture in classic_gaits.default_gait(formation, steps=steps):
            _, _, terminated, truncated, _ = env.step(posture)
            if terminated or truncated:
                break
        total = time.perf_counter() - start
    finally:
        env.close()
    return stopwatch.steps / stopwatch.seconds, steps / total


def table_rate(formation_name: str, sim: str, *, steps: int = 30, repeats: int = 20) -> float:
    """Steps/s of the table environment walking the default reference gait ``repeats`` times
    (memo: its pairs measured before the clock starts)."""
    formation = load_formation(resolve_formation(formation_name))
    env = TableLocomotionEnv(formation=formation, sim=sim)
    gait = np.asarray(classic_gaits.default_gait(formation, steps=steps))
    try:
        for round_ in range(repeats + 1):
            if round_ == 1:
                start = time.perf_counter()
            env.reset(seed=0)
            for posture in gait:
                _, _, terminated, truncated, _ = env.step(posture)
                if terminated or truncated:
                    break
        return repeats * steps / (time.perf_counter() - start)
    finally:
        env.close()


def throughput() -> list[tuple[str, str, float]]:
    """``(figure, formation, steps per second)`` rows for the report."""
    rows: list[tuple[str, str, float]] = []
    for name in ("snake5", "legged12"):
        raw, exact = exact_rates(name)
        rows += [
            ("raw physics steps/s (240 Hz)", name, raw),
            ("exact environment, upper-agent steps/s", name, exact),
        ]
    memo = table_rate("snake5", "memo")
    rows += [
        ("table environment (MSM), steps/s", "legged12", table_rate("legged12", "msm")),
        ("table environment (memo, measured pairs), steps/s", "snake5", memo),
        ("memo speed-up over the exact environment (x)", "snake5", memo / rows[1][2]),
    ]
    return rows
