"""A body's repertoire: a MAP-Elites archive of open-loop posture cycles that walk, each played
in exact physics, built in batches and resumable.

Every gait is played as one trial of the body's own rules (its preset's task, lower agent and
physics, in a world) from the rest posture; one that fails is not kept, so every elite is a
verified gait. The gaits are played in exact physics, not in the memo table: a random cycle
rarely shares a posture with another gait, so each of its k postures (and the rest posture)
would be a new settled start for the table, about a second of simulated time each, and k + 1
of them take about as long to simulate as the trial itself (30 commands of a fraction of a
second each).

The archive is filled in one of two simulators (``RepertoireSettings.fill``):

* ``exact``: MAP-Elites in exact physics, each gait's descriptor measured in its trial
  (:class:`~qdsega.adaptation.descriptor.GaitDescriptor`); any body.
* ``msm``: MAP-Elites in the Minimal Simulation Model (:mod:`qdsega.adaptation.msm_fill`),
  then every elite played once in exact physics, which keeps the ones that walk at their exact
  distance, in their cells; legged bodies. It fills a large archive in minutes, and holds the
  gaits a body walks with once a leg no longer works, which an exact search keeps too few of.

A build may be seeded with a finished run's verified gaits (:func:`run_gaits`): they are
played first, so the archive starts from the run's best and varies it.

A repertoire folder holds ``repertoire.npz`` (the archive, the search's state) and
``repertoire.json`` (what it is of and how it was built); both are replaced after every batch,
so a build that is stopped, however, continues from its last batch to the same archive. Like a
run folder, it keeps its own copy of the formation (``formation/``, ``formation.json``) and of
the world (``world.yaml``), which adaptation reads. :func:`export_repertoire` writes its elites
as ``elites.csv`` (:func:`write_elites`).
"""

from __future__ import annotations

import csv
import hashlib
import json
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from qdsega.adaptation.archive import QD_OFFSET_M, Archive, cvt_centroids, grid_centroids
from qdsega.adaptation.descriptor import GaitDescriptor
from qdsega.adaptation.fills import FILLS, fill_name
from qdsega.adaptation.folders import RepertoireFolder
from qdsega.adaptation.map_elites import MapElites
from qdsega.adaptation.msm_fill import DESCRIPTOR as MSM_DESCRIPTOR
from qdsega.adaptation.msm_fill import commanded_duty, fill_in_msm
from qdsega.atomic import replaced_atomically
from qdsega.description import Formation
from qdsega.errors import RunFolderError
from qdsega.locomotion.rules import ExactRules
from qdsega.msm import LegLayout
from qdsega.progress import ProgressFactory
from qdsega.training.finished_run import FinishedRun
from qdsega.training.formation_copy import FormationSnapshot, copy_world
from qdsega.training.run_folder import RunFolder

if TYPE_CHECKING:
    from qdsega.locomotion.exact_trials import CycleTrial

GRID_DIMS = 2
"""Descriptor spaces of at most this many dimensions get a regular grid, larger ones a CVT."""


