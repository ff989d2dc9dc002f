"""``qdsega adapt``: find a gait for a changed body in a few trials, from a repertoire."""

from __future__ import annotations

import argparse
from pathlib import Path

from qdsega.errors import ConfigError
from qdsega.folder_names import default_folder

NAME = "adapt"
HELP = (
    "adapt a changed body (a unit lost, locked or added) with the intact body's repertoire: "
    "gaits tried in exact physics or on a robot, each chosen by a model that every trial "
    "corrects"
)
TRIALS = 20
"""The budget where ``--trials`` is not given (an external adaptation keeps its own)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("repertoire", type=Path, metavar="REPERTOIRE", help="of qdsega repertoire")
    body = parser.add_mutually_exclusive_group(required=True)
    body.add_argument(
        "--formation", metavar="CHANGED",
        help="the changed body (a file or name): the gaits mapped onto it, tried in exact physics",
    )  # fmt: skip
    body.add_argument(
        "--blind", metavar="BODY",
        help="a body hidden from the search (a file or name): the intact gaits, unmapped, "
        "tried on it in exact physics",
    )  # fmt: skip
    body.add_argument(
        "--external", action="store_true",
        help="a robot: write the next gait to try as DIR/trials/NNN.csv and exit; its distance "
        "(m) in DIR/trials/NNN.result, rerun to go on",
    )  # fmt: skip
    parser.add_argument(
        "--trials", type=int, metavar="N",
        help=f"at most ({TRIALS}; --external: the folder's, a larger one goes on)",
    )  # fmt: skip
    parser.add_argument(
        "--fresh", type=Path, metavar="RUN",
        help="a fresh qdsega train run of the changed body: its result F is drawn on the curve",
    )  # fmt: skip
    parser.add_argument(
        "--no-video", action="store_true", help="skip filming the gait found (seconds)"
    )
    parser.add_argument(
        "--out", type=Path, metavar="DIR",
        help="default runs/adapt-NAME (-blind, or -external for the repertoire's body)",
    )  # fmt: skip


def run(args: argparse.Namespace) -> int:
    # Imported here: it starts PyBullet, which the other commands need not load.
    from qdsega.adaptation.adapt import adapt, adapt_blind
    from qdsega.adaptation.external import external_step
    from qdsega.adaptation.folders import AdaptationFolder
    from qdsega.adaptation.repertoire import load_repertoire
    from qdsega.analysis.adaptation_plots import adaptation_curve
    from qdsega.analysis.render import render_adaptation
    from qdsega.analysis.report import write_report
    from qdsega.description import load_formation, resolve_formation
    from qdsega.progress import ProgressLine
    from qdsega.simulation.camera import CameraConfig
    from qdsega.training.formation_copy import load_run_world
    from qdsega.training.run_folder import RunFolder

    if args.trials is not None and args.trials < 1:
        raise ConfigError(f"--trials must be at least 1, got {args.trials}")
    fresh_m = None
    if args.fresh is not None:
        folder = RunFolder(args.fresh)
        folder.require_finished()
        fresh_m = float(folder.read_summary()["distance_m"])
    trials = TRIALS if args.trials is None else args.trials
    if args.external:
        intact = load_repertoire(args.repertoire)[1]["formation"]
        out = args.out or default_folder(intact, command="adapt", settings=["external"])
        step = external_step(args.repertoire, out, trials=args.trials)
        if step.result is None:
            print(f"trial {step.trial}: play {step.gait}, then write the distance walked (m) "
                  f"to {step.answer}, and run this again")  # fmt: skip
            return 0
        result, body = step.result, None  # the robot is the body: nothing to film
    elif args.blind is not None:
        body = load_formation(resolve_formation(args.blind))
        out = args.out or default_folder(body.name, command="adapt", settings=["blind"])
        result = adapt_blind(args.repertoire, body, out, trials=trials, progress=ProgressLine)
    else:
        body = load_formation(resolve_formation(args.formation))
        out = args.out or default_folder(body.name, command="adapt")
        result = adapt(args.repertoire, body, out, trials=trials, progress=ProgressLine)
    files = AdaptationFolder(out)
    adaptation_curve(result, files.curve, fresh_m=fresh_m)
    if body is not None and not args.no_video:
        render_adaptation(out, body, load_run_world(args.repertoire), CameraConfig())
    write_report(out)
    where = {"mapped": "with exact physics", "blind": "with exact physics, the body hidden"}
    print(
        f"{result['formation']}: {result['distance_m']:.4f} m "
        f"{where.get(result['mode'], 'on the robot')} at trial {result['trial_found']} of "
        f"{len(result['trials'])} (stopped: {result['stopped']}; {result['wall_s']:.1f} s) "
        f"-> {out}, {files.report.name}"
    )
    return 0
