"""``qdsega train``: learn a formation's locomotion with QDSEGA; write a run folder."""

from __future__ import annotations

import argparse
from functools import partial
from pathlib import Path
from typing import Any

from qdsega.adaptation.adapt import is_adaptation, warm_start_from
from qdsega.agent.config import PRESETS
from qdsega.description import (
    load_formation,
    named_world,
    resolve_formation,
)
from qdsega.errors import ConfigError
from qdsega.folder_names import default_folder
from qdsega.training.config import SIMULATORS, TrainingConfig, resolve_config
from qdsega.training.progress import ProgressDisplay
from qdsega.training.run import (
    PREDICTION_TOLERANCE,
    TrainingInterrupted,
    budget_overrides,
    resume,
    train,
)
from qdsega.training.run_folder import RunFolder

NAME = "train"
HELP = "learn locomotion with QDSEGA and write a run folder (or continue one with --resume)"
"""Where run folders go when --out is not given."""
_RUN_OPTIONS = (
    "sim", "workers", "ray", "preset", "config", "seed", "out", "overwrite", "generations",
    "trials", "light_bearing_deg", "warm_start", "allow_unmatched", "world",
)  # fmt: skip
"""Options that configure a new run, which --resume does not take."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("formation", type=Path, nargs="?", metavar="FORMATION.yaml")
    parser.add_argument(
        "--resume",
        type=Path,
        metavar="RUN",
        help="continue a stopped run from its last finished generation (no other options); "
        "of a finished run, print its result and succeed",
    )
    parser.add_argument(
        "--sim",
        choices=SIMULATORS,
        default=None,
        help="simulator: msm (Minimal Simulation Model, legged only), memo (PyBullet "
        "transitions measured once each) or pybullet (every step simulated); default: the "
        "--config file's, else msm",
    )
    parser.add_argument(
        "--workers", type=int, metavar="N", help="processes measuring memo transitions"
    )
    parser.add_argument(
        "--ray",
        metavar="local|ADDRESS",
        help="the workers are Ray actors: local starts Ray on this machine, an address joins a "
        "cluster (pip install -e '.[ray]' in the checkout); the run learns the same",
    )
    parser.add_argument(
        "--preset",
        help=f"one of {', '.join(PRESETS)}; default: the --config file's, else the body's "
        "(paper-legged in the MSM; else memo-legged for legs, paper-snake without)",
    )
    parser.add_argument(
        "--config",
        type=Path,
        metavar="FILE.yaml",
        help="settings over the preset's, keys as in a run's config.yaml; flags override it",
    )
    parser.add_argument("--seed", type=int, help="random seed (default: the config's, 0)")
    parser.add_argument(
        "--out",
        type=Path,
        metavar="RUN",
        help="run folder (default runs/FORMATION[-WORLD]-SIM-seedS)",
    )
    parser.add_argument(
        "--overwrite", action="store_true", help="delete an existing run folder --out first"
    )
    parser.add_argument("--generations", type=int, metavar="N", help="generations to run")
    parser.add_argument("--trials", type=int, metavar="N", help="trials per generation")
    parser.add_argument(
        "--light-bearing-deg", type=float, metavar="D", help="move the light to this bearing"
    )
    parser.add_argument(
        "--world",
        metavar="NAME|FILE",
        help="the ground to learn on: a world file or a shipped name (flat, ice, slope, "
        "stairs, rubble, tunnel, corridor; docs/worlds.md); default flat",
    )
    parser.add_argument(
        "--warm-start",
        type=Path,
        metavar="RUN",
        help="start from a finished run's last population and Q-table, its joints matched to "
        "this formation's by name (a changed body relearns from what it knew); or from the "
        "gait qdsega adapt found for this formation",
    )
    parser.add_argument(
        "--allow-unmatched",
        action="store_true",
        help="with --warm-start: start even from a run sharing no joint name with FORMATION",
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
            raise ConfigError(f"--resume continues a run as it was configured; drop {extra}")
        out = args.resume
        folder = RunFolder(out)
        if folder.finished:  # nothing to resume: a script resuming whatever it finds goes on
            print(result_line(folder.read_summary(), out, finished=True))
            return 0
        start = partial(resume, out, progress=progress)
    else:
        if args.formation is None:
            raise ConfigError("give a FORMATION.yaml to train, or --resume RUN")
        args.formation = resolve_formation(args.formation)
        config = run_config(args)
        if config.ray is not None:  # refused here, before the run folder exists
            if config.sim != "memo":
                raise ConfigError("--ray measures memo transitions: it goes with --sim memo")
            from qdsega.workers.ray_cluster import connect

            connect(config.ray, cpus=config.workers)
        world = None if args.world is None else named_world(args.world)
        out = args.out or default_folder(
            args.formation.stem,
            world=None if world is None else world.file,
            settings=[config.sim],
            seed=config.seed,
        )
        if args.allow_unmatched and args.warm_start is None:
            raise ConfigError("--allow-unmatched goes with --warm-start RUN")
        warm_start = args.warm_start
        if warm_start is not None and is_adaptation(warm_start):
            warm_start = warm_start_from(warm_start, load_formation(args.formation))
        start = partial(
            train,
            args.formation,
            config,
            out,
            overwrite=args.overwrite,
            progress=progress,
            warm_start=warm_start,
            allow_unmatched=args.allow_unmatched,
            world=world,
        )
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
    print(result_line(summary, out))
    warning = prediction_warning(summary)
    if warning is not None:
        print(f"qdsega train: {warning}")
    return 0


def result_line(summary: dict[str, Any], out: Path, *, finished: bool = False) -> str:
    """The line that names a run's result, ending ``-> RUN``; ``finished``: said of a run that
    ``--resume`` found already finished."""
    facts = f"{summary['distance_m']:.4f} m"
    if summary["sim"] == "memo":
        facts += f" with exact physics (the table predicted {summary['greedy_distance']:.4f} m)"
    if summary["optimum"] is not None:
        facts += f", optimum {summary['optimum']:.4f} m ({summary['greedy_over_optimum']:.3f})"
    done = "the run is already finished, nothing to resume; its result: " if finished else ""
    return (
        f"{summary['formation']}: {done}greedy policy of generation "
        f"{summary['result_generation']} {facts}, {summary['env_steps']} steps in "
        f"{summary['wall_s']:.1f} s -> {out}"
    )


def prediction_warning(summary: dict[str, Any]) -> str | None:
    """What to say of a memo run whose table mispredicted its result by more than
    ``PREDICTION_TOLERANCE``, else None."""
    error = summary["prediction_error"]
    if summary["sim"] != "memo" or error is None or abs(error) <= PREDICTION_TOLERANCE:
        return None
    return (
        f"the table's prediction is {error:+.0%} off exact physics (more than "
        f"{PREDICTION_TOLERANCE:.0%}): the table did not hold where this run went (varied "
        "ground: docs/worlds.md); the distance above is exact physics"
    )


def run_config(args: argparse.Namespace) -> TrainingConfig:
    """The configuration of a new run: the preset (named, else the body's), then the
    ``--config`` file, then the flags that were given.

    Raises:
        ConfigError: unknown preset, bad configuration file or value.
        FormationError: a formation that does not load.
    """
    overrides = budget_overrides(generations=args.generations, trials=args.trials, seed=args.seed)
    for key in ("sim", "workers", "ray", "light_bearing_deg"):
        if getattr(args, key) is not None:
            overrides[key] = getattr(args, key)
    formation = load_formation(resolve_formation(args.formation))
    return resolve_config(
        preset=args.preset, file=args.config, overrides=overrides, formation=formation
    )
