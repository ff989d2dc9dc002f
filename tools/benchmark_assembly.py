"""Benchmark: assembly time of every shipped formation and PyBullet steps/s while it walks.

Usage: .venv/bin/python tools/benchmark_assembly.py [--seconds 5]

Stepping is measured with every joint driven by a square wave between its first two levels
(1 s period), the formation's own friction and the default PhysicsSettings.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from qdsega import ASSEMBLIES_DIR
from qdsega.assembly import assemble
from qdsega.description import load_formation
from qdsega.simulation import PhysicsSettings
from qdsega.simulation.bullet import BulletSimulation


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0, help="simulated time per formation")
    parser.add_argument("--repeats", type=int, default=5, help="assemblies timed per formation")
    args = parser.parse_args()
    settings = PhysicsSettings()
    print(f"{'formation':<10} {'joints':>6} {'assemble_ms':>11} {'steps/s':>8}")
    for file in sorted(ASSEMBLIES_DIR.glob("*.yaml")):
        times = []
        for _ in range(args.repeats):
            start = time.perf_counter()
            formation = load_formation(file)
            robot = assemble(formation)
            times.append(1000 * (time.perf_counter() - start))
        with BulletSimulation(robot=robot, settings=settings) as sim:
            rest = np.array(formation.posture_rad(formation.rest_levels()))
            other = np.array(
                [j.levels_rad[min(1, len(j.levels_rad) - 1)] for j in formation.joints]
            )
            sim.reset(rest)
            steps = round(args.seconds / settings.time_step_s)
            half_period = round(0.5 / settings.time_step_s)
            start = time.perf_counter()
            for k in range(steps):
                if k % half_period == 0:
                    sim.command(other if (k // half_period) % 2 else rest)
                sim.step()
            rate = steps / (time.perf_counter() - start)
        median = statistics.median(times)
        print(f"{formation.name:<10} {len(formation.joints):>6} {median:>11.1f} {rate:>8.0f}")


if __name__ == "__main__":
    main()
