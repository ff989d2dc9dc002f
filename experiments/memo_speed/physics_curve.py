"""What cheaper physics settings cost in accuracy: memo transitions measured at each setting.

Usage: .venv/bin/python experiments/memo_speed/physics_curve.py [FORMATION] [--postures 12]
           [--seed 0] [--preset memo-legged] [--settings 240:50,240:20,120:50,120:20]

Draws ``--postures`` random sources and targets and measures every source -> target
transition (the memo table's own measurement, one worker) at each setting ``HZ:ITERATIONS``
(physics rate, solver iterations per step; the first is the reference, PyBullet's and the
toolkit's default 240:50). Prints, per setting, the transitions measured per second and how
far its moves are from the reference's: failures that agree, and the forward (dx, m) and
heading (dtheta, rad) gaps among the pairs where neither fails. A cheaper setting changes
the physics for the whole run (memo table, exact trials and references alike), so what it
buys is speed, and what it costs is this gap to the default physics.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import numpy as np

from qdsega.description import load_formation, resolve_formation
from qdsega.locomotion.memo import MeasuredTransitions
from qdsega.training.config import resolve_config


def parse_settings(text: str) -> list[tuple[float, int]]:
    """``"240:50,120:20"`` -> [(240.0, 50), (120.0, 20)] (Hz, solver iterations)."""
    settings = []
    for item in text.split(","):
        hz, _, iterations = item.partition(":")
        try:
            rate, count = float(hz), int(iterations)
        except ValueError:
            raise SystemExit(f"--settings: {item!r} is not HZ:ITERATIONS") from None
        if not rate > 0 or count < 1:
            raise SystemExit(f"--settings: {item!r} needs HZ > 0 and ITERATIONS >= 1")
        settings.append((rate, count))
    return settings


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("formation", nargs="?", default="legged12")
    parser.add_argument("--postures", type=int, default=12)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--preset", default="memo-legged")
    parser.add_argument("--settings", default="240:50,240:20,120:50,120:20")
    args = parser.parse_args()
    if args.postures < 1:
        parser.error(f"--postures must be at least 1, got {args.postures}")
    settings = parse_settings(args.settings)
    formation = load_formation(resolve_formation(args.formation))
    config = resolve_config(preset=args.preset, overrides={"sim": "memo"})
    levels = np.array([len(joint.levels_rad) for joint in formation.joints])
    rng = np.random.default_rng(args.seed)
    sources = rng.integers(0, levels, size=(args.postures, len(levels)))
    targets = rng.integers(0, levels, size=(args.postures, len(levels)))
    reference = None  # the first setting's table
    print(f"{formation.name}: {args.postures**2} random transitions per setting, one worker")
    print(
        "| physics (Hz : solver iterations) | transitions/s | failure agrees | mean \\|dx\\| (m) "
        "| dx gap: median / 90th pct (m) | dtheta gap: median / 90th pct (rad) |"
    )
    print("|---|---|---|---|---|---|")
    for hz, iterations in settings:
        physics = replace(config.physics, time_step_s=1.0 / hz, solver_iterations=iterations)
        memo = MeasuredTransitions(
            formation=formation, lower_agent=config.lower_agent, physics=physics, workers=1
        )
        start = time.perf_counter()
        try:
            table = memo.transitions(sources, targets)
        finally:
            memo.close()
        rate = memo.measured / (time.perf_counter() - start)
        reference = reference or table
        both = ~(table.failed | reference.failed)
        dx = np.abs(table.dx - reference.dx)[both]
        dtheta = np.abs(table.dtheta - reference.dtheta)[both]
        gaps = [
            f"{np.median(g):.4f} / {np.percentile(g, 90):.4f}" if g.size else "-"
            for g in (dx, dtheta)
        ]
        agree = np.mean(table.failed == reference.failed)
        moving = np.abs(table.dx[~table.failed])
        mean_dx = float(np.mean(moving)) if moving.size else 0.0
        print(
            f"| {hz:g} : {iterations} | {rate:.1f} | {agree:.1%} | {mean_dx:.4f} "
            f"| {gaps[0]} | {gaps[1]} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
