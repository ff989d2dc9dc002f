"""``qdsega bench``: QDSEGA against other learners, same tasks and budgets; BENCHMARKS.md."""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

from qdsega.errors import ConfigError
from qdsega.workers.ray_cluster import add_ray_option

NAME = "bench"
HELP = (
    "run every method on every task for several seeds and write OUT/BENCHMARKS.md and its "
    "figures (re-running continues; about 9 hours on 2 cores, --quick under a minute)"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--quick", action="store_true", help="tiny budgets: checks the pipeline in minutes"
    )
    parser.add_argument(
        "--out", type=Path, metavar="DIR",
        help="where runs, results and the report go (default benchmarks, with --quick "
        "runs/bench-quick; in a world other than flat, -WORLD appended)",
    )  # fmt: skip
    parser.add_argument("--jobs", type=int, default=2, metavar="N", help="runs at a time")
    add_ray_option(parser)
    parser.add_argument(
        "--report-only", action="store_true",
        help="run nothing: write OUT/BENCHMARKS.md from the runs finished so far",
    )  # fmt: skip
    parser.add_argument(
        "--world", metavar="WORLD",
        help="run the PyBullet tasks in this world, a world file or a shipped name (flat, ice, "
        "slope, stairs, rubble, tunnel, corridor; docs/worlds.md), leaving out the MSM task, "
        "which knows no terrain; default flat",
    )  # fmt: skip


def run(args: argparse.Namespace) -> int:
    from qdsega.bench.runner import run_bench
    from qdsega.bench.runs import bench_runs
    from qdsega.bench.tasks import FLAT, FULL, QUICK, STABLE_BASELINES, in_world, suffix
    from qdsega.progress import ProgressLine

    if args.jobs < 1:
        raise ConfigError(f"--jobs must be at least 1, got {args.jobs}")
    if args.ray is not None:  # refused here, before anything is written
        from qdsega.workers.ray_cluster import connect

        connect(args.ray)
    every = QUICK if args.quick else FULL
    tasks, left_out = in_world(every, args.world or FLAT)  # a bad world: WorldError, exit 2
    if not tasks:
        raise ConfigError(
            f"the MSM knows no terrain and every task is in it: none walks in {args.world}"
        )
    learners = sorted({m for t in tasks for m in t.methods if m in STABLE_BASELINES})
    if learners and importlib.util.find_spec("stable_baselines3") is None:
        raise ConfigError(
            f"the methods {', '.join(learners)} need stable-baselines3: "
            "pip install -e '.[bench]' in the checkout"
        )
    place = "" if tasks == every else suffix(args.world)
    out = args.out or Path(("runs/bench-quick" if args.quick else "benchmarks") + place)
    world = "" if args.world is None else f" --world {args.world}"
    command = "qdsega bench" + (" --quick" if args.quick else "") + world + f" --out {out}"
    command += " --report-only" if args.report_only else ""
    for task in left_out:
        why = "the MSM knows no terrain" if task.sim == "msm" else f"it walks in {task.world}"
        print(f"qdsega bench: {task.name} left out: {why}", flush=True)
    print(f"qdsega bench: {len(bench_runs(tasks))} runs -> {out}", flush=True)
    file, errors = run_bench(
        tasks,
        out,
        jobs=args.jobs,
        ray=args.ray,
        report_only=args.report_only,
        command=command,
        log=_log,
        progress=ProgressLine,
    )  # runs finished of all, with an ETA, on stderr
    print(f"qdsega bench: {len(errors)} runs failed -> {file}" if errors else f"-> {file}")
    return 1 if errors else 0


def _log(line: str) -> None:
    print(line, file=sys.stdout, flush=True)
