"""Benchmark: assembly time of every shipped formation and PyBullet steps/s while it walks.

Usage: .venv/bin/python tools/benchmark_assembly.py [--seconds 5]

Stepping is measured while the formation walks its default scripted gait (the wave gait for
legged bodies, a serpenoid wave for snakes; a new posture every 0.5 s at 1.5 rad/s), with its
own friction and the default PhysicsSettings.
"""

from __future__ import annotations

import argparse
import statistics
import time

from qdsega.assembly import assemble
from qdsega.baselines import classic_gaits
from qdsega.description import load_formation
from qdsega.description.shipped import ASSEMBLIES_DIR
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
            sim.reset(formation.posture_rad(formation.rest_levels()))
            period = round(0.5 / settings.time_step_s)
            steps = round(args.seconds / settings.time_step_s)
            gait = classic_gaits.default_gait(formation, steps=steps // period + 1)
            start = time.perf_counter()
            for k in range(steps):
                if k % period == 0:
                    sim.command(formation.posture_rad(gait[k // period]), speed_rad_s=1.5)
                sim.step()
            rate = steps / (time.perf_counter() - start)
        median = statistics.median(times)
        print(f"{formation.name:<10} {len(formation.joints):>6} {median:>11.1f} {rate:>8.0f}")


if __name__ == "__main__":
    main()
