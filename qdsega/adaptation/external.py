"""Adaptation on a robot (``qdsega adapt --external``): the search of :class:`~qdsega.adaptation.
adapt.Adaptation` asks for gaits as files, and the robot's side answers with files.

Each call of :func:`external_step` replays the search from its folder and stops at the first
trial without a result:

1. ``external.json``: what the robot needs for every trial (written once): the joints, the rest
   posture, the step and the joints' speed, the repertoire it is adapted from;
2. ``trials/NNN.csv``: the gait to try, the intact body's joint angles over time
   (:class:`~qdsega.adaptation.trajectory.JointTrajectory`);
3. ``trials/NNN.result``: written by the robot's side once it has played it: the distance the
   robot walked toward the light (m), optionally followed on the line by a note (why the
   trial failed), which ``adapt.json`` keeps.

Every file is whole or absent, and the search is deterministic, so a call after any crash
goes on from the last result, asking for no finished trial again. Once the search is done,
and only then, ``adapt.json`` and ``gait.csv`` are written as :func:`~qdsega.adaptation.adapt.
adapt` writes them, of the intact body (the robot's joints).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.adaptation.adapt import (
    DEFAULT_TRIALS,
    Adaptation,
    MappedRepertoire,
    write_adaptation,
)
from qdsega.adaptation.folders import AdaptationFolder
from qdsega.adaptation.trajectory import JointTrajectory
from qdsega.adaptation.trial_model import LENGTH_SCALE
from qdsega.atomic import replaced_atomically
from qdsega.errors import RunFolderError
from qdsega.locomotion.lower_agent import SETTLE_S

SAME_ROBOT = ("repertoire", "formation", "joints", "rest_rad", "step_s", "commands")
"""What ``external.json`` must keep across calls: the gaits asked for depend on nothing else."""


@dataclass(frozen=True)
class ExternalStep:
    """Where an external adaptation stands after a call.

    Attributes:
        trial: the trial to play next (from 1), None once the search is done.
        gait: its CSV, None once done.
        answer: where the robot's side writes its distance, None once done.
        result: ``adapt.json``'s content once done, else None.
    """

    trial: int | None
    gait: Path | None
    answer: Path | None
    result: dict[str, Any] | None


def external_step(
    repertoire: Path,
    out: Path,
    *,
    trials: int | None = None,
    length_scale: float = LENGTH_SCALE,
) -> ExternalStep:
    """Take the external adaptation in folder ``out`` from repertoire ``repertoire`` as far as
    the robot's results in it go; write the next gait to try, or the result. ``trials``: the
    budget (None: the folder's, else :data:`DEFAULT_TRIALS`; a larger one goes on).

    Raises:
        RunFolderError: not a repertoire, or a corrupt one; ``out`` holds another adaptation;
            a result that is not a distance; a gait file that is not the gait the search
            asks for now (a result before it was changed).
        FormationError: the repertoire holds no gait.
    """
    intact = MappedRepertoire.unmapped(repertoire)
    rules = intact.rules()
    folder = AdaptationFolder(out)
    facts = _claim(folder, robot_facts(intact, trials))
    search = Adaptation(repertoire=intact, trials=facts["trials"], length_scale=length_scale)
    began: float | None = None
    trial = 0
    while (ask := search.ask()) is not None:
        trial += 1
        gait, answer = folder.trial_gait(trial), folder.trial_result(trial)
        wanted = JointTrajectory.trial(intact.changed, ask.cycle, rules)
        if not gait.is_file():
            wanted.write(gait)
        elif not JointTrajectory.read(gait).same_as(wanted):
            message = (
                "is not the gait the search asks for now (a result before it changed); put "
                "the result back, or adapt into another --out"
            )
            raise RunFolderError(message, file=gait)
        if began is None:
            began = gait.stat().st_mtime
        if not answer.is_file():
            folder.result.unlink(missing_ok=True)  # a larger budget: not done after all
            return ExternalStep(trial, gait, answer, None)
        distance, note = read_answer(answer)
        search.tell(distance, failure=note, wall_s=answer.stat().st_mtime - began)
    result = write_adaptation(
        out,
        search,
        mode="external",
        body=intact.changed,
        joints=intact.mapping,
        gait=search.best().cycle,
        trial_steps=rules.task.trial_steps,
        wall_s=search.played[-1]["wall_s"],
    )
    return ExternalStep(None, None, None, result)


def robot_facts(intact: MappedRepertoire, trials: int | None) -> dict[str, Any]:
    """``external.json``'s content: what a robot needs to play the gaits of ``intact`` (the
    repertoire on the intact body), and the budget (None where not given)."""
    body, rules = intact.changed, intact.rules()
    step_s = rules.lower_agent.step_duration_for(body)
    speed = rules.lower_agent.joint_speed_rad_s
    rest = np.array(body.rest_levels(), dtype=np.int64)
    return {
        "repertoire": str(intact.path.resolve()),
        "formation": body.name,
        "joints": [j.name for j in body.joints],
        "rest_rad": list(body.posture_rad(rest)),
        "joint_speed_rad_s": [min(speed, j.spec.velocity_rad_s) for j in body.joints],
        "settle_s": SETTLE_S,
        "step_s": step_s,
        "commands": rules.task.trial_steps,
        "duration_s": rules.task.trial_steps * step_s,
        "light_m": list(body.light.position_m),
        "trials": trials,
        "play": (
            "start in rest_rad and hold it settle_s; then from each row's time_s on, drive "
            "every joint toward the row's angle (rad) at joint_speed_rad_s; at the last row's "
            "time, write the distance walked toward the light (m) to trials/NNN.result "
            "(light_m: where the light stands from the start, x straight ahead, y to the left)"
        ),
    }


def _claim(folder: AdaptationFolder, facts: dict[str, Any]) -> dict[str, Any]:
    """Make ``folder`` this external adaptation's, writing ``facts`` as its ``external.json``
    (the budget: the given one, else the folder's, else the default); returns them.

    Raises:
        RunFolderError: the folder holds another adaptation, or an external adaptation of
            another repertoire or robot.
    """
    file = folder.external
    if file.is_file():
        try:
            held = json.loads(file.read_text(encoding="utf-8"))
            mine = {k: held[k] for k in SAME_ROBOT} == {k: facts[k] for k in SAME_ROBOT}
            budget = int(held["trials"])
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise RunFolderError(f"corrupt external adaptation ({exc})", file=file) from None
        if not mine:
            message = "holds an external adaptation of another repertoire; choose another --out"
            raise RunFolderError(message, file=folder.path)
    elif folder.result.is_file():
        message = "holds an adaptation played in exact physics; choose another --out"
        raise RunFolderError(message, file=folder.path)
    else:
        budget = DEFAULT_TRIALS
    facts = {**facts, "trials": budget if facts["trials"] is None else facts["trials"]}
    if facts["trials"] < 1:
        raise ValueError(f"trials must be at least 1, got {facts['trials']}")
    folder.path.mkdir(parents=True, exist_ok=True)
    with replaced_atomically(file) as partial:
        partial.write_text(json.dumps(facts, indent=2) + "\n", encoding="utf-8")
    return facts


def read_answer(file: Path) -> tuple[float, str | None]:
    """The distance (m) in a trial's result file, and the note after it on its line (None
    where there is none).

    Raises:
        RunFolderError: not a finite distance first.
    """
    lines = file.read_text(encoding="utf-8").strip().splitlines()
    first, *note = lines[0].split(maxsplit=1) if lines else [""]
    try:
        distance = float(first)
    except ValueError:
        distance = float("nan")
    if not np.isfinite(distance):
        message = f"expected the distance the robot walked (m), a number, got {first!r}"
        raise RunFolderError(message, file=file)
    return distance, note[0] if note else None
