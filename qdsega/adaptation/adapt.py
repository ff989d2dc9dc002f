"""Trial and error on a changed body, guided by the intact body's repertoire (IT&E).

The search (:class:`Adaptation`) is ask/tell: one trial at a time, the gait of the highest
upper confidence bound of the trial model (:class:`qdsega.adaptation.trial_model.TrialModel`,
the archive's fitness as its prior mean) is asked for, the caller plays it and tells how far
it went, and the model learns what it did; the search stops when no untried gait is predicted
to beat the best trial, or after ``trials`` trials. Nothing is random: the same repertoire and
distances give the same trials. Its trials are played one of three ways (:data:`MODES`):

* ``mapped`` (:func:`adapt`): every elite gait mapped onto the changed body joint by joint
  (:class:`qdsega.training.joint_mapping.JointMapping`: matched joints at the nearest level,
  added ones at rest, dropped and locked ones gone), played in exact physics on that body;
* ``blind`` (:func:`adapt_blind`): the intact body's gaits, unmapped, played on a body the
  search knows nothing of (:mod:`qdsega.adaptation.hidden_body`);
* ``external`` (:mod:`qdsega.adaptation.external`): the intact body's gaits handed to a robot
  as files, its distances read back.

An adaptation folder holds ``adapt.json`` (the trials, the gait found, why it stopped, the
joints' mapping) and ``gait.csv`` (the trial of the gait found: its cycle repeated for a
trial's commands, one posture of level indices a row, as ``qdsega render FORMATION
--postures`` takes it). ``qdsega train CHANGED --warm-start DIR`` goes on from the gait found
(:func:`warm_start_from`).
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.adaptation.folders import AdaptationFolder
from qdsega.adaptation.repertoire import load_repertoire
from qdsega.adaptation.trajectory import JointTrajectory
from qdsega.adaptation.trial_model import LENGTH_SCALE, TrialModel
from qdsega.agent.learner import LearnerState
from qdsega.agent.policy import SequencePolicy
from qdsega.atomic import replaced_atomically
from qdsega.description import Formation, World
from qdsega.errors import FormationError, RunFolderError
from qdsega.locomotion.rules import ExactRules
from qdsega.progress import ProgressFactory
from qdsega.training.config import TrainingConfig, resolve_config
from qdsega.training.formation_copy import load_run_formation, load_run_world
from qdsega.training.joint_mapping import JointMapping
from qdsega.training.reconfiguration import WarmStart

DEFAULT_TRIALS = 20
"""Trials an adaptation may run (IT&E's budget)."""
MODES = {
    "mapped": "exact physics, on the changed body, the gaits mapped onto it",
    "blind": "exact physics, on a body hidden from the search, the intact body's gaits",
    "external": "the robot, the intact body's gaits handed to it as files",
}
"""How an adaptation's trials are played (module docstring), in words."""


@dataclass(frozen=True)
class MappedRepertoire:
    """A repertoire's elite gaits mapped onto a changed body joint by joint.

    Attributes:
        path: the repertoire's folder.
        record: the repertoire's record (``repertoire.json``).
        changed: the changed body, lit by the repertoire's world.
        world: the world the repertoire was built in.
        mapping: the intact body's joints onto the changed body's.
        cells: the archive's filled cells (C,).
        gaits: each filled cell's elite cycle on the changed body (k, J_changed).
        prior: each one's distance on the intact body (C,) (m).
        descriptors: each one's descriptor on the intact body (C, D).
    """

    path: Path
    record: dict[str, Any]
    changed: Formation
    world: World
    mapping: JointMapping
    cells: np.ndarray
    gaits: list[np.ndarray]
    prior: np.ndarray
    descriptors: np.ndarray

    @classmethod
    def of(cls, repertoire: Path, changed: Formation) -> MappedRepertoire:
        """Map the repertoire in folder ``repertoire`` onto ``changed``.

        Raises:
            RunFolderError: not a repertoire, or a corrupt one.
            FormationError: ``changed`` has no actuated joint in common with the repertoire's
                body, or the repertoire holds no gait.
        """
        archive, record = load_repertoire(repertoire)
        intact = load_run_formation(repertoire, TrainingConfig())
        world = load_run_world(repertoire)
        changed = world.lights(changed)
        mapping = JointMapping.between(intact, changed)
        if not mapping.matched:
            message = f"no actuated joint in common with the repertoire's body ({intact.name})"
            raise FormationError(message, file=changed.file)
        cells = archive.filled
        if not len(cells):
            raise FormationError("the repertoire holds no gait that walks", file=changed.file)
        rest = np.array(changed.rest_levels(), dtype=np.int64)
        return cls(
            path=repertoire,
            record=record,
            changed=changed,
            world=world,
            mapping=mapping,
            cells=cells,
            gaits=[mapping.postures(archive.gait(int(c)), rest) for c in cells],
            prior=archive.fitness[cells],
            descriptors=archive.descriptors[cells],
        )

    @classmethod
    def unmapped(cls, repertoire: Path) -> MappedRepertoire:
        """The repertoire in folder ``repertoire`` as it is: its gaits on the intact body.

        Raises:
            RunFolderError: not a repertoire, or a corrupt one.
            FormationError: the repertoire holds no gait.
        """
        return cls.of(repertoire, load_run_formation(repertoire, TrainingConfig()))

    def rules(self) -> ExactRules:
        """The changed body's own rules (its memo preset's task, lower agent and physics) in
        the repertoire's world: what every trial is judged by."""
        return resolve_config(overrides={"sim": "memo"}, formation=self.changed).rules(self.world)


@dataclass(frozen=True)
class Ask:
    """A gait the search asks to be tried.

    Attributes:
        index: its place among the repertoire's gaits (:attr:`MappedRepertoire.gaits`).
        cell: its archive cell.
        cycle: its posture cycle (k, J) of the search's body's level indices.
        predicted_m: the model's mean for it before the trial (m).
        intact_m: its distance on the intact body (m).
    """

    index: int
    cell: int
    cycle: np.ndarray
    predicted_m: float
    intact_m: float


class Adaptation:
    """The search of IT&E, ask/tell: :meth:`ask` names the gait to try next, the caller plays it
    where it will (exact physics, a hidden body, a robot) and :meth:`tell` says how far it
    went. The same repertoire and distances give the same asks.

    Args:
        repertoire: the gaits to choose from, with their prior (the intact body's distances).
        trials: the most trials it asks for (IT&E's budget).
        length_scale: the trial model's (:class:`TrialModel`).
    """

    def __init__(
        self,
        *,
        repertoire: MappedRepertoire,
        trials: int = DEFAULT_TRIALS,
        length_scale: float = LENGTH_SCALE,
    ) -> None:
        if trials < 1:
            raise ValueError(f"trials must be at least 1, got {trials}")
        prior = repertoire.prior
        self.repertoire = repertoire
        self.trials = trials
        self.model = TrialModel(
            descriptors=repertoire.descriptors,
            prior=prior,
            signal=max(float(np.std(prior)), 0.1 * float(np.max(np.abs(prior))), 1e-3),
            length_scale=length_scale,
        )
        self.played: list[dict[str, Any]] = []
        """A record per trial told: the cell, the prediction, the distances, the failure."""
        self._told: list[Ask] = []
        self._pending: Ask | None = None

    @property
    def budget(self) -> int:
        """The most trials it can ask for: ``trials``, or fewer gaits."""
        return min(self.trials, len(self.repertoire.cells))

    def ask(self) -> Ask | None:
        """The gait to try next (the same again until told), or None once the search is done
        (:meth:`TrialModel.done`)."""
        if self._pending is None and not self.model.done(self.trials):
            k = self.model.next_cell()
            mean, _ = self.model.posterior()
            self._pending = Ask(
                index=k,
                cell=int(self.repertoire.cells[k]),
                cycle=self.repertoire.gaits[k],
                predicted_m=float(mean[k]),
                intact_m=float(self.repertoire.prior[k]),
            )
        return self._pending

    def tell(self, distance_m: float, *, failure: str | None, wall_s: float) -> None:
        """How far the gait last asked for went (m), why its trial failed (None: it did not)
        and the seconds since the search began."""
        if self._pending is None:
            raise ValueError("tell needs a gait asked for and not yet told")
        asked, self._pending = self._pending, None
        self.model.tell(asked.index, distance_m)
        self._told.append(asked)
        self.played.append(
            {
                "cell": asked.cell,
                "predicted_m": asked.predicted_m,
                "intact_m": asked.intact_m,
                "distance_m": float(distance_m),
                "failure": failure,
                "wall_s": wall_s,
            }
        )

    def best(self) -> Ask:
        """The gait of the farthest trial (the first of equals).

        Raises:
            ValueError: nothing told yet.
        """
        if not self._told:
            raise ValueError("no trial told yet")
        return self._told[int(np.argmax(self.model.observed))]

    def outcome(self) -> dict[str, Any]:
        """What the search found, for ``adapt.json``: the trials, the farthest and which trial
        it was, its cell, why the search stopped, the best prediction left."""
        mean, _ = self.model.posterior()
        best = int(np.argmax(self.model.observed))
        return {
            "trials": self.played,
            "distance_m": self.model.observed[best],
            "trial_found": best + 1,
            "cell": self._told[best].cell,
            "stopped": "no untried gait was predicted to beat the best trial"
            if self.model.settled()
            else f"after {len(self.played)} trials",
            "best_predicted_m": float(np.max(mean)),
        }


def adapt(
    repertoire: Path,
    changed: Formation,
    out: Path,
    *,
    trials: int = DEFAULT_TRIALS,
    length_scale: float = LENGTH_SCALE,
    progress: ProgressFactory | None = None,
) -> dict[str, Any]:
    """Adapt ``changed`` with the repertoire in folder ``repertoire``, its gaits mapped onto
    it; write ``out``. ``length_scale`` is the trial model's (:class:`TrialModel`);
    ``progress`` shows the trials run of at most ``trials`` (None: silent).

    Raises:
        RunFolderError: not a repertoire, or a corrupt one.
        FormationError: ``changed`` has no actuated joint in common with the repertoire's
            body.
    """
    mapped = MappedRepertoire.of(repertoire, changed)
    search = Adaptation(repertoire=mapped, trials=trials, length_scale=length_scale)
    rules = mapped.rules()
    from qdsega.locomotion.exact_trials import ExactTrials  # starts PyBullet: only here

    start = time.perf_counter()
    with ExactTrials(formation=mapped.changed, rules=rules, workers=1) as exact:
        for ask in _asked(search, progress):
            policy = SequencePolicy(commands=ask.cycle)
            (trial,) = exact.rollouts([policy], steps=rules.task.trial_steps)
            search.tell(trial.distance_m, failure=trial.failure, wall_s=time.perf_counter() - start)
    return write_adaptation(
        out,
        search,
        mode="mapped",
        body=mapped.changed,
        joints=mapped.mapping,
        gait=search.best().cycle,
        trial_steps=rules.task.trial_steps,
        wall_s=time.perf_counter() - start,
    )


def adapt_blind(
    repertoire: Path,
    hidden: Formation,
    out: Path,
    *,
    trials: int = DEFAULT_TRIALS,
    length_scale: float = LENGTH_SCALE,
    progress: ProgressFactory | None = None,
) -> dict[str, Any]:
    """Adapt a robot whose change the search does not know: the repertoire's gaits, unmapped,
    as the intact body's joint angles at its timing (what ``--external`` hands a robot),
    played on ``hidden`` (:class:`~qdsega.adaptation.hidden_body.HiddenBody`); write ``out``,
    with the gait found as ``hidden``'s postures. Arguments and errors as :func:`adapt`'s.
    """
    joints = MappedRepertoire.of(repertoire, hidden).mapping  # refuses a body without one
    intact = MappedRepertoire.unmapped(repertoire)
    search = Adaptation(repertoire=intact, trials=trials, length_scale=length_scale)
    rules = intact.rules()  # the intact body's timing and trial: the robot's controller's
    step_s = rules.lower_agent.step_duration_for(intact.changed)
    from qdsega.adaptation.hidden_body import HiddenBody  # starts PyBullet: only here

    start = time.perf_counter()
    robot = HiddenBody(
        body=hidden, world=intact.world, step_s=step_s, commands=rules.task.trial_steps
    )
    with robot:
        for ask in _asked(search, progress):
            trial = robot.play(JointTrajectory.trial(intact.changed, ask.cycle, rules))
            search.tell(trial.distance_m, failure=trial.failure, wall_s=time.perf_counter() - start)
    found = JointTrajectory.of(intact.changed, search.best().cycle, step_s)
    return write_adaptation(
        out,
        search,
        mode="blind",
        body=robot.body,
        joints=joints,
        gait=found.levels_on(robot.body),
        trial_steps=rules.task.trial_steps,
        wall_s=time.perf_counter() - start,
    )


def _asked(search: Adaptation, progress: ProgressFactory | None) -> Iterator[Ask]:
    """Each gait ``search`` asks for, until it is done, the trials shown on ``progress``'s
    line once each is told."""
    line = None if progress is None else progress("adapt", search.budget)
    try:
        while (ask := search.ask()) is not None:
            yield ask
            if line is not None:
                line.update(len(search.played), f"best {max(search.model.observed):.3f} m")
    finally:
        if line is not None:
            line.close()


def write_adaptation(
    out: Path,
    search: Adaptation,
    *,
    mode: str,
    body: Formation,
    joints: JointMapping,
    gait: np.ndarray,
    trial_steps: int,
    wall_s: float,
) -> dict[str, Any]:
    """Write a finished search's ``adapt.json`` and ``gait.csv`` (``gait`` repeated for
    ``trial_steps`` commands) into ``out``; returns the result. ``mode`` is how its trials
    were played (:data:`MODES`), ``body`` the body the gait found is for, ``joints`` the
    intact body's joints onto it, ``gait`` the cycle found (k, J) of ``body``'s level
    indices."""
    repertoire = search.repertoire
    result = {
        "mode": mode,
        "played_on": MODES[mode],
        "repertoire": str(repertoire.path.resolve()),
        "intact": repertoire.record["formation"],
        "formation": body.name,
        "formation_file": None if body.file is None else str(Path(body.file).resolve()),
        "world": repertoire.world.name,
        "joints": joints.report(),
        **search.outcome(),
        "gait": np.asarray(gait).tolist(),
        "wall_s": wall_s,
    }
    out.mkdir(parents=True, exist_ok=True)
    folder = AdaptationFolder(out)
    with replaced_atomically(folder.gait) as partial:
        commands = np.resize(gait, (trial_steps, np.shape(gait)[1]))
        np.savetxt(partial, commands, fmt="%d", delimiter=",")
    with replaced_atomically(folder.result) as partial:
        partial.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    return result


def is_adaptation(folder: Path) -> bool:
    """Whether ``folder`` holds an adaptation's result."""
    return AdaptationFolder(folder).result.is_file()


def warm_start_from(folder: Path, formation: Formation) -> WarmStart:
    """A warm start of ``formation`` from the gait an adaptation of it found: a learner drawn
    at random as a fresh run's, that gait's trial handed on as the elite path, verified on the
    body before the first generation.

    Raises:
        RunFolderError: a corrupt result, or an adaptation of another body.
    """
    try:
        result = json.loads(AdaptationFolder(folder).result.read_text(encoding="utf-8"))
        gait = np.array(result["gait"], dtype=np.int64)
        found = {k: result[k] for k in ("formation", "distance_m", "trials", "joints")}
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise RunFolderError(f"corrupt adaptation ({exc})", file=folder) from None
    if (
        found["formation"] != formation.name
        or gait.ndim != 2
        or gait.shape[1] != len(formation.joints)
    ):
        message = f"an adaptation of {found['formation']}, not of {formation.name}"
        raise RunFolderError(message, file=folder)
    mapping = JointMapping.between(formation, formation)  # the gait is the body's own
    source = LearnerState(
        completed=0,
        population=np.unique(gait, axis=0),
        rng_state={},
        previous=None,
        elite=(np.zeros((0, gait.shape[1]), dtype=np.int64), None),
        elite_path=gait,  # a cycle: verifying it repeats it for a trial
    )
    record = {
        "run": str(folder.resolve()),
        "formation": found["formation"],
        "seed": None,
        "generations": 0,
        "distance_m": found["distance_m"],
        "adapt_trials": len(found["trials"]),
        "joints": mapping.report(),
    }
    return WarmStart(record, mapping, source)
