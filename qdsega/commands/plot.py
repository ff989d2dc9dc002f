"""``qdsega plot``: Fig. 11 and Fig. 12 style figures from a run folder."""

from __future__ import annotations

import argparse
from pathlib import Path

NAME = "plot"
HELP = "draw trajectories (Fig. 11) and the acquired gait (Fig. 12) of a run folder"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "run_dir", type=Path, metavar="RUN", help="a folder written by qdsega train"
    )


def run(args: argparse.Namespace) -> int:
    from qdsega.training.plots import plot_run  # matplotlib loads only when plotting

    for path in plot_run(args.run_dir):
        print(path)
    return 0
