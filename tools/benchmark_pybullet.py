"""Benchmark: exact-mode environment steps against raw stepSimulation for the same model.

Usage: .venv/bin/python tools/benchmark_pybullet.py [--formations snake5 legged12] [--steps 40]

The environment runs a reference gait (LocomotionEnv.step: lower agent, failure checks, body
pose, reward, exterior state) while a stopwatch around the engine's ``stepSimulation`` calls
records the time spent in physics. Physics and overhead are thus measured on the very same
states; comparing with a separate raw loop would compare different contact states (a robot
teleported into its posture is not one that settled and walked). The overhead is everything
that is not physics, relative to physics. Each run repeats ``--repeats`` times and the
fastest counts (the other core may be busy).
"""

from __future__ import annotations

import argparse
import math
import time

from qdsega.baselines import classic_gaits
from qdsega.bench.throughput import PhysicsStopwatch
from qdsega.description import load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.locomotion.env import LocomotionEnv, TaskConfig


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--formations", nargs="+", default=["snake5", "legged12"])
    parser.add_argument("--steps", type=int, default=40, help="upper-agent steps per loop")
    parser.add_argument("--repeats", type=int, default=3, help="runs of each loop")
    args = parser.parse_args()
    print(
        f"{'formation':<10} {'raw steps/s':>11} {'env steps/s':>11} {'overhead':>8} "
        f"{'upper steps/s':>13}"
    )
    for name in args.formations:
        formation = load_formation(ASSEMBLIES_DIR / f"{name}.yaml")
        task = TaskConfig(trial_steps=args.steps)
        postures = classic_gaits.default_gait(formation, steps=args.steps)
        env = LocomotionEnv(formation=formation, task=task)
        stopwatch = PhysicsStopwatch(env.sim.step)
        env.sim.step = stopwatch  # type: ignore[method-assign]
        best: tuple[float, float, int] = (math.inf, math.inf, 0)
        for _ in range(args.repeats):
            env.reset(seed=0)
            stopwatch.reset()
            start = time.perf_counter()
            for posture in postures:
                env.step(posture)
            total = time.perf_counter() - start
            best = min(best, (total, stopwatch.seconds, stopwatch.steps))
        env.close()
        total, physics_s, steps = best
        print(
            f"{name:<10} {steps / physics_s:>11.0f} {steps / total:>11.0f} "
            f"{total / physics_s - 1:>8.1%} {len(postures) / total:>13.1f}"
        )


if __name__ == "__main__":
    main()
