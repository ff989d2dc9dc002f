"""The CMA-ES reference gait of a formation under the training defaults, searched or cached.

Usage: .venv/bin/python tools/reference_search.py FORMATION [--preset NAME] [--world WORLD]
[--budget-trials N] [--seed S] [--workers N] [--ship]

The rules are those ``qdsega train --preset NAME`` uses (trial length, lower agent, physics;
every shipped preset has the same ones), in ``--world`` (a shipped world's name or a world file;
default the flat plane, as the benchmark reads it) under its light where it names one. The
result is cached (``$QDSEGA_CACHE/references``, default ``~/.cache/qdsega/references``), so a
second call with the same arguments prints the stored search at once. ``--ship`` also copies it into
``qdsega/baselines/references/``, where ``qdsega evaluate`` and ``qdsega bench`` find it on
every machine with the same PyBullet version.
"""

from __future__ import annotations

import argparse
import math
import shutil
from pathlib import Path

from qdsega.baselines.reference_search import DEFAULT_BUDGET_TRIALS, SHIPPED_DIR, reference_gait
from qdsega.bench.tasks import FLAT, read_world
from qdsega.description import load_formation, resolve_formation
from qdsega.training.config import resolve_config


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("formation", type=Path, help="formation YAML file or shipped name")
    parser.add_argument("--preset", help="training preset whose rules apply (default: default)")
    parser.add_argument(
        "--world", default=FLAT, help="shipped world name or world file (default: flat)"
    )
    parser.add_argument("--budget-trials", type=int, default=DEFAULT_BUDGET_TRIALS)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument(
        "--ship", action="store_true", help="copy it into qdsega/baselines/references/"
    )
    args = parser.parse_args()
    try:
        config = resolve_config(preset=args.preset)
        world = read_world(args.world)
        formation = world.lights(load_formation(resolve_formation(args.formation)))
        result = reference_gait(
            formation,
            rules=config.rules(world),
            budget_trials=args.budget_trials,
            seed=args.seed,
            workers=args.workers,
        )
    except ValueError as exc:  # QdsegaError (FormationError, ConfigError) included
        parser.error(str(exc))
    gait = result.params
    print(
        f"{formation.name}: {result.kind} reference {result.distance_m:.4f} m in "
        f"{len(result.postures)} steps, period {gait.period_steps} steps; search of "
        f"{result.evaluations} trials ({result.budget_steps} steps budgeted) took "
        f"{result.wall_s:.1f} s"
    )
    print("joint           offset  amplitude  phase (deg)")
    for joint, offset, amplitude, phase in zip(
        formation.joints, gait.offset_rad, gait.amplitude_rad, gait.phase_rad, strict=True
    ):
        print(
            f"{joint.name:<14} {math.degrees(offset):7.1f} {math.degrees(amplitude):10.1f} "
            f"{math.degrees(phase):6.0f}"
        )
    print("postures (level indices), one period:")
    for row in result.postures[: gait.period_steps]:
        print("  " + " ".join(str(level) for level in row))
    print(f"cached in {result.file}")
    if args.ship and result.file is not None and result.file.parent != SHIPPED_DIR:
        shutil.copyfile(result.file, SHIPPED_DIR / result.file.name)
        print(f"shipped as {SHIPPED_DIR / result.file.name}")


if __name__ == "__main__":
    main()
