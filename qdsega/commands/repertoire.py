"""``qdsega repertoire``: a body's MAP-Elites archive of gaits that walk, for adapting later."""

from __future__ import annotations

import argparse
from pathlib import Path

from qdsega.errors import ConfigError

NAME = "repertoire"
HELP = (
    "build a body's repertoire: a MAP-Elites archive of diverse open-loop gaits, each played in "
    "exact physics (re-running continues an interrupted build)"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("formation", metavar="FORMATION", help="a file or a shipped name")
    parser.add_argument("--world", metavar="WORLD", help="a file or a shipped name; default flat")
    parser.add_argument(
        "--evaluations", type=int, default=2000, metavar="N", help="gaits played in all"
    )
    parser.add_argument("--cells", type=int, default=128, metavar="C", help="archive cells")
    parser.add_argument("--seed", type=int, default=0, metavar="S")
    parser.add_argument("--workers", type=int, default=2, metavar="N", help="processes")
    parser.add_argument("--out", type=Path, metavar="DIR", help="default runs/repertoire-NAME")


def run(args: argparse.Namespace) -> int:
    # Imported here: it starts PyBullet, which the other commands need not load.
    from qdsega.adaptation.repertoire import (
        RepertoireSettings,
        build_repertoire,
        load_repertoire,
    )
    from qdsega.analysis.adaptation_plots import ARCHIVE_MAP, archive_map
    from qdsega.description import (
        World,
        load_formation,
        named_world,
        resolve_formation,
    )
    from qdsega.progress import ProgressLine
    from qdsega.training.config import resolve_config

    if args.workers < 1:
        raise ConfigError(f"--workers must be at least 1, got {args.workers}")
    try:
        settings = RepertoireSettings(
            evaluations=args.evaluations, cells=args.cells, seed=args.seed
        )
    except ValueError as exc:
        raise ConfigError(f"--{exc}") from None
    world = World() if args.world is None else named_world(args.world)
    formation = world.lights(load_formation(resolve_formation(args.formation)))
    rules = resolve_config(overrides={"sim": "memo"}, formation=formation).rules(world)
    out = args.out or Path("runs") / f"repertoire-{formation.name}"
    build_repertoire(
        formation, out, rules=rules, settings=settings, workers=args.workers, progress=ProgressLine
    )
    archive, record = load_repertoire(out)
    if len(archive.filled):
        archive_map(archive, record, out / ARCHIVE_MAP)
    best = "none walked" if record["best_m"] is None else f"best {record['best_m']:.4f} m"
    print(
        f"{formation.name}: {record['filled']} cells of {settings.cells} filled "
        f"({record['coverage']:.0%}), {best}, {record['evaluations_done']} gaits played in "
        f"{record['wall_s']:.1f} s -> {out}"
    )
    return 0
