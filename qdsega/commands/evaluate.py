"""``qdsega evaluate``: replay a run's greedy policy with exact physics, beside a reference."""

from __future__ import annotations

import argparse
from pathlib import Path

from qdsega.errors import ConfigError

NAME = "evaluate"
HELP = "replay a run's greedy policy in PyBullet and compare it with a reference gait"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("run", type=Path, metavar="RUN", help="a run folder of qdsega train")
    parser.add_argument(
        "--reference-trials",
        type=int,
        metavar="N",
        help="exact trials the CMA-ES reference search may run (default 600; 0: no search); "
        "its result is cached, shipped references first",
    )
    parser.add_argument(
        "--formation",
        type=Path,
        metavar="OTHER.yaml",
        help="replay the policy on another formation instead (a changed body: joints matched "
        "by name); writes RUN/evaluation-on-NAME.json",
    )
    parser.add_argument(
        "--world",
        metavar="NAME|FILE",
        help="judge it in another world instead (a world file or a shipped name: flat, ice, "
        "slope, stairs, rubble, tunnel, corridor); writes RUN/evaluation-in-WORLD.json",
    )


def run(args: argparse.Namespace) -> int:
    # Imported here: it starts PyBullet, which the other commands need not load.
    from qdsega.analysis.evaluation import evaluate_on, evaluate_run
    from qdsega.description import named_world
    from qdsega.progress import ProgressLine
    from qdsega.training.joint_mapping import describe
    from qdsega.training.run_folder import RunFolder

    world = None if args.world is None else named_world(args.world)
    place = "" if world is None else f" in {world.name}"
    if args.formation is not None:
        if args.reference_trials is not None:
            raise ConfigError("--reference-trials does not go with --formation")
        result, file = evaluate_on(args.run, args.formation, world=world)
        joints = describe(result["joints"])
        failure = "" if result["failure"] is None else f" (failed: {result['failure']})"
        print(
            f"{result['policy_of']} policy on {result['formation']}{place}: "
            f"{result['distance_m']:.4f} m with exact physics{failure}; {joints} -> {file}"
        )
        return 0

    budget = {} if args.reference_trials is None else {"reference_trials": args.reference_trials}
    result = evaluate_run(args.run, **budget, progress=ProgressLine, world=world)  # on stderr
    reference = result["reference"]
    ratio = "n/a" if result["ratio"] is None else f"{result['ratio']:.3f}"
    predicted = result["memo_prediction_m"]
    memo = "" if predicted is None else f" (memo predicted {predicted:.4f} m)"
    file = RunFolder(args.run).evaluation_file(world=None if world is None else world.name)
    print(
        f"{result['formation']}{place}: learnt policy {result['distance_m']:.4f} m{memo}; "
        f"best reference: {reference['kind']} {reference['distance_m']:.4f} m; ratio {ratio} "
        f"-> {file}"
    )
    return 0
