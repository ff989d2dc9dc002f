"""A robot's side of ``qdsega adapt --external``, played by a body in exact physics.

Usage: .venv/bin/python experiments/adaptation/stand_in_robot.py REPERTOIRE --body BODY
           --out DIR [--trials N]

It drives the external adaptation as a robot's script would (docs/after-damage.md): it runs
``qdsega adapt REPERTOIRE --external --out DIR``, plays each gait the command asks for
(``DIR/trials/NNN.csv``) and writes the distance walked to ``DIR/trials/NNN.result``, until
``DIR/adapt.json`` is written. The robot is BODY (a file or shipped name), a changed body the
search knows nothing of, in the repertoire's world
(:class:`qdsega.adaptation.hidden_body.HiddenBody`): its trials are the ones ``qdsega adapt
REPERTOIRE --blind BODY`` plays. Stopped and run again, it goes on where it stopped.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from qdsega.adaptation.folders import AdaptationFolder
from qdsega.adaptation.hidden_body import HiddenBody
from qdsega.adaptation.trajectory import JointTrajectory
from qdsega.atomic import replaced_atomically
from qdsega.cli import main as qdsega
from qdsega.description import load_formation, resolve_formation
from qdsega.training.formation_copy import load_run_world


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("repertoire", type=Path, metavar="REPERTOIRE")
    parser.add_argument("--body", required=True, help="the robot: a changed body, hidden")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR")
    parser.add_argument("--trials", type=int, help="at most (the command's default)")
    args = parser.parse_args()
    folder = AdaptationFolder(args.out)
    command = ["adapt", str(args.repertoire), "--external", "--out", str(args.out)]
    command += [] if args.trials is None else ["--trials", str(args.trials)]
    body = load_formation(resolve_formation(args.body))
    robot = None
    try:
        while True:
            if qdsega(command) != 0:
                raise SystemExit("qdsega adapt --external failed")
            if folder.result.is_file():
                break
            if robot is None:  # the timing the robot is asked to keep
                facts = json.loads(folder.external.read_text(encoding="utf-8"))
                world = load_run_world(args.repertoire)
                robot = HiddenBody(
                    body=body, world=world, step_s=facts["step_s"], commands=facts["commands"]
                )
            trial = 1
            while folder.trial_result(trial).is_file():
                trial += 1
            played = robot.play(JointTrajectory.read(folder.trial_gait(trial)))
            answer = f"{played.distance_m!r} {played.failure or ''}".strip()
            with replaced_atomically(folder.trial_result(trial)) as partial:  # whole or absent
                partial.write_text(answer + "\n", encoding="utf-8")
    finally:
        if robot is not None:
            robot.close()


if __name__ == "__main__":
    main()
