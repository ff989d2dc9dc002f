"""Benchmark: exact-mode environment steps against raw stepSimulation for the same model.

Usage: .venv/bin/python tools/benchmark_pybullet.py [--formations snake5 legged12] [--steps 40]

Both loops command the same posture sequence (a reference gait) with the same step duration;
"raw" only commands the joints and steps the physics, "env" runs LocomotionEnv.step (lower
agent, failure checks, body pose, reward, exterior state). The overhead is everything that is
not physics. Each loop runs ``--repeats`` times, alternating, and the fastest run counts (the
other core may be busy).
"""

from __future__ import annotations

import argparse
import math
import time

from qdsega import ASSEMBLIES_DIR
from qdsega.assembly import assemble
from qdsega.description import load_formation
from qdsega.locomotion import reference_gaits
from qdsega.locomotion.env import LocomotionEnv, TaskConfig
from qdsega.simulation.bullet import BulletSimulation


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
        postures = reference_gaits.default_gait(formation, steps=args.steps)
        env = LocomotionEnv(formation=formation, task=task)
        physics_per_step = env.lower_agent.physics_steps
        speed = task.lower_agent.joint_speed_rad_s
        env_time = raw_time = math.inf
        with BulletSimulation(robot=assemble(formation)) as sim:
            for _ in range(args.repeats):
                env.reset(seed=0)
                start = time.perf_counter()
                for posture in postures:
                    env.step(posture)
                env_time = min(env_time, time.perf_counter() - start)
                sim.reset(formation.posture_rad(formation.rest_levels()))
                start = time.perf_counter()
                for posture in postures:
                    sim.command(formation.posture_rad(posture), speed_rad_s=speed)
                    sim.step(physics_per_step)
                raw_time = min(raw_time, time.perf_counter() - start)
        env.close()
        total = physics_per_step * len(postures)
        print(
            f"{name:<10} {total / raw_time:>11.0f} {total / env_time:>11.0f} "
            f"{env_time / raw_time - 1:>8.1%} {len(postures) / env_time:>13.1f}"
        )


if __name__ == "__main__":
    main()