@dataclass(frozen=True, kw_only=True)
class RepertoireSettings:
    """How a repertoire is built.

    Attributes:
        fill: the simulator the archive is filled in, ``pybullet`` or ``msm`` (module
            docstring; ``exact``, the name before 0.2.0, reads as ``pybullet``).
        evaluations: gaits played in that simulator (-); an MSM fill then plays each elite in
            exact physics.
        cells: the archive's cells, about (a grid rounds to a whole number a side) (-).
        batch: gaits played between two saves (-).
        initial: random gaits before variations of elites (-).
        max_cycle: the longest cycle, in postures (-).
        seed: the seed of the CVT and of the search.
    """

    fill: str = "pybullet"
    evaluations: int = FILLS["pybullet"][0]
    cells: int = FILLS["pybullet"][1]
    batch: int = 32
    initial: int = 200
    max_cycle: int = 6
    seed: int = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "fill", fill_name(self.fill))
        if self.fill not in FILLS:
            raise ValueError(f"fill must be one of {', '.join(FILLS)}, got {self.fill!r}")
        for name in ("evaluations", "cells", "batch", "initial"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")
        if self.max_cycle < 2:
            raise ValueError(f"max_cycle must be at least 2, got {self.max_cycle}")


def empty_archive(
    formation: Formation, settings: RepertoireSettings, *, longest: int = 0
) -> Archive:
    """The archive a repertoire of ``formation`` starts from, for cycles of up to
    ``settings.max_cycle`` postures or ``longest`` (a seed's), the larger."""
    dims = GaitDescriptor.of(formation).size
    if dims <= GRID_DIMS:
        centroids = grid_centroids(dims, max(1, round(settings.cells ** (1 / dims))))
    else:
        rng = np.random.default_rng([settings.seed, 1])
        centroids = cvt_centroids(dims, settings.cells, rng)
    max_cycle = max(settings.max_cycle, longest)
    return Archive.empty(centroids, max_cycle=max_cycle, n_joints=len(formation.joints))


def run_gaits(run: FinishedRun) -> list[np.ndarray]:
    """A finished run's verified gaits, to seed a repertoire: its elite path (its best trial
    verified in exact physics) and its result's exact replay, each one trial's postures (k, J).

    Raises:
        RunFolderError: no checkpoint, or a corrupt one.
    """
    checkpoint = run.checkpoint
    if checkpoint is None:
        raise RunFolderError(f"not a finished run (no {RunFolder.CHECKPOINT})", file=run.path)
    paths = [checkpoint.learner.elite_path, checkpoint.gait[1:]]  # the replay's start is rest
    gaits: list[np.ndarray] = []
    for path in paths:
        path = None if path is None else np.asarray(path, dtype=np.int64)
        if path is not None and len(path) and not any(np.array_equal(path, g) for g in gaits):
            gaits.append(path)
    return gaits


def build_repertoire(
    formation: Formation,
    out: Path,
    *,
    rules: ExactRules,
    settings: RepertoireSettings,
    workers: int,
    seeds: Sequence[np.ndarray] = (),
    seeded_from: Path | None = None,
    progress: ProgressFactory | None = None,
) -> dict[str, Any]:
    """Build (or continue) the repertoire of ``formation`` in folder ``out``; returns its
    record (``repertoire.json``). ``seeds`` (gaits (k, J), from run ``seeded_from``) are
    played first.

    Raises:
        RunFolderError: ``out`` holds a repertoire of another body or other settings, or a
            corrupt one.
    """
    levels = np.array([len(j.levels_rad) for j in formation.joints], dtype=np.int64)
    record = _record(formation, rules, settings, seeds, seeded_from)
    longest = max((len(g) for g in seeds), default=0)
    archive, search, told, elapsed = _resume(out, formation, settings, record, longest)
    describe = _describer(formation, settings)
    budget = settings.evaluations
    start = time.perf_counter()
    if settings.fill == "msm":  # the MSM's elites are the gaits exact physics plays
        shape = archive.gaits.shape
        fast = Archive.empty(archive.centroids, max_cycle=shape[1], n_joints=shape[2])
        fill_in_msm(
            formation,
            fast,
            task=rules.task,
            evaluations=settings.evaluations,
            initial=settings.initial,
            max_cycle=settings.max_cycle,
            rng=np.random.default_rng([settings.seed, 3]),
            seeds=seeds,
            progress=progress,
        )
        seeds = [*seeds, *(fast.gait(int(c)) for c in fast.filled)]
        budget = len(seeds)
    if told == 0:
        snapshot = FormationSnapshot.of(formation)  # read before anything is written
        out.mkdir(parents=True, exist_ok=True)
        snapshot.write(out)
        copy_world(rules.world, out)
    emitter = MapElites(
        archive=archive,
        levels=levels,
        rng=search,
        initial=settings.initial,
        cycle=settings.max_cycle,
        seeds=seeds,
    )
    emitter.told = told
    line = None
    if progress is not None:
        line = progress("repertoire", budget, initial=emitter.told)
    from qdsega.locomotion.exact_trials import ExactTrials  # starts PyBullet: only here

    try:
        with ExactTrials(formation=formation, rules=rules, workers=workers) as trials:
            while emitter.told < budget:
                gaits = emitter.ask(min(settings.batch, budget - emitter.told))
                played = trials.cycles(gaits, steps=rules.task.trial_steps)
                descriptors = [describe(g, t) for g, t in zip(gaits, played, strict=True)]
                rollouts = [t.rollout for t in played]
                distances = [np.nan if t.failed else t.distance_m for t in rollouts]
                emitter.tell(gaits, np.array(descriptors), np.array(distances))
                record.update(
                    evaluations_done=emitter.told,
                    wall_s=elapsed + time.perf_counter() - start,
                    **archive_summary(archive),
                )
                _save(out, archive, emitter, record)
                if line is not None:
                    line.update(emitter.told, f"{len(archive.filled)} cells filled")
    finally:
        if line is not None:
            line.close()
    return record


def archive_summary(archive: Archive) -> dict[str, Any]:
    """What a repertoire's record says of its archive: cells filled, coverage, the best
    distance (m, None where empty), the QD-score and its offset (m)."""
    filled = len(archive.filled)
    return {
        "filled": filled,
        "coverage": archive.coverage,
        "best_m": float(archive.fitness[archive.best()]) if filled else None,
        "qd_score": archive.qd_score,
        "qd_offset_m": QD_OFFSET_M,
    }


def write_elites(archive: Archive, record: dict[str, Any], path: Path) -> None:
    """The archive's elites as CSV at ``path``, the farthest first, a row each: the cell, the
    distance (m), each descriptor value, the cycle's length and the cycle itself, its postures
    separated by ``;`` and each posture's level indices (in the record's joint order) by
    spaces."""
    names = [f"descriptor_{name}" for name in record["descriptor_names"]]
    cells = sorted((int(c) for c in archive.filled), key=lambda c: (-archive.fitness[c], c))
    with replaced_atomically(path) as partial, partial.open("w", newline="") as stream:
        writer = csv.writer(stream, lineterminator="\n")
        writer.writerow(["cell", "distance_m", *names, "postures", "gait"])
        for cell in cells:
            gait = archive.gait(cell)
            writer.writerow(
                [
                    cell,
                    float(archive.fitness[cell]),
                    *(float(v) for v in archive.descriptors[cell]),
                    len(gait),
                    ";".join(" ".join(str(level) for level in posture) for posture in gait),
                ]
            )


def export_repertoire(folder: Path) -> tuple[Archive, dict[str, Any]]:
    """Write a repertoire folder's ``elites.csv`` and bring its record's summary (QD-score
    included) up to its archive; returns the archive and the record.

    Raises:
        RunFolderError: no repertoire there, or a corrupt one.
    """
    archive, record = load_repertoire(folder)
    files = RepertoireFolder(folder)
    write_elites(archive, record, files.elites)
    record.update(archive_summary(archive))
    _write_record(folder, record)
    return archive, record


def _describer(
    formation: Formation, settings: RepertoireSettings
) -> Callable[[np.ndarray, CycleTrial], np.ndarray]:
    """How the build describes a gait from its exact trial: measured for a PyBullet fill, the
    commands' duty factors (the cells the MSM filled) for an MSM fill."""
    if settings.fill == "msm":
        legs = LegLayout.from_formation(formation)
        return lambda gait, _trial: commanded_duty(legs, gait)
    measured = GaitDescriptor.of(formation)
    return lambda gait, trial: measured(trial.contacts, trial.rollout.poses, len(gait))


def load_repertoire(folder: Path) -> tuple[Archive, dict[str, Any]]:
    """The archive and record of a repertoire folder.

    Raises:
        RunFolderError: no repertoire there, or a corrupt one.
    """
    files = RepertoireFolder(folder)
    if not files.archive.is_file() or not files.record.is_file():
        message = f"not a repertoire (no {files.archive.name} and {files.record.name})"
        raise RunFolderError(message, file=folder)
    try:
        record = json.loads(files.record.read_text(encoding="utf-8"))
        with np.load(files.archive) as data:
            archive = Archive.from_state({k: data[k] for k in data.files})
            int(data["told"])
        if not isinstance(record, dict) or len(record["joints"]) != archive.gaits.shape[2]:
            raise ValueError("the record's joints do not fit the archive")
        if len(record["descriptor_names"]) != archive.centroids.shape[1]:
            raise ValueError("the record's descriptor names do not fit the archive")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise RunFolderError(f"corrupt repertoire ({exc})", file=folder) from None
    return archive, record


def _record(
    formation: Formation,
    rules: ExactRules,
    settings: RepertoireSettings,
    seeds: Sequence[np.ndarray],
    seeded_from: Path | None,
) -> dict[str, Any]:
    descriptor = GaitDescriptor.of(formation)
    kind = MSM_DESCRIPTOR if settings.fill == "msm" else descriptor.kind
    digest = hashlib.sha256()
    for gait in seeds:
        digest.update(np.ascontiguousarray(gait, dtype=np.int64).tobytes() + b";")
    return {
        "formation": formation.name,
        "joints": [j.name for j in formation.joints],
        "levels": [len(j.levels_rad) for j in formation.joints],
        "world": rules.world.name,
        "descriptor": kind,
        "descriptor_names": list(descriptor.names),
        "trial_steps": rules.task.trial_steps,
        "settings": asdict(settings),
        "seeds": {
            "run": None if seeded_from is None else str(seeded_from.resolve()),
            "gaits": len(seeds),
            "sha256": digest.hexdigest(),
        },
    }


def _resume(
    out: Path,
    formation: Formation,
    settings: RepertoireSettings,
    record: dict[str, Any],
    longest: int,
) -> tuple[Archive, np.random.Generator, int, float]:
    """The archive, the search's generator, the gaits played and the wall time so far: from
    ``out`` where it holds a repertoire, else fresh."""
    search = np.random.default_rng([settings.seed, 2])
    if not RepertoireFolder(out).archive.is_file():
        return empty_archive(formation, settings, longest=longest), search, 0, 0.0
    archive, saved = load_repertoire(out)
    keys = ("formation", "joints", "levels", "world", "descriptor", "settings", "seeds")
    mine: dict[str, Any]
    theirs: dict[str, Any]
    mine, theirs = ({k: dict(r.get(k) or {}) if k == "settings" else r.get(k) for k in keys}
                    for r in (record, saved))  # fmt: skip
    if "fill" in theirs["settings"]:  # a record from before 0.2.0 may say "exact"
        theirs["settings"]["fill"] = fill_name(theirs["settings"]["fill"])
    if settings.fill == "pybullet":  # a PyBullet build may go on to a larger budget
        for both in (mine, theirs):
            both["settings"].pop("evaluations", None)
    if mine != theirs:
        message = (
            "holds a repertoire of another body, world, descriptor, settings or seeds; choose "
            "another --out"
        )
        raise RunFolderError(message, file=out)
    with np.load(RepertoireFolder(out).archive) as data:
        search.bit_generator.state = json.loads(str(data["search_state"]))
        told = int(data["told"])
    return archive, search, told, float(saved.get("wall_s", 0.0))


def _save(out: Path, archive: Archive, emitter: MapElites, record: dict[str, Any]) -> None:
    """The record, then the archive with the search's state and count. In this order a build
    killed between the two still resumes: it goes on from the archive, whose batch the
    record is at most one ahead of (the record is read only for its wall time)."""
    state = json.dumps(emitter.rng.bit_generator.state)
    told = np.array(emitter.told)
    _write_record(out, record)
    with replaced_atomically(RepertoireFolder(out).archive) as partial:
        arrays = {"search_state": np.array(state), "told": told, **archive.state()}
        # numpy's stubs match **arrays against savez_compressed's allow_pickle: bool
        np.savez_compressed(partial, **arrays)  # type: ignore[arg-type]


def _write_record(out: Path, record: dict[str, Any]) -> None:
    """``repertoire.json``, written then renamed."""
    with replaced_atomically(RepertoireFolder(out).record) as partial:
        partial.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
