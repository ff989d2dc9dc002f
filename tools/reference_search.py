"""The CMA-ES reference gait of a formation under the training defaults, searched or cached.

Usage: .venv/bin/python tools/reference_search.py FORMATION.yaml [--budget-trials N] [--seed S]
[--workers N]

The rules are those ``qdsega train`` uses by default (trial length, lower agent, physics); the
result is cached (``$QDSEGA_CACHE/references``, default ``~/.cache/qdsega/references``), so
a second call with the same arguments prints the stored search at once.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from qdsega.description import load_formation
from qdsega.training.config import TrainingConfig
from qdsega.training.reference_search import DEFAULT_BUDGET_TRIALS, reference_gait
from qdsega.training.worlds import task_of


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("formation", type=Path, help="formation YAML file")
    parser.add_argument("--budget-trials", type=int, default=DEFAULT_BUDGET_TRIALS)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    config = TrainingConfig()
    try:
        formation = load_formation(args.formation)
        result = reference_gait(
            formation,
            task=task_of(config),
            lower_agent=config.lower_agent,
            physics=config.physics,
            budget_trials=args.budget_trials,
            seed=args.seed,
            workers=args.workers,
        )
    except ValueError as exc:  # FormationError included
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


if __name__ == "__main__":
    main()
