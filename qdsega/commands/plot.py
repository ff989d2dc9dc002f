"""``qdsega plot``: the figures of a run folder (:mod:`qdsega.analysis.plots`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

NAME = "plot"
HELP = (
    "draw a run's learning curve, Q-table size, trajectories (Fig. 11), gait (Fig. 12), "
    "snake poses (Fig. 13) and joint angles as PNG files in the run folder"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "run_dir", type=Path, metavar="RUN", help="a folder written by qdsega train"
    )
    parser.add_argument(
        "--fresh",
        type=Path,
        metavar="RUN",
        help="for a warm-started RUN: the fresh run whose learning curve to draw beside it "
        "(default: a finished folder beside RUN that trained the same formation from scratch)",
    )


def run(args: argparse.Namespace) -> int:
    from qdsega.analysis.plots import plot_run  # matplotlib loads only when plotting

    paths, notes = plot_run(args.run_dir, fresh=args.fresh)
    for path in paths:
        print(path)
    for note in notes:
        print(f"qdsega plot: note: {note}", file=sys.stderr)
    return 0
