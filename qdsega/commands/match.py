"""``qdsega match``: which body for which world; every formation trained in every world."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from qdsega.errors import ConfigError
from qdsega.workers.ray_cluster import add_ray_option

if TYPE_CHECKING:
    import numpy as np

NAME = "match"
HELP = (
    "train and evaluate every formation in every world (a sweep), then write a matrix of exact "
    "distances, the best body for each world, a heatmap and a page with a still of each cell"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("formations", nargs="+", metavar="FORMATION", help="files or names")
    parser.add_argument(
        "--world", nargs="+", required=True, metavar="WORLD", help="world files or shipped names"
    )
    parser.add_argument("--seeds", nargs="+", type=int, default=[0], metavar="S")
    parser.add_argument("--preset", help="one preset for every body (default: each body's own)")
    parser.add_argument(
        "--budget",
        choices=("screen", "full"),
        default="screen",
        help="screen: each preset cut to 8 generations (default); full: the presets as they are",
    )
    parser.add_argument(
        "--config", type=Path, metavar="FILE.yaml", help="settings over the budget (as --config)"
    )
    parser.add_argument(
        "--reference-trials",
        type=int,
        metavar="N",
        help="the CMA-ES reference search's trials per cell (default 600; 0: classic gaits only)",
    )
    parser.add_argument("--out", type=Path, metavar="DIR", help="default runs/match")
    parser.add_argument("--jobs", type=int, default=1, metavar="N", help="runs at a time")
    add_ray_option(parser)


def run(args: argparse.Namespace) -> int:
    # Imported here: stills start PyBullet, which the other commands need not load.
    from qdsega.analysis.render import final_still
    from qdsega.description import load_formation, named_world, resolve_formation
    from qdsega.match import SCREEN, best_bodies, match_grid, matrix, write_matrix
    from qdsega.progress import ProgressLine
    from qdsega.simulation.camera import CameraConfig
    from qdsega.sweep import grid_runs, run_sweep
    from qdsega.training.config import resolve_config
    from qdsega.yaml_reader import load_yaml

    if args.jobs < 1:
        raise ConfigError(f"--jobs must be at least 1, got {args.jobs}")
    settings = dict(SCREEN) if args.budget == "screen" else {}
    if args.config is not None:
        data = load_yaml(args.config, error_type=ConfigError).data
        if not isinstance(data, dict):
            raise ConfigError("expected a mapping of settings", file=args.config)
        settings = _merged(settings, data)
    formations = [
        (resolve_formation(f), load_formation(resolve_formation(f))) for f in args.formations
    ]
    worlds = [named_world(w) for w in args.world]
    for _, formation in formations:  # every setting checked before anything is written
        resolve_config(
            preset=args.preset, overrides={**settings, "sim": "memo"}, formation=formation
        )
    out = args.out or Path("runs") / "match"
    runs = grid_runs(
        formations, worlds, [args.preset], {"match": settings}, args.seeds, "memo",
        args.reference_trials, out,
    )  # fmt: skip
    text = match_grid(  # the grid as qdsega sweep takes it, for the record
        [str(path) for path, _ in formations],
        [str(w.file) for w in worlds],
        seeds=args.seeds,
        preset=args.preset,
        settings=settings,
        reference_trials=args.reference_trials,
    )
    (out / "grid.yaml").write_text(text, encoding="utf-8")
    print(f"qdsega match: {len(runs)} runs -> {out}", flush=True)
    rows = run_sweep(runs, out, jobs=args.jobs, ray=args.ray, progress=ProgressLine)
    cells = matrix(rows)
    formation_names = list(dict.fromkeys(row["formation"] for row in rows))
    world_names = list(dict.fromkeys(row["world"] for row in rows))
    camera = CameraConfig()  # the usual picture size
    shot = [(key, cell.run) for key, cell in cells.items() if cell.run]
    line = ProgressLine("stills", len(shot), delay_s=5.0)  # each replays its cell's trial
    stills: dict[tuple[str, str], np.ndarray] = {}
    for done, (key, run) in enumerate(shot, start=1):
        stills[key] = final_still(out / run, camera)
        line.update(done, f"{key[0]} in {key[1]}")
    line.close()
    files = write_matrix(cells, formation_names, world_names, out, stills)
    for world, body in best_bodies(cells).items():
        print(f"{world}: {body or 'no body moved'}")
    print(" ".join(str(f) for f in files))
    return 0


def _merged(base: dict[str, Any], more: dict[str, Any]) -> dict[str, Any]:
    """``more`` over ``base``, nested mappings merged key by key."""
    merged = dict(base)
    for key, value in more.items():
        both = isinstance(value, dict) and isinstance(merged.get(key), dict)
        merged[key] = _merged(merged[key], value) if both else value
    return merged
