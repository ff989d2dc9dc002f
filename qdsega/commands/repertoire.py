"""``qdsega repertoire``: a body's MAP-Elites archive of gaits that walk, for adapting later."""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path
from typing import Any

from qdsega.adaptation.fills import FILLS, RENAMED_FILLS, default_fill, fill_name
from qdsega.adaptation.folders import RepertoireFolder
from qdsega.errors import ConfigError, QdsegaWarning
from qdsega.folder_names import default_folder

NAME = "repertoire"
HELP = (
    "build a body's repertoire: a MAP-Elites archive of diverse open-loop gaits, each kept only "
    "once exact physics has played it (re-running continues an interrupted build)"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "formation",
        metavar="FORMATION|RUN|REPERTOIRE",
        help="a file or a shipped name, or a finished run folder: its body and world, its "
        "verified gaits played first; or a repertoire folder, with --export (nothing built)",
    )
    parser.add_argument(
        "--world", metavar="WORLD", help="a file or a shipped name; default flat (or the run's)"
    )
    parser.add_argument(
        "--fill",
        choices=(*FILLS, *RENAMED_FILLS),
        help="the simulator the archive is filled in: msm (then every elite played in exact "
        "physics; the default for a body with legs on both sides) or pybullet (any body; "
        "exact, its name before 0.2.0, still works)",
    )
    defaults = ", ".join(f"{fill} {n}" for fill, (n, _) in FILLS.items())
    parser.add_argument(
        "--evaluations", type=int, metavar="N", help=f"gaits played in that world ({defaults})"
    )
    cells = ", ".join(f"{fill} {c}" for fill, (_, c) in FILLS.items())
    parser.add_argument("--cells", type=int, metavar="C", help=f"archive cells ({cells})")
    parser.add_argument("--seed", type=int, metavar="S", help="default 0")
    parser.add_argument("--workers", type=int, metavar="N", help="processes (default 2)")
    parser.add_argument(
        "--out", type=Path, metavar="DIR", help="default runs/repertoire-NAME[-WORLD]"
    )
    parser.add_argument(
        "--export",
        action="store_true",
        help=f"also write the elites as DIR/{RepertoireFolder(Path()).elites.name}, one row "
        "each (gait, descriptor, distance, cell)",
    )


BUILD_OPTIONS = ("world", "fill", "evaluations", "cells", "seed", "workers", "out")
"""The options that say how a repertoire is built, refused with a repertoire folder."""


def run(args: argparse.Namespace) -> int:
    # Imported here: it starts PyBullet, which the other commands need not load.
    from qdsega.adaptation.repertoire import (
        RepertoireSettings,
        archive_summary,
        build_repertoire,
        export_repertoire,
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

    source = Path(args.formation)
    if RepertoireFolder(source).record.is_file():  # an existing repertoire: export it only
        if not args.export:
            raise ConfigError(f"{source} holds a repertoire: add --export to write its elites")
        given = [f"--{name}" for name in BUILD_OPTIONS if getattr(args, name) is not None]
        if given:
            raise ConfigError(f"{', '.join(given)}: a repertoire folder is exported as it is")
        archive, record = export_repertoire(source)
        elites = RepertoireFolder(source).elites
        summary = archive_summary(archive)
        print(f"{_summary(record['formation'], summary, len(archive.centroids))} -> {elites}")
        return 0
    workers = 2 if args.workers is None else args.workers
    if workers < 1:
        raise ConfigError(f"--workers must be at least 1, got {workers}")
    if source.is_dir():  # a run: its body, world and rules, its gaits played first
        if args.world is not None:
            raise ConfigError("--world: a run's repertoire is built in the run's world")
        finished = FinishedRun.open(source)
        config, formation, world = finished.config, finished.formation, finished.world
        seeds, seeded_from = run_gaits(finished), source
    else:
        world = World() if args.world is None else named_world(args.world)
        formation = world.lights(load_formation(resolve_formation(args.formation)))
        config = resolve_config(overrides={"sim": "memo"}, formation=formation)
        seeds, seeded_from = [], None
    if args.fill in RENAMED_FILLS:
        warnings.warn(
            f"--fill {args.fill} is now --fill {fill_name(args.fill)} (the old name goes in 0.3.0)",
            QdsegaWarning,
            stacklevel=1,
        )
    fill = fill_name(args.fill) if args.fill else default_fill(formation)
    evaluations, cells = FILLS[fill]
    try:
        settings = RepertoireSettings(
            fill=fill,
            evaluations=evaluations if args.evaluations is None else args.evaluations,
            cells=cells if args.cells is None else args.cells,
            seed=0 if args.seed is None else args.seed,
        )
    except ValueError as exc:
        raise ConfigError(f"--{exc}") from None
    out = args.out or default_folder(formation.name, command="repertoire", world=world.file)
    build_repertoire(
        formation,
        out,
        rules=config.rules(world),
        settings=settings,
        workers=workers,
        seeds=seeds,
        seeded_from=seeded_from,
        progress=ProgressLine,
    )
    archive, record = export_repertoire(out) if args.export else load_repertoire(out)
    if len(archive.filled):
        archive_map(archive, record, RepertoireFolder(out).archive_map)
    played = f"{record['evaluations_done']} gaits played"
    if fill == "msm":
        played = f"{settings.evaluations} gaits played in the MSM, {played} in exact physics,"
    head = _summary(formation.name, archive_summary(archive), len(archive.centroids))
    print(f"{head}, {played} in {record['wall_s']:.1f} s -> {out}")
    return 0


def _summary(formation: str, summary: dict[str, Any], cells: int) -> str:
    """How a repertoire's line begins: cells filled, coverage, best and QD-score (its
    archive's summary)."""
    best = "none walked" if summary["best_m"] is None else f"best {summary['best_m']:.4f} m"
    return (
        f"{formation}: {summary['filled']} cells of {cells} filled "
        f"({summary['coverage']:.0%}), {best}, QD-score {summary['qd_score']:.2f} "
        f"(offset {summary['qd_offset_m']:g} m)"
    )
