"""``qdsega gallery``: pictures of every shipped body and world, the unit types and the leg
states."""

from __future__ import annotations

import argparse
from pathlib import Path

from qdsega.errors import ConfigError
from qdsega.folder_names import RUNS
from qdsega.simulation.camera import HEIGHT_PX, WIDTH_PX

NAME = "gallery"
HELP = (
    "draw every body at its start, every world with a body in it, a contact sheet of each, "
    "a diagram of each unit type and a leg in each leg state"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", type=Path, metavar="DIR", help="default runs/gallery")
    parser.add_argument(
        "--formation",
        nargs="+",
        metavar="FORMATION",
        help="files or shipped names (default: every shipped formation)",
    )
    parser.add_argument(
        "--world",
        nargs="+",
        metavar="WORLD",
        help="files or shipped names (default: every shipped world)",
    )
    parser.add_argument("--width", type=int, default=WIDTH_PX, help="pixels (default %(default)s)")
    parser.add_argument(
        "--height", type=int, default=HEIGHT_PX, help="pixels (default %(default)s)"
    )


def run(args: argparse.Namespace) -> int:
    # Imported here: pictures start PyBullet, which the other commands need not load.
    from qdsega.analysis.gallery import draw_gallery
    from qdsega.description import (
        load_formation,
        load_unit_type,
        named_world,
        resolve_formation,
        shipped_formation_names,
        shipped_unit_names,
        shipped_world_names,
    )
    from qdsega.description.shipped import UNITS_DIR
    from qdsega.simulation.camera import CameraConfig

    try:
        camera = CameraConfig(width=args.width, height=args.height)
    except ValueError as exc:
        raise ConfigError(str(exc)) from None
    # Every input is read before anything is drawn: a mistake writes nothing.
    formations = [
        load_formation(resolve_formation(name))
        for name in args.formation or shipped_formation_names()
    ]
    worlds = [named_world(name) for name in args.world or shipped_world_names()]
    units = [load_unit_type(UNITS_DIR, name) for name in shipped_unit_names()]
    out = args.out or RUNS / NAME
    drawn = draw_gallery(out, formations=formations, worlds=worlds, units=units, camera=camera)
    for group, files in (
        ("bodies", drawn.bodies),
        ("worlds", drawn.worlds),
        ("units", drawn.units),
        ("legs", drawn.legs),
    ):
        print(f"{group}: {len(files)} pictures -> {', '.join(str(f) for f in files)}")
    return 0
