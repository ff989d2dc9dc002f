"""``qdsega report``: one self-contained HTML page about a run, for sharing a result."""

from __future__ import annotations

import argparse
from pathlib import Path

NAME = "report"
HELP = (
    "write one self-contained HTML page: summary, evaluation, figures, video, configuration, "
    "formation"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "run", type=Path, metavar="RUN", help="a run folder of qdsega train, or of qdsega adapt"
    )
    parser.add_argument(
        "-o", "--output", type=Path, metavar="OUT.html", help="default RUN/report.html"
    )


def run(args: argparse.Namespace) -> int:
    from qdsega.analysis.report import write_report  # loads matplotlib's figure list

    print(write_report(args.run, args.output))
    return 0
