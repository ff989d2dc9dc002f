"""Fuzz the whole pipeline with random valid formations: each is written as YAML, read,
assembled, loaded in PyBullet and left to rest for 1 s in its rest posture; it must stay finite
and move less than 0.2 m.

Usage: .venv/bin/python tools/random_formations.py N [--seed S]

Prints one line per failure and a summary; exits with status 1 if any formation failed. The
formations come from ``qdsega.description.random_formation`` (chains, trees, legged bodies).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

from qdsega.assembly import assemble
from qdsega.description import Formation, load_formation
from qdsega.description.random_formation import random_formation
from qdsega.errors import FormationError
from qdsega.simulation.bullet import BulletSimulation

REST_S = 1.0
"""Simulated rest after the robot is placed (s)."""

MAX_MOVE_M = 0.2
"""Largest distance the root unit may travel while it rests (m). Bodies settle and some tip
over (seed 1: at most 0.06 m in 300 formations); an unstable simulation flies off."""


def check(formation: Formation) -> str | None:
    """What is wrong with ``formation`` at rest in PyBullet, or None."""
    with BulletSimulation(robot=assemble(formation)) as sim:
        rest = formation.posture_rad(formation.rest_levels())
        sim.reset(rest)
        start, _ = sim.base_pose()
        sim.step(round(REST_S / sim.settings.time_step_s))
        end, _ = sim.base_pose()
        positions, orientations = sim.unit_states()
        if not (np.all(np.isfinite(positions)) and np.all(np.isfinite(orientations))):
            return "NaN in the simulation"
        moved = float(np.linalg.norm(end - start))
        if moved > MAX_MOVE_M:
            return f"moved {moved:.3f} m at rest"
    return None


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("count", type=int, metavar="N", help="formations to try")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    start = time.perf_counter()
    failures = units = joints = legs = 0
    with tempfile.TemporaryDirectory(prefix="qdsega-random-") as folder:
        for k in range(args.count):
            data = random_formation(rng, name=f"random{k}")
            file = Path(folder) / f"random{k}.yaml"
            file.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
            try:
                formation = load_formation(file)
                problem = check(formation)
            except FormationError as exc:
                problem = f"refused: {exc}"
            else:
                units += len(formation.units)
                joints += len(formation.joints)
                legs += len(formation.legs)
            if problem is not None:
                failures += 1
                print(f"random{k} (seed {args.seed}): {problem}", file=sys.stderr)
    elapsed = time.perf_counter() - start
    print(
        f"{args.count} random formations ({units} units, {joints} joints, {legs} legs), "
        f"{failures} failures, {elapsed:.1f} s"
    )
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
