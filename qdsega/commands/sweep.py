"""``qdsega sweep``: train and evaluate a grid of runs, then write one summary table."""

from __future__ import annotations

import argparse
from pathlib import Path

from qdsega.errors import ConfigError
from qdsega.progress import ProgressLine
from qdsega.sweep import SweepRun, read_grid, run_sweep
from qdsega.workers.ray_cluster import add_ray_option

NAME = "sweep"
HELP = (
    "train and evaluate formations x worlds x seeds x presets x configs from GRID.yaml, each "
    "into its own run folder; write OUT/sweep.csv and OUT/sweep.md (re-running resumes)"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "grid", type=Path, metavar="GRID.yaml", help="the grid (see docs/commands.md)"
    )
    parser.add_argument(
        "--out", type=Path, metavar="DIR", help="where the runs and the table go (default "
        "runs/GRID)"
    )  # fmt: skip
    parser.add_argument(
        "--jobs", type=int, default=1, metavar="N", help="runs at a time on local processes"
    )
    add_ray_option(parser)


def run(args: argparse.Namespace) -> int:
    if args.jobs < 1:
        raise ConfigError(f"--jobs must be at least 1, got {args.jobs}")
    if args.ray is not None:  # refused here, before anything is written
        from qdsega.workers.ray_cluster import connect

        connect(args.ray)
    out = args.out or Path("runs") / args.grid.stem
    runs = read_grid(args.grid, out)
    print(f"qdsega sweep: {len(runs)} runs -> {out}", flush=True)

    def report(run: SweepRun, status: str) -> None:
        print(f"{run.name}: {status}", flush=True)

    rows = run_sweep(
        runs, out, jobs=args.jobs, ray=args.ray, report=report, progress=ProgressLine
    )  # runs finished of all, with an ETA, on stderr
    failed = sum(row["status"] != "ok" for row in rows)
    print(f"{len(rows) - failed} of {len(rows)} runs finished -> {out / 'sweep.md'}")
    return 1 if failed else 0
