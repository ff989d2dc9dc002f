"""Reproduce the paper's first experiment (section 4.1) in the MSM, over several seeds.

Usage: .venv/bin/python experiments/msm/reproduce_msm.py [--seeds 0 1 2 3 4] [--out runs/reproduce]
           [--generations G] [--trials T] [--turn-bearing-deg 60] [--formation FILE]

Trains (in-process, :func:`qdsega.training.run.train_or_resume`) legged12 in the MSM with the
paper-legged preset for each seed into ``OUT/seedS``, then once more with the light 60 deg to
the left into ``OUT/turn``, and prints the result over the optimum per seed and the turn; all of
it also goes to ``OUT/reproduction.json``. A finished run folder is kept and an unfinished one
resumed, so running it again finishes what a crash left (delete ``OUT`` to start again).
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.training.config import resolve_config
from qdsega.training.run import budget_overrides, train_or_resume


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--formation", type=Path, default=ASSEMBLIES_DIR / "legged12.yaml")
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    parser.add_argument("--generations", type=int)
    parser.add_argument("--trials", type=int)
    parser.add_argument("--out", type=Path, default=Path("runs/reproduce"))
    parser.add_argument("--turn-bearing-deg", type=float, default=60.0)
    args = parser.parse_args()

    ratios = []
    for seed in args.seeds:
        overrides = budget_overrides(generations=args.generations, trials=args.trials, seed=seed)
        config = resolve_config(preset="paper-legged", overrides=overrides)
        s = train_or_resume(args.formation, config, args.out / f"seed{seed}")
        ratios.append(s["greedy_over_optimum"])
        print(
            f"seed {seed}: greedy {s['greedy_distance']:.4f} m / optimum {s['optimum']:.4f} m "
            f"= {s['greedy_over_optimum']:.3f} ({s['env_steps']} steps, {s['wall_s']:.1f} s)",
            flush=True,
        )
    passed = sum(r >= 0.95 for r in ratios)
    print(f"seeds at >= 0.95 of the optimum: {passed} of {len(ratios)}")

    overrides = budget_overrides(
        generations=args.generations, trials=args.trials, seed=args.seeds[0]
    )
    overrides["light_bearing_deg"] = args.turn_bearing_deg
    config = resolve_config(preset="paper-legged", overrides=overrides)
    s = train_or_resume(args.formation, config, args.out / "turn")
    lx, ly = s["light_xy"]
    straight = math.hypot(lx, ly) - math.hypot(lx - s["optimum"], ly)
    print(
        f"light at {args.turn_bearing_deg:g} deg: greedy covers {s['greedy_distance']:.4f} m "
        f"toward it (walking straight at best: {straight:.4f} m), final heading "
        f"{s['final_heading_deg']:.1f} deg"
    )
    (args.out / "reproduction.json").write_text(
        json.dumps({"ratios": ratios, "passed": passed, "turn": s}, indent=2) + "\n",
        encoding="utf-8",
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
