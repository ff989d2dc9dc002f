"""``qdsega adapt``: find a gait for a changed body in a few exact trials, from a repertoire."""

from __future__ import annotations

import argparse
from pathlib import Path

from qdsega.errors import ConfigError
from qdsega.folder_names import default_folder

NAME = "adapt"
HELP = (
    "adapt a changed body (a unit lost, locked or added) with the intact body's repertoire: "
    "gaits tried in exact physics, each chosen by a model that every trial corrects"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("repertoire", type=Path, metavar="REPERTOIRE", help="of qdsega repertoire")
    parser.add_argument(
        "--formation", required=True, metavar="CHANGED", help="the changed body: a file or name"
    )
    parser.add_argument("--trials", type=int, default=20, metavar="N", help="at most (20)")
    parser.add_argument(
        "--fresh", type=Path, metavar="RUN",
        help="a fresh qdsega train run of the changed body: its result F is drawn on the curve",
    )  # fmt: skip
    parser.add_argument(
        "--no-video", action="store_true", help="skip filming the gait found (seconds)"
    )
    parser.add_argument("--out", type=Path, metavar="DIR", help="default runs/adapt-NAME")


def run(args: argparse.Namespace) -> int:
    # Imported here: it starts PyBullet, which the other commands need not load.
    from qdsega.adaptation.adapt import adapt
    from qdsega.adaptation.folders import AdaptationFolder
    from qdsega.analysis.adaptation_plots import adaptation_curve
    from qdsega.analysis.render import render_adaptation
    from qdsega.analysis.report import write_report
    from qdsega.description import load_formation, resolve_formation
    from qdsega.progress import ProgressLine
    from qdsega.simulation.camera import CameraConfig
    from qdsega.training.formation_copy import load_run_world
    from qdsega.training.run_folder import RunFolder

    if args.trials < 1:
        raise ConfigError(f"--trials must be at least 1, got {args.trials}")
    changed = load_formation(resolve_formation(args.formation))
    fresh_m = None
    if args.fresh is not None:
        folder = RunFolder(args.fresh)
        folder.require_finished()
        fresh_m = float(folder.read_summary()["distance_m"])
    out = args.out or default_folder(changed.name, command="adapt")
    result = adapt(args.repertoire, changed, out, trials=args.trials, progress=ProgressLine)
    files = AdaptationFolder(out)
    adaptation_curve(result, files.curve, fresh_m=fresh_m)
    if not args.no_video:
        render_adaptation(out, changed, load_run_world(args.repertoire), CameraConfig())
    write_report(out)
    print(
        f"{changed.name}: {result['distance_m']:.4f} m with exact physics at trial "
        f"{result['trial_found']} of {len(result['trials'])} (stopped: {result['stopped']}; "
        f"{result['wall_s']:.1f} s) -> {out}, {files.report.name}"
    )
    return 0
