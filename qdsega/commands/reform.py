"""``qdsega reform``: the formation a body's units should take (after damage, or for a world),
and the fewest moves that get there."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from qdsega.folder_names import default_folder

NAME = "reform"
HELP = (
    "find the formation a body's units should take in a world: candidate bodies made of its "
    "units (and spares), screened, the best learnt and judged in exact physics against the "
    "body as it is; writes the winner, the fewest moves to it and one page"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("formation", metavar="FORMATION", help="the body now: a file or a name")
    parser.add_argument(
        "--spare", action="append", default=[], metavar="TYPE=N",
        help="spare units it may use besides its own, e.g. --spare servo=2 (repeatable)",
    )  # fmt: skip
    parser.add_argument(
        "--repertoire", type=Path, metavar="REP",
        help="the intact body's repertoire (qdsega repertoire): the body as it is is also "
        "adapted from it",
    )  # fmt: skip
    add_search_arguments(parser, out="runs/reform-NAME[-WORLD]")


def add_search_arguments(parser: argparse.ArgumentParser, *, out: str) -> None:
    """The options of a search for a body, ``reform``'s and ``design``'s."""
    from qdsega.reform.settings import ReformSettings

    defaults = ReformSettings()
    parser.add_argument("--world", metavar="WORLD", help="a world file or shipped name (flat)")
    parser.add_argument(
        "--config", type=Path, metavar="FILE.yaml",
        help="settings over each candidate's own preset (keys as in qdsega train --config)",
    )  # fmt: skip
    parser.add_argument("--out", type=Path, metavar="DIR", help=f"default {out}")
    parser.add_argument("--jobs", type=int, default=1, metavar="N", help="runs at a time")
    parser.add_argument("--ray", metavar="local|ADDRESS", help="runs as Ray tasks instead")
    parser.add_argument("--seed", type=int, default=defaults.seed, metavar="S")
    parser.add_argument(
        "--screen", type=int, default=defaults.screen, metavar="G",
        help=f"generations each candidate learns before ranking ({defaults.screen})",
    )  # fmt: skip
    parser.add_argument(
        "--rounds", type=int, default=defaults.rounds, metavar="R",
        help=f"rounds of moves; later ones move on from the best few ({defaults.rounds})",
    )  # fmt: skip
    parser.add_argument(
        "--top", type=int, default=defaults.top, metavar="K",
        help=f"candidates learnt to the end besides the body as it is ({defaults.top})",
    )  # fmt: skip
    parser.add_argument(
        "--allow-blocked", action="store_true",
        help="go on with a body whose joint cannot reach a level without the body hitting "
        "itself (a warning for the body as it is), instead of refusing or dropping it",
    )  # fmt: skip


def run(args: argparse.Namespace) -> int:
    from qdsega.description import resolve_formation
    from qdsega.reform.material import parse_units
    from qdsega.reform.outputs import count_moves

    formation = resolve_formation(args.formation)
    spares = parse_units(args.spare)
    out = args.out or default_folder(formation.stem, command="reform", world=world_file(args.world))
    record = search(args, formation, out, spares=spares, repertoire=args.repertoire)
    winner = record["winner"]
    verdict = (
        f"re-form into {winner['name']} in {count_moves(len(winner['moves']))}"
        if winner["reformed"]
        else f"keep the body ({winner['how']})"
    )
    print_verdict(record, verdict, out)
    return 0


def world_file(world: str | None) -> Path | None:
    """The file a ``--world`` argument names (None for the flat plane)."""
    from qdsega.description import resolve_world

    return None if world is None else resolve_world(world)


def search(
    args: argparse.Namespace,
    formation: Path,
    out: Path,
    *,
    spares: dict[str, int] | None = None,
    repertoire: Path | None = None,
) -> dict[str, Any]:
    """Run the search the options ``args`` describe (:func:`qdsega.reform.search.reform`)."""
    # Imported here: the search starts PyBullet, which the other commands need not load.
    from qdsega.description import resolve_world
    from qdsega.progress import ProgressLine
    from qdsega.reform.search import reform
    from qdsega.reform.settings import ReformSettings

    settings = ReformSettings(
        seed=args.seed,
        screen=args.screen,
        rounds=args.rounds,
        top=args.top,
        allow_blocked=args.allow_blocked,
    )
    return reform(
        formation,
        out=out,
        world_file=None if args.world is None else resolve_world(args.world),
        spares=spares,
        repertoire=repertoire,
        config=args.config,
        settings=settings,
        jobs=args.jobs,
        ray=args.ray,
        progress=ProgressLine,
    )


def print_verdict(record: dict[str, Any], verdict: str, out: Path) -> None:
    """The one line a search prints at its end."""
    from qdsega.reform.folder import ReformFolder

    folder = ReformFolder(out)
    print(
        f"{record['inputs']['formation']}: {verdict}, {record['winner']['distance_m']:.4f} m "
        f"with exact physics ({record['wall_s'] / 60:.1f} min) -> {folder.summary}, "
        f"{folder.plan}, {folder.page}"
    )
