"""``qdsega train``: learn a formation's locomotion with QDSEGA; write a run folder."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from qdsega.agent.config import PRESETS
from qdsega.training.config import SIMULATORS, resolve_config
from qdsega.training.run import budget_overrides, train

NAME = "train"
HELP = "learn locomotion with QDSEGA and write a run folder"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("formation", type=Path, metavar="FORMATION.yaml")
    parser.add_argument(
        "--sim",
        choices=SIMULATORS,
        default="msm",
        help="world: msm (Minimal Simulation Model, legged only), memo (PyBullet "
        "transitions measured once each) or pybullet (every step simulated); default msm",
    )
    parser.add_argument(
        "--workers", type=int, metavar="N", help="processes measuring memo transitions"
    )
    parser.add_argument("--preset", choices=sorted(PRESETS), default="paper-legged")
    parser.add_argument("--config", type=Path, metavar="FILE.yaml", help="overrides (YAML)")
    parser.add_argument("--seed", type=int, help="random seed (default: the config's, 0)")
    parser.add_argument("--out", type=Path, default=Path("runs/latest"), metavar="RUN")
    parser.add_argument("--generations", type=int, metavar="N", help="generations to run")
    parser.add_argument("--trials", type=int, metavar="N", help="trials per generation")
    parser.add_argument(
        "--light-bearing-deg", type=float, metavar="D", help="move the light to this bearing"
    )
    parser.add_argument("--quiet", action="store_true", help="no per-generation lines")


def run(args: argparse.Namespace) -> int:
    overrides = budget_overrides(generations=args.generations, trials=args.trials, seed=args.seed)
    overrides["sim"] = args.sim
    if args.workers is not None:
        overrides["workers"] = args.workers
    if args.light_bearing_deg is not None:
        overrides["light_bearing_deg"] = args.light_bearing_deg
    config = resolve_config(preset=args.preset, file=args.config, overrides=overrides)
    log = None if args.quiet else (lambda line: print(line, file=sys.stderr))
    summary = train(args.formation, config, args.out, log=log)
    oracle = ""
    if summary["optimum"] is not None:
        oracle = f", optimum {summary['optimum']:.4f} m ({summary['greedy_over_optimum']:.3f})"
    print(
        f"{summary['formation']}: greedy {summary['greedy_distance']:.4f} m{oracle}, "
        f"{summary['env_steps']} steps in {summary['wall_s']:.1f} s -> {args.out}"
    )
    return 0
