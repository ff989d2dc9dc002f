"""``qdsega train``: learn a formation's locomotion with QDSEGA; write a run folder."""

from __future__ import annotations

import argparse
import shutil
from functools import partial
from pathlib import Path

from qdsega.agent.config import PRESETS
from qdsega.description import resolve_formation
from qdsega.errors import FormationError
from qdsega.training.config import SIMULATORS, resolve_config
from qdsega.training.progress import ProgressDisplay
from qdsega.training.run import TrainingInterrupted, budget_overrides, resume, train

NAME = "train"
HELP = "learn locomotion with QDSEGA and write a run folder (or continue one with --resume)"
RUNS_DIR = Path("runs")
_RUN_OPTIONS = (
    "sim", "workers", "preset", "config", "seed", "out", "overwrite", "generations", "trials",
    "light_bearing_deg",
)  # fmt: skip
"""Options that configure a new run, which --resume does not take."""
"""Where run folders go when --out is not given."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("formation", type=Path, nargs="?", metavar="FORMATION.yaml")
    parser.add_argument(
        "--resume",
        type=Path,
        metavar="RUN",
        help="continue a stopped run from its last finished generation (no other options)",
    )
    parser.add_argument(
        "--sim",
        choices=SIMULATORS,
        default=None,
        help="world: msm (Minimal Simulation Model, legged only), memo (PyBullet "
        "transitions measured once each) or pybullet (every step simulated); default msm",
    )
    parser.add_argument(
        "--workers", type=int, metavar="N", help="processes measuring memo transitions"
    )
    parser.add_argument("--preset", help=f"one of {', '.join(PRESETS)}; default paper-legged")
    parser.add_argument("--config", type=Path, metavar="FILE.yaml", help="overrides (YAML)")
    parser.add_argument("--seed", type=int, help="random seed (default: the config's, 0)")
    parser.add_argument(
        "--out", type=Path, metavar="RUN", help="run folder (default runs/FORMATION-SIM-seedS)"
    )
    parser.add_argument(
        "--overwrite", action="store_true", help="delete an existing run folder --out first"
    )
    parser.add_argument("--generations", type=int, metavar="N", help="generations to run")
    parser.add_argument("--trials", type=int, metavar="N", help="trials per generation")
    parser.add_argument(
        "--light-bearing-deg", type=float, metavar="D", help="move the light to this bearing"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress display")


def run(args: argparse.Namespace) -> int:
    progress = None if args.quiet else ProgressDisplay()
    if args.resume is not None:
        given = [
            f"--{k.replace('_', '-')}"
            for k in _RUN_OPTIONS
            if getattr(args, k) not in (None, False)
        ]
        if args.formation is not None or given:
            extra = ", ".join(([str(args.formation)] if args.formation else []) + given)
            raise FormationError(f"--resume continues a run as it was configured; drop {extra}")
        out = args.resume
        start = partial(resume, out, progress=progress)
    else:
        if args.formation is None:
            raise FormationError("give a FORMATION.yaml to train, or --resume RUN")
        args.formation = resolve_formation(args.formation)
        preset = args.preset or "paper-legged"
        config = resolve_config(preset=preset, file=args.config, overrides=_overrides(args))
        out = args.out or RUNS_DIR / f"{args.formation.stem}-{config.sim}-seed{config.seed}"
        if args.overwrite and out.is_dir():
            if not (out / "config.yaml").is_file():
                raise FormationError(
                    "--overwrite deletes run folders only (no config.yaml)", file=out
                )
            shutil.rmtree(out)
        start = partial(train, args.formation, config, out, progress=progress)
    try:
        summary = start()
    except TrainingInterrupted as stop:
        print(
            f"qdsega train: interrupted; generation {stop.completed} is saved, continue with: "
            f"qdsega train --resume {stop.run}"
        )
        return 130
    finally:
        if progress is not None:
            progress.close()
    facts = f"{summary['distance_m']:.4f} m"
    if summary["sim"] == "memo":
        facts += f" with exact physics (the table predicted {summary['greedy_distance']:.4f} m)"
    if summary["optimum"] is not None:
        facts += f", optimum {summary['optimum']:.4f} m ({summary['greedy_over_optimum']:.3f})"
    print(
        f"{summary['formation']}: greedy policy {facts}, {summary['env_steps']} steps in "
        f"{summary['wall_s']:.1f} s -> {out}"
    )
    return 0


def _overrides(args: argparse.Namespace) -> dict[str, object]:
    overrides = budget_overrides(generations=args.generations, trials=args.trials, seed=args.seed)
    overrides["sim"] = args.sim or "msm"
    if args.workers is not None:
        overrides["workers"] = args.workers
    if args.light_bearing_deg is not None:
        overrides["light_bearing_deg"] = args.light_bearing_deg
    return overrides
