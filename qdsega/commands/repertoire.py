"""``qdsega repertoire``: a body's MAP-Elites archive of gaits that walk, for adapting later."""

from __future__ import annotations

import argparse
from pathlib import Path

from qdsega.adaptation.fills import FILLS, default_fill
from qdsega.errors import ConfigError
from qdsega.folder_names import default_folder

NAME = "repertoire"
HELP = (
    "build a body's repertoire: a MAP-Elites archive of diverse open-loop gaits, each kept only "
    "once exact physics has played it (re-running continues an interrupted build)"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "formation",
        metavar="FORMATION|RUN",
        help="a file or a shipped name, or a finished run folder: its body and world, its "
        "verified gaits played first",
    )
    parser.add_argument(
        "--world", metavar="WORLD", help="a file or a shipped name; default flat (or the run's)"
    )
    parser.add_argument(
        "--fill",
        choices=tuple(FILLS),
        help="the world the archive is filled in: msm (then every elite played in exact "
        "physics; the default for a body with legs on both sides) or exact (any body)",
    )
    defaults = ", ".join(f"{fill} {n}" for fill, (n, _) in FILLS.items())
    parser.add_argument(
        "--evaluations", type=int, metavar="N", help=f"gaits played in that world ({defaults})"
    )
    cells = ", ".join(f"{fill} {c}" for fill, (_, c) in FILLS.items())
    parser.add_argument("--cells", type=int, metavar="C", help=f"archive cells ({cells})")
    parser.add_argument("--seed", type=int, default=0, metavar="S")
    parser.add_argument("--workers", type=int, default=2, metavar="N", help="processes")
    parser.add_argument(
        "--out", type=Path, metavar="DIR", help="default runs/repertoire-NAME[-WORLD]"
    )


def run(args: argparse.Namespace) -> int:
    # Imported here: it starts PyBullet, which the other commands need not load.
    from qdsega.adaptation.folders import RepertoireFolder
    from qdsega.adaptation.repertoire import (
        RepertoireSettings,
        build_repertoire,
        load_repertoire,
        run_gaits,
    )
    from qdsega.analysis.adaptation_plots import archive_map
    from qdsega.description import (
        World,
        load_formation,
        named_world,
        resolve_formation,
    )
    from qdsega.progress import ProgressLine
    from qdsega.training.config import resolve_config
    from qdsega.training.finished_run import FinishedRun

    if args.workers < 1:
        raise ConfigError(f"--workers must be at least 1, got {args.workers}")
    run_folder = Path(args.formation)
    if run_folder.is_dir():  # a run: its body, world and rules, its gaits played first
        if args.world is not None:
            raise ConfigError("--world: a run's repertoire is built in the run's world")
        finished = FinishedRun.open(run_folder)
        config, formation, world = finished.config, finished.formation, finished.world
        seeds, seeded_from = run_gaits(finished), run_folder
    else:
        world = World() if args.world is None else named_world(args.world)
        formation = world.lights(load_formation(resolve_formation(args.formation)))
        config = resolve_config(overrides={"sim": "memo"}, formation=formation)
        seeds, seeded_from = [], None
    fill = args.fill or default_fill(formation)
    evaluations, cells = FILLS[fill]
    try:
        settings = RepertoireSettings(
            fill=fill,
            evaluations=evaluations if args.evaluations is None else args.evaluations,
            cells=cells if args.cells is None else args.cells,
            seed=args.seed,
        )
    except ValueError as exc:
        raise ConfigError(f"--{exc}") from None
    out = args.out or default_folder(formation.name, command="repertoire", world=world.file)
    build_repertoire(
        formation,
        out,
        rules=config.rules(world),
        settings=settings,
        workers=args.workers,
        seeds=seeds,
        seeded_from=seeded_from,
        progress=ProgressLine,
    )
    archive, record = load_repertoire(out)
    if len(archive.filled):
        archive_map(archive, record, RepertoireFolder(out).archive_map)
    best = "none walked" if record["best_m"] is None else f"best {record['best_m']:.4f} m"
    played = f"{record['evaluations_done']} gaits played"
    if fill == "msm":
        played = f"{settings.evaluations} gaits played in the MSM, {played} in exact physics,"
    print(
        f"{formation.name}: {record['filled']} cells of {settings.cells} filled "
        f"({record['coverage']:.0%}), {best}, {played} in {record['wall_s']:.1f} s -> {out}"
    )
    return 0
