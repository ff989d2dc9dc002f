"""``qdsega design``: a body for a world from a bag of units, found as ``reform`` finds one."""

from __future__ import annotations

import argparse

from qdsega.commands.reform import add_search_arguments, print_verdict, search, world_file
from qdsega.folder_names import default_folder

NAME = "design"
HELP = (
    "a body for a world from a bag of units (e.g. hub=2 servo=8): a first body put together "
    "by a fixed rule, then re-formed for the world as reform does"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("units", nargs="+", metavar="TYPE=N", help="the units, e.g. hub=2 servo=8")
    add_search_arguments(parser, out="runs/design-UNITS[-WORLD]")


def run(args: argparse.Namespace) -> int:
    from qdsega.description.formation_writer import formation_yaml
    from qdsega.reform.design import first_body
    from qdsega.reform.material import parse_units
    from qdsega.reform.outputs import count_moves

    bag = parse_units(args.units, what="a unit")
    label = "-".join(f"{name}{count}" for name, count in bag.items())
    out = args.out or default_folder(label, command="design", world=world_file(args.world))
    body = first_body(bag, name=f"design_{label}")
    file = out / "first.yaml"
    if not file.is_file():
        comment = "the first body of qdsega design, by its fixed rule (qdsega/reform/design.py)"
        text = formation_yaml(body, file, comment=comment)
        out.mkdir(parents=True, exist_ok=True)
        file.write_text(text, encoding="utf-8")
    record = search(args, file, out)
    winner = record["winner"]
    moved = count_moves(len(winner["moves"]))
    how = f"{moved} from it" if winner["reformed"] else "the first body"
    print_verdict(record, f"designed {winner['name']} ({how})", out)
    return 0
