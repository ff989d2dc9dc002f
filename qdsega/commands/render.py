"""``qdsega render``: an off-screen video of a run's greedy policy or of a posture sequence."""

from __future__ import annotations

import argparse
from pathlib import Path

from qdsega.errors import ConfigError, FormationError
from qdsega.simulation.camera import HEIGHT_PX, WIDTH_PX

NAME = "render"
HELP = "render a run's greedy policy (or a formation and a posture sequence) as MP4 or GIF"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "source",
        type=Path,
        metavar="RUN|FORMATION",
        help="a run folder, or a formation (file or shipped name) together with --postures",
    )
    parser.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.mp4|OUT.gif")
    parser.add_argument(
        "--postures",
        type=Path,
        metavar="FILE.csv",
        help="with a formation: one row per step, one level index per joint",
    )
    parser.add_argument(
        "--width",
        type=int,
        default=WIDTH_PX,
        help="pixels (default %(default)s; less for a smaller file)",
    )
    parser.add_argument(
        "--height",
        type=int,
        default=HEIGHT_PX,
        help="pixels (default %(default)s; less for a smaller file)",
    )
    parser.add_argument("--fps", type=int, default=20, help="frames per simulated second")
    parser.add_argument(
        "--distance",
        type=float,
        metavar="M",
        help="camera distance (m; default: frame the body, 1.2 times its size at rest)",
    )
    parser.add_argument(
        "--world",
        metavar="NAME|FILE",
        help="with a formation: the ground it walks on, a world file or a shipped name "
        "(flat, ice, slope, stairs, rubble, tunnel, corridor); default flat",
    )
    parser.add_argument("--pitch", type=float, default=25.0, help="camera looks down (deg)")
    parser.add_argument("--fov", type=float, default=60.0, help="vertical field of view (deg)")


def run(args: argparse.Namespace) -> int:
    # Imported here: rendering starts PyBullet, which the other commands need not load.
    from qdsega.analysis.render import read_postures, render_postures, render_run
    from qdsega.description import (
        load_formation,
        named_world,
        resolve_formation,
    )
    from qdsega.simulation.camera import CameraConfig

    try:
        camera = CameraConfig(
            width=args.width,
            height=args.height,
            fps=args.fps,
            distance_m=args.distance,
            pitch_deg=args.pitch,
            fov_deg=args.fov,
        )
    except ValueError as exc:
        raise ConfigError(str(exc)) from None
    if args.source.is_dir():
        if args.world is not None:
            raise ConfigError("--world goes with a formation and --postures")
        film = render_run(args.source, args.output, camera)
    elif args.postures is None:
        raise FormationError("a formation file needs --postures FILE.csv", file=args.source)
    else:
        formation = load_formation(resolve_formation(args.source))
        world = None if args.world is None else named_world(args.world)
        postures = read_postures(args.postures, len(formation.joints))
        film = render_postures(formation, postures, args.output, camera, world=world)
    stopped = f" (stopped early: {film.failure})" if film.failure else ""
    print(f"{len(film.frames)} frames at {film.fps} fps -> {args.output}{stopped}")
    return 0
