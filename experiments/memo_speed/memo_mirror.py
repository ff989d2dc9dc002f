"""Is PyBullet mirror-symmetric for a left-right symmetric legged body? A check.

Usage: .venv/bin/python experiments/memo_speed/memo_mirror.py [FORMATION] [--postures 10]
           [--seed 0] [--preset memo-legged]

A legged formation mirrored left to right is itself, with its k-th left leg in place of its
k-th right leg (legs are declared front to back on each side, and every leg's levels mean the
same on both sides: swing [forward, back], lift [down, up]). If physics were mirror-symmetric
too, the transition of the mirrored postures would be the mirrored move (the same ``dx``,
``-dy``, ``-dtheta``, the same failure), and memo mode could measure one of each pair (it does
not: a QDSEGA population holds hardly any posture's mirror image;
``docs/notes/2026-12-02-memo-speed.md``).

Draws ``--postures`` random sources and targets, measures every source -> target transition
and every mirrored one in PyBullet (the memo table's own measurement), and prints how far
each mirrored move is from the move it mirrors. A formation with joints outside its working
legs (a snake, a broken leg) or unequal sides is refused.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from qdsega.description import Formation, load_formation, resolve_formation
from qdsega.locomotion.memo import MeasuredTransitions
from qdsega.training.config import resolve_config


def mirror_permutation(formation: Formation) -> np.ndarray:
    """Index of each joint's mirror image in the posture vector, shape (J,)."""
    left, right = formation.legs_on("left"), formation.legs_on("right")
    names = [joint.name for joint in formation.joints]
    in_legs = {name for leg in formation.legs for name in (leg.swing_joint, leg.lift_joint)}
    if not left or len(left) != len(right) or set(names) != in_legs or formation.broken_legs:
        raise SystemExit(f"{formation.name}: no left-right mirror of its joints")
    partner: dict[str, str] = {}
    for a, b in zip(left, right, strict=True):
        for x, y in ((a.swing_joint, b.swing_joint), (a.lift_joint, b.lift_joint)):
            partner[x], partner[y] = y, x
    return np.array([names.index(partner[name]) for name in names])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("formation", nargs="?", default="legged12")
    parser.add_argument("--postures", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--preset", default="memo-legged")
    args = parser.parse_args()
    if args.postures < 1:
        parser.error(f"--postures must be at least 1, got {args.postures}")
    formation = load_formation(resolve_formation(args.formation))
    mirror = mirror_permutation(formation)
    config = resolve_config(preset=args.preset, overrides={"sim": "memo"})
    levels = np.array([len(joint.levels_rad) for joint in formation.joints])
    rng = np.random.default_rng(args.seed)
    sources = rng.integers(0, levels, size=(args.postures, len(levels)))
    targets = rng.integers(0, levels, size=(args.postures, len(levels)))
    memo = MeasuredTransitions(
        formation=formation, lower_agent=config.lower_agent, physics=config.physics, workers=2
    )
    start = time.perf_counter()
    try:
        plain = memo.transitions(sources, targets)
        mirrored = memo.transitions(sources[:, mirror], targets[:, mirror])
    finally:
        memo.close()
    wall = time.perf_counter() - start
    failed = np.stack([plain.failed.ravel(), mirrored.failed.ravel()])  # (2, pairs)
    both = ~failed.any(axis=0)
    print(
        f"{formation.name}: {memo.measured} transitions measured in {wall:.1f} s on 2 "
        f"workers; {failed.mean():.0%} fail"
    )
    print(f"failure agrees with the mirror's on {np.mean(failed[0] == failed[1]):.1%} of pairs")
    print(f"{both.sum()} pairs where neither fails:")
    print("| field | mean abs (plain) | median abs gap | 90th percentile gap | max gap |")
    print("|---|---|---|---|---|")
    for name, sign, unit in (("dx", 1, "m"), ("dy", -1, "m"), ("dtheta", -1, "rad")):
        a = getattr(plain, name).ravel()[both]
        b = sign * getattr(mirrored, name).ravel()[both]
        gap = np.abs(a - b)
        if not gap.size:
            print(f"| {name} ({unit}) | - | - | - | - |")
            continue
        print(
            f"| {name} ({unit}) | {np.abs(a).mean():.4f} | {np.median(gap):.4f} | "
            f"{np.quantile(gap, 0.9):.4f} | {gap.max():.4f} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
