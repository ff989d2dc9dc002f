"""Trial and error on a changed body, guided by the intact body's repertoire (IT&E).

Every elite gait of the repertoire is mapped onto the changed body joint by joint
(:class:`qdsega.training.joint_mapping.JointMapping`: matched joints at the nearest level,
added ones at rest, dropped and locked ones gone). Then, one exact trial at a time, the gait of
the highest upper confidence bound of the trial model (:class:`qdsega.adaptation.trial_model.
TrialModel`, the archive's fitness as its prior mean) is played on the changed body, and the
model learns what it did; the search stops when no untried gait is predicted to beat the best
trial, or after ``trials`` trials. Nothing is random: the same repertoire and body
give the same trials.

An adaptation folder holds ``adapt.json`` (the trials, the gait found, why it stopped, the
joints' mapping) and ``gait.csv`` (the trial of the gait found: its cycle repeated for a
trial's commands, one posture of level indices a row, as ``qdsega render FORMATION
--postures`` takes it). ``qdsega train CHANGED --warm-start DIR`` goes on from the gait found
(:func:`warm_start_from`).
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.adaptation.folders import AdaptationFolder
from qdsega.adaptation.repertoire import load_repertoire
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
"""Exact trials an adaptation may run (IT&E's budget)."""


@dataclass(frozen=True)
class MappedRepertoire:
    """A repertoire's elite gaits mapped onto a changed body joint by joint.

    Attributes:
        record: the repertoire's record (``repertoire.json``).
        changed: the changed body, lit by the repertoire's world.
        world: the world the repertoire was built in.
        mapping: the intact body's joints onto the changed body's.
        cells: the archive's filled cells (C,).
        gaits: each filled cell's elite cycle on the changed body (k, J_changed).
        prior: each one's distance on the intact body (C,) (m).
        descriptors: each one's descriptor on the intact body (C, D).
    """

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
            record=record,
            changed=changed,
            world=world,
            mapping=mapping,
            cells=cells,
            gaits=[mapping.postures(archive.gait(int(c)), rest) for c in cells],
            prior=archive.fitness[cells],
            descriptors=archive.descriptors[cells],
        )

    def rules(self) -> ExactRules:
        """The changed body's own rules (its memo preset's task, lower agent and physics) in
        the repertoire's world: what every trial is judged by."""
        return resolve_config(overrides={"sim": "memo"}, formation=self.changed).rules(self.world)


def adapt(
    repertoire: Path,
    changed: Formation,
    out: Path,
    *,
    trials: int = DEFAULT_TRIALS,
    length_scale: float = LENGTH_SCALE,
    progress: ProgressFactory | None = None,
) -> dict[str, Any]:
    """Adapt ``changed`` with the repertoire in folder ``repertoire``; write ``out``.
    ``length_scale`` is the trial model's (:class:`TrialModel`); ``progress`` shows the trials
    run of at most ``trials`` (None: silent).

    Raises:
        RunFolderError: not a repertoire, or a corrupt one.
        FormationError: ``changed`` has no actuated joint in common with the repertoire's
            body.
    """
    if trials < 1:
        raise ValueError(f"trials must be at least 1, got {trials}")
    mapped = MappedRepertoire.of(repertoire, changed)
    changed, cells, gaits, prior = mapped.changed, mapped.cells, mapped.gaits, mapped.prior
    model = TrialModel(
        descriptors=mapped.descriptors,
        prior=prior,
        signal=max(float(np.std(prior)), 0.1 * float(np.max(np.abs(prior))), 1e-3),
        length_scale=length_scale,
    )
    rules = mapped.rules()
    from qdsega.locomotion.exact_trials import ExactTrials  # starts PyBullet: only here

    start = time.perf_counter()
    played: list[dict[str, Any]] = []
    line = None if progress is None else progress("adapt", min(trials, len(cells)))
    with ExactTrials(formation=changed, rules=rules, workers=1) as exact:
        while not model.done(trials):
            k = model.next_cell()
            mean, _ = model.posterior()
            (trial,) = exact.rollouts(
                [SequencePolicy(commands=gaits[k])], steps=rules.task.trial_steps
            )
            model.tell(k, trial.distance_m)
            played.append(
                {
                    "cell": int(cells[k]),
                    "predicted_m": float(mean[k]),
                    "intact_m": float(prior[k]),
                    "distance_m": trial.distance_m,
                    "failure": trial.failure,
                    "wall_s": time.perf_counter() - start,
                }
            )
            if line is not None:
                line.update(len(played), f"best {max(model.observed):.3f} m")
    if line is not None:
        line.close()
    mean, _ = model.posterior()
    best = int(np.argmax(model.observed))
    found = model.tried[best]
    settled = model.settled()
    result = {
        "repertoire": str(repertoire.resolve()),
        "intact": mapped.record["formation"],
        "formation": changed.name,
        "formation_file": None if changed.file is None else str(Path(changed.file).resolve()),
        "world": mapped.world.name,
        "joints": mapped.mapping.report(),
        "trials": played,
        "distance_m": model.observed[best],
        "trial_found": best + 1,
        "cell": int(cells[found]),
        "gait": gaits[found].tolist(),
        "stopped": "no untried gait was predicted to beat the best trial"
        if settled
        else f"after {len(played)} trials",
        "best_predicted_m": float(np.max(mean)),
        "wall_s": time.perf_counter() - start,
    }
    out.mkdir(parents=True, exist_ok=True)
    folder = AdaptationFolder(out)
    with replaced_atomically(folder.gait) as partial:
        commands = np.resize(gaits[found], (rules.task.trial_steps, len(changed.joints)))
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
