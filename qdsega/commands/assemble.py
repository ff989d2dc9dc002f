"""``qdsega assemble``: formation files -> self-contained URDF files (and MJCF files with
``--mjcf``), with a summary table.

A body with a joint that cannot reach one of its levels without hitting itself is refused
(:mod:`qdsega.simulation.reach`), before it trains for nothing; ``--allow-blocked`` warns
instead."""

from __future__ import annotations

import argparse
import time
from collections.abc import Sequence
from pathlib import Path

from qdsega.errors import ConfigError

NAME = "assemble"
HELP = "assemble formation YAML files into URDF files"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "formations",
        nargs="+",
        type=Path,
        metavar="FORMATION",
        help="formation file, or the name of a shipped one (snake5, legged12, ...)",
    )
    target = parser.add_mutually_exclusive_group()
    target.add_argument(
        "-o", "--output", type=Path, metavar="OUT.urdf", help="output file (one formation only)"
    )
    target.add_argument(
        "--out-dir",
        type=Path,
        metavar="DIR",
        help="write DIR/<formation name>.urdf for each formation (default: the current folder)",
    )
    parser.add_argument(
        "--mjcf",
        action="store_true",
        help="also write MJCF for MuJoCo next to each URDF (<name>.xml, on a floor)",
    )
    parser.add_argument(
        "--allow-blocked",
        action="store_true",
        help="assemble a body with a level a joint cannot reach without the body hitting "
        "itself, with a warning instead of an error",
    )


def run(args: argparse.Namespace) -> int:
    # Imported here: the assembler loads trimesh (about 1 s) and the reach check PyBullet,
    # which the other commands need not.
    from qdsega.assembly import assemble, write_assembly
    from qdsega.assembly.assembler import write_model
    from qdsega.assembly.mjcf import assemble_mjcf
    from qdsega.description import load_formation, resolve_formation
    from qdsega.simulation.reach import check_reach

    if args.output is not None and len(args.formations) > 1:
        raise ConfigError("-o/--output takes one formation; use --out-dir for several")
    if args.mjcf and args.output is not None and args.output.suffix == ".xml":
        raise ConfigError(f"--mjcf writes {args.output} beside the URDF: name the URDF *.urdf")
    rows = []
    for file in args.formations:
        start = time.perf_counter()
        formation = load_formation(resolve_formation(file))
        robot = assemble(formation)
        check_reach(robot, allow_blocked=args.allow_blocked)
        mjcf_text = assemble_mjcf(robot) if args.mjcf else None  # refused before any file
        elapsed_ms = 1000.0 * (time.perf_counter() - start)
        out = args.output or (args.out_dir or Path.cwd()) / f"{formation.name}.urdf"
        write_assembly(robot, out)
        row: tuple[str, ...] = (
            formation.name,
            str(len(formation.units)),
            str(len(formation.joints)),
            str(len(formation.legs)),
            f"{robot.mass_kg:.2f}",
            f"{elapsed_ms:.1f}",
            str(out),
        )
        if mjcf_text is not None:
            mjcf = out.with_suffix(".xml")
            write_model(mjcf_text, robot.assets, mjcf)
            row += (str(mjcf),)
        rows.append(row)
    header = ("formation", "units", "joints", "legs", "mass_kg", "assemble_ms", "urdf")
    _print_table(header + (("mjcf",) if args.mjcf else ()), rows)
    return 0


def _print_table(header: tuple[str, ...], rows: Sequence[tuple[str, ...]]) -> None:
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    for row in [header, *rows]:
        cells = (cell.ljust(width) for cell, width in zip(row, widths, strict=True))
        print("  ".join(cells).rstrip())
