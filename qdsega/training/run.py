"""A training run: learn a formation's locomotion and write the run folder
(``docs/run-folder.md`` specifies every file).

The loop is one-way, ask and tell: the learner learns a generation, the run asks the
simulator to replay what it proposes with exact physics (the generation's greedy policy,
exploring trials, the local search), and tells the learner how those trials walked. The
simulator never calls the learner.
"""

from __future__ import annotations

import math
import shutil
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import numpy as np
import yaml

from qdsega.agent.learner import QDSEGA, Generation
from qdsega.agent.policy import Rollout, SequencePolicy
from qdsega.agent.verification import Verification
from qdsega.atomic import replaced_atomically
from qdsega.description import Formation, World, load_formation
from qdsega.errors import ConfigError, QdsegaWarning, RunFolderError
from qdsega.progress import ProgressLine
from qdsega.training.checkpoint import Checkpoint, load_checkpoint, save_checkpoint
from qdsega.training.config import TrainingConfig, read_run_config
from qdsega.training.finished_run import FinishedRun
from qdsega.training.formation_copy import (
    FormationSnapshot,
    copy_world,
    load_run_formation,
    load_run_world,
    read_formation_record,
    world_sha256,
)
from qdsega.training.interrupt import InterruptWatch
from qdsega.training.joint_mapping import JointMapping
from qdsega.training.reconfiguration import WarmStart, warm_record, warm_state
from qdsega.training.run_folder import METRIC_COLUMNS, RunFolder
from qdsega.training.run_lock import run_lock
from qdsega.training.sims import (
    Failures,
    TrainingSim,
    build_sim,
    build_verification,
    check_sim,
    leg_states,
    memo_starts,
)

PREDICTION_TOLERANCE = 0.10
"""The learner's model predicts a result well when its prediction is this close to exact
physics (relative): the memo table holds where the run went."""
HOPELESS_SHARE = 0.9
"""A generation whose verified trials' commands failed at least this often (nearly every trial
failing at its first command) warns once: the body may not be able to move at all."""
MISSES_TO_WARN = 3
"""A memo run warns, while it trains, once its table has mispredicted the greedy policy by more
than ``PREDICTION_TOLERANCE`` this many generations in a row."""
_SIM_STEPS = METRIC_COLUMNS.index("sim_steps")
_GREEDY = METRIC_COLUMNS.index("greedy_distance_m")
_GREEDY_EXACT = METRIC_COLUMNS.index("greedy_exact_m")


@dataclass(frozen=True)
class GenerationReport:
    """What a progress display shows after each generation.

    Attributes:
        generation: generations finished (from 1).
        generations: generations in the run.
        greedy_distance_m: the greedy policy's distance toward the light in the learner's
            world (m).
        greedy_exact_m: the same with exact physics (m).
        actions: Q-table actions.
        q_entries: Q-table entries (states x actions).
        steps_per_s: learning steps (commands) per wall second in this generation.
        elapsed_s: wall time of the run so far, all sessions (s).
        session_s: wall time since this session (start or resume) began (s).
        session_generations: generations finished in this session.
    """

    generation: int
    generations: int
    greedy_distance_m: float
    greedy_exact_m: float
    actions: int
    q_entries: int
    steps_per_s: float
    elapsed_s: float
    session_s: float
    session_generations: int


class TrainingInterrupted(Exception):
    """Ctrl-C during training; the checkpoint of the last finished generation is kept."""

    def __init__(self, run: Path, completed: int) -> None:
        super().__init__(f"interrupted after generation {completed}")
        self.run = run
        self.completed = completed


class Progress(Protocol):
    """Told when a session of the run starts and after every generation."""

    def start(self, *, completed: int, generations: int) -> None: ...

    def generation(self, report: GenerationReport, failed: Failures) -> None:
        """After each generation: what it learnt, and how its verified trials failed."""
        ...


def train(
    formation_file: Path | str,
    config: TrainingConfig,
    out: Path | str,
    *,
    overwrite: bool = False,
    progress: Progress | None = None,
    warm_start: Path | WarmStart | None = None,
    allow_unmatched: bool = False,
    world: World | None = None,
) -> dict[str, Any]:
    """Train with ``config`` and write the new run folder ``out``; return the summary.

    ``config.yaml`` and the copies of the formation and the world are written first, before
    anything slow, so that :func:`resume` can continue a run stopped at any moment.

    Args:
        overwrite: delete the run folder ``out`` first if it exists.
        world: the ground it learns on (default the flat plane); its light, if it has one,
            replaces the formation's.
        warm_start: a finished run folder to start from: its last population and Q-table,
            mapped onto this formation by joint name
            (:mod:`qdsega.training.reconfiguration`); or what to start from, read already
            (a gait ``qdsega adapt`` found).
        allow_unmatched: warm-start even from a run that shares no joint name with this
            formation.

    Raises:
        RunFolderError: ``out`` exists (and ``overwrite`` is not set, or it is not a run
            folder), or another process is writing it; unreadable formation, or one the chosen
            world cannot model; a warm start from a missing or unfinished run, from one whose
            exterior states differ, or (without ``allow_unmatched``) from an unrelated body.
        TrainingInterrupted: Ctrl-C; ``out`` holds the last finished generation.
    """
    return _finished(
        _start(
            formation_file,
            config,
            out,
            overwrite=overwrite,
            progress=progress,
            warm_start=warm_start,
            allow_unmatched=allow_unmatched,
            world=world,
        )
    )


def _start(
    formation_file: Path | str,
    config: TrainingConfig,
    out: Path | str,
    *,
    overwrite: bool = False,
    progress: Progress | None = None,
    warm_start: Path | WarmStart | None = None,
    allow_unmatched: bool = False,
    world: World | None = None,
    until: int | None = None,
) -> dict[str, Any] | None:
    """:func:`train`, stopped after generation ``until`` (None: at the end) with the run left
    resumable (None returned then)."""
    out = Path(out)
    folder = RunFolder(out)
    original = load_formation(formation_file)
    lit = original if world is None else world.lights(original)
    check_sim(config.with_light(lit), config, world)
    if config.sim == "memo" and world is not None and not world.is_plane:
        memo_starts(config.with_light(lit), config, world)  # refused before anything is written
    warm = None
    if warm_start is not None:
        warm = (
            warm_start
            if isinstance(warm_start, WarmStart)
            else _warm_source(Path(warm_start), original, config, allow_unmatched)
        )
    snapshot = FormationSnapshot.of(original)
    if out.exists() and not out.is_dir():
        raise RunFolderError("not a folder; choose another --out", file=out)
    if _contents(out) and not folder.started:
        raise RunFolderError(f"not empty and not a run folder (no {folder.CONFIG})", file=out)
    out.mkdir(parents=True, exist_ok=True)
    with run_lock(out):
        previous = _contents(out)
        if previous and not overwrite:
            raise RunFolderError(
                "run folder exists; continue it with --resume, start it again with "
                "--overwrite, or choose another --out",
                file=out,
            )
        for entry in previous:
            if entry.is_dir():
                shutil.rmtree(entry)
            else:
                entry.unlink()
        with replaced_atomically(folder / folder.CONFIG) as partial:
            partial.write_text(yaml.safe_dump(config.to_dict(), sort_keys=False), encoding="utf-8")
        snapshot.write(out)
        if world is not None:
            copy_world(world, out)
        if warm is not None:
            warm.mapping.save(folder / folder.WARM_START_STATE, warm.source)
            folder.write_json(folder.WARM_START, warm.record)
        formation = load_run_formation(out, config)
        return _run(folder, formation, config, None, progress, until=until)


def _finished(summary: dict[str, Any] | None) -> dict[str, Any]:
    assert summary is not None, "a run not stopped early finishes"
    return summary


def _warm_source(
    run: Path, formation: Formation, config: TrainingConfig, allow_unmatched: bool
) -> WarmStart:
    """What a warm start from ``run`` needs: its record, the joint mapping onto
    ``formation`` and the run's last learner state.

    Raises:
        RunFolderError: see :func:`train`.
    """
    source = FinishedRun.open(run, RunFolder.CONFIG, RunFolder.CHECKPOINT)
    source_config, checkpoint = source.config, source.checkpoint
    if checkpoint is None or checkpoint.learner.previous is None:
        raise RunFolderError(f"not a finished run folder (no {RunFolder.CHECKPOINT})", file=run)
    if source_config.task.exterior_bin_edges_deg != config.task.exterior_bin_edges_deg:
        raise ConfigError(
            "its exterior states (task.exterior_bin_edges_deg) differ from this run's; its "
            "Q-table cannot carry over",
            file=run,
        )
    source_formation = source.formation
    mapping = JointMapping.between(source_formation, formation)
    if not mapping.matched and not allow_unmatched:
        raise RunFolderError(
            f"{source_formation.name} shares no joint name with {formation.name}; nothing "
            "carries over (give --allow-unmatched to start from it anyway)",
            file=run,
        )
    return WarmStart(warm_record(run, source.summary, mapping), mapping, checkpoint.learner)


def resume(run: Path | str, *, progress: Progress | None = None) -> dict[str, Any]:
    """Continue the run folder ``run`` from its checkpoint, or from its start when it stopped
    before the first one; return the summary.

    Raises:
        RunFolderError: missing, corrupt or finished run folder; another process is writing it.
        WorldError: a body that would start inside one of the world's obstacles.
        TrainingInterrupted: Ctrl-C; ``run`` holds the last finished generation.
    """
    return _finished(_continue(run, progress=progress))


def _continue(
    run: Path | str, *, progress: Progress | None = None, until: int | None = None
) -> dict[str, Any] | None:
    """:func:`resume`, stopped after generation ``until`` as :func:`_start` is."""
    run = Path(run)
    folder = RunFolder(run)
    if not run.is_dir():
        raise RunFolderError("run folder not found", file=run)
    if not folder.started:
        raise RunFolderError(
            f"nothing to resume (no {folder.CONFIG}); start the run with "
            f"qdsega train FORMATION --out {run}",
            file=run,
        )
    config = read_run_config(run)
    formation = load_run_formation(run, config)
    check_sim(formation, config, load_run_world(run))  # a folder older than the check
    with run_lock(run):
        if folder.finished:
            raise RunFolderError(
                f"run is finished ({folder.SUMMARY} exists); nothing to resume", file=run
            )
        return _run(folder, formation, config, load_checkpoint(run), progress, until=until)


def train_or_resume(
    formation_file: Path | str,
    config: TrainingConfig,
    out: Path | str,
    *,
    progress: Progress | None = None,
    world: World | None = None,
) -> dict[str, Any]:
    """Make ``out`` a finished run and return its summary: kept when it is finished, resumed
    when it was started, else trained with ``config`` in ``world`` (default flat). Sweeps,
    the benchmark and the experiments make their runs this way, so that running them again
    finishes what a crash left.

    Raises:
        RunFolderError, FormationError, ConfigError: as :func:`train` and :func:`resume`.
        TrainingInterrupted: Ctrl-C; ``out`` holds the last finished generation.
    """
    folder = RunFolder(Path(out))
    if folder.finished:
        folder.require_finished()
        return folder.read_summary()
    if folder.started:
        return resume(out, progress=progress)
    return train(formation_file, config, out, progress=progress, world=world)


def train_until(
    formation_file: Path | str,
    config: TrainingConfig,
    out: Path | str,
    *,
    generations: int,
    world: World | None = None,
) -> int:
    """Learn the run ``out`` (trained with ``config`` in ``world``, or resumed) up to
    generation ``generations`` and stop there, resumable: the first generations of the run
    that :func:`train_or_resume` would finish. Return the generations it has learnt.

    Raises:
        RunFolderError, FormationError, ConfigError: as :func:`train` and :func:`resume`.
        TrainingInterrupted: Ctrl-C; ``out`` holds the last finished generation.
    """
    folder = RunFolder(Path(out))
    if not folder.started:
        _start(formation_file, config, out, world=world, until=generations)
    elif not folder.finished and completed_generations(folder.path) < generations:
        _continue(out, until=generations)
    return completed_generations(folder.path)


def completed_generations(run: Path) -> int:
    """Generations the run folder ``run`` has learnt (its checkpoint's; 0 before the first)."""
    checkpoint = load_checkpoint(run)
    return 0 if checkpoint is None else checkpoint.learner.completed


def _contents(folder: Path) -> list[Path]:
    """What ``folder`` holds besides its lock file (nothing when it does not exist)."""
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if p.name != RunFolder.LOCK)


def _run(
    folder: RunFolder,
    formation: Formation,
    config: TrainingConfig,
    checkpoint: Checkpoint | None,
    progress: Progress | None,
    *,
    until: int | None = None,
) -> dict[str, Any] | None:
    """Learn generations until the run's last (then finish it and return its summary) or
    until generation ``until`` (then leave it resumable and return None)."""
    session_start = time.perf_counter()
    out = folder.path
    sim = build_sim(
        formation,
        config,
        out,
        world=load_run_world(out),
        measuring=None if progress is None else ProgressLine,
    )
    verification = build_verification(config)
    try:
        learner = QDSEGA(
            config=config.agent,
            levels=np.array([len(j.levels_rad) for j in formation.joints]),
            model=sim.provider,
            task=sim.task,
            rng=np.random.default_rng(config.seed),
        )
        if checkpoint is None:
            if (folder / folder.WARM_START_STATE).is_file():
                mapping, source = JointMapping.load(folder / folder.WARM_START_STATE)
                learner.restore(
                    warm_state(
                        mapping,
                        source,
                        levels=learner.levels,
                        start=sim.provider.start_posture(),
                        population=config.agent.genetic.population,
                        rng=learner.rng,
                    )
                )
            checkpoint = _first_checkpoint(formation, config, learner)
            save_checkpoint(out, checkpoint)
        else:
            try:
                learner.restore(checkpoint.learner)
                sim.restore(checkpoint.world)
                verification.restore(checkpoint.world)
            except ValueError as exc:
                message = f"{folder.CHECKPOINT} does not fit {folder.CONFIG} ({exc})"
                raise RunFolderError(message, file=out) from None
        first_elapsed, resumed_at = checkpoint.elapsed_s, checkpoint.learner.completed
        simulated = int(checkpoint.metrics[-1, _SIM_STEPS]) if len(checkpoint.metrics) else 0
        if progress is not None:
            progress.start(completed=resumed_at, generations=config.agent.genetic.generations)
        warned = False
        with InterruptWatch() as watch:
            try:
                last = config.agent.genetic.generations
                while learner.completed < (last if until is None else min(until, last)):
                    before = sim.failures
                    path = learner.untried_path  # a handed-on path no trial has verified
                    if path is not None and sim.exact is not None:
                        handed_on = _verify_path(sim, verification, learner, path)
                        _record_handed_on(folder, handed_on)
                    generation = learner.step()
                    exact = _verify_generation(sim, verification, learner, generation)
                    elapsed = first_elapsed + time.perf_counter() - session_start
                    sim_steps = simulated + sim.simulated_steps()
                    world = {**sim.state(), **verification.state()}
                    checkpoint = _advance(
                        checkpoint, generation, exact, learner, world, sim_steps, elapsed
                    )
                    sim.save(out)
                    save_checkpoint(out, checkpoint)
                    folder.write_metrics(checkpoint.metrics)
                    failed = sim.failures.since(before)
                    if failed.share >= HOPELESS_SHARE and not warned:
                        warned = True
                        warnings.warn(_hopeless(failed, generation.index), QdsegaWarning, 2)
                    misses = table_misses(checkpoint.metrics)
                    if sim.exact is not None and misses == MISSES_TO_WARN:
                        warnings.warn(_unheld(checkpoint.metrics), QdsegaWarning, 2)
                    if progress is not None:
                        report = _report(
                            checkpoint, generation, exact, config, session_start, resumed_at
                        )
                        progress.generation(report, failed)
                if learner.completed < last:
                    return None
                return _finish(folder, formation, config, sim, checkpoint)
            except BaseException as exc:
                if not (watch.interrupted or isinstance(exc, KeyboardInterrupt)):
                    raise
                sim.save(out)  # transitions measured since the checkpoint are kept too
                raise TrainingInterrupted(out, checkpoint.learner.completed) from None
    finally:
        sim.close()


def _first_checkpoint(formation: Formation, config: TrainingConfig, learner: QDSEGA) -> Checkpoint:
    steps = config.task.trial_steps
    return Checkpoint(
        learner=learner.state(),
        metrics=np.zeros((0, len(METRIC_COLUMNS))),
        poses=np.zeros((0, steps + 1, 3)),
        exact_poses=np.zeros((0, steps + 1, 3)),
        gait=np.zeros((0, len(formation.joints)), dtype=np.int64),
        world={},
        env_steps=0,
        elapsed_s=0.0,
        result=0,
        result_policy=None,
    )


def _advance(
    checkpoint: Checkpoint,
    generation: Generation,
    exact: Rollout,
    learner: QDSEGA,
    world: dict[str, np.ndarray],
    sim_steps: int,
    elapsed_s: float,
) -> Checkpoint:
    """The checkpoint after ``generation`` and its exact replay (the learner has already
    reproduced); ``world``: the simulator's and the local search's state; ``sim_steps``: the
    run's simulated steps so far. The generation becomes the
    result when its exact replay goes strictly farther than the result so far."""
    space = generation.space
    result, result_policy, gait = checkpoint.result, checkpoint.result_policy, checkpoint.gait
    best_m = checkpoint.metrics[result - 1, _GREEDY_EXACT] if result else -math.inf
    if exact.distance_m > best_m:
        result = generation.index
        result_policy = generation.policy
        gait = exact.reached_postures(space.postures[0])
    row = [
        generation.index,
        space.n_actions,
        space.n_interior,
        generation.q.size,
        generation.distances.max(),
        generation.distances.mean(),
        generation.greedy.distance_m,
        exact.distance_m,
        int(generation.fell.sum()),
        generation.steps,
        sim_steps,
        generation.wall_s,
    ]
    return Checkpoint(
        learner=learner.state(),
        metrics=np.vstack([checkpoint.metrics, np.array(row, dtype=np.float64)]),
        poses=np.concatenate([checkpoint.poses, generation.greedy.poses[None]]),
        exact_poses=np.concatenate([checkpoint.exact_poses, exact.poses[None]]),
        gait=gait,
        world=world,
        env_steps=checkpoint.env_steps + generation.steps,
        elapsed_s=elapsed_s,
        result=result,
        result_policy=result_policy,
    )


def _report(
    checkpoint: Checkpoint,
    generation: Generation,
    exact: Rollout,
    config: TrainingConfig,
    session_start: float,
    resumed_at: int,
) -> GenerationReport:
    session_s = time.perf_counter() - session_start
    return GenerationReport(
        generation=generation.index,
        generations=config.agent.genetic.generations,
        greedy_distance_m=generation.greedy.distance_m,
        greedy_exact_m=exact.distance_m,
        actions=generation.space.n_actions,
        q_entries=generation.q.size,
        steps_per_s=generation.steps / max(generation.wall_s, 1e-9),
        elapsed_s=checkpoint.elapsed_s,
        session_s=session_s,
        session_generations=generation.index - resumed_at,
    )


def _finish(
    folder: RunFolder,
    formation: Formation,
    config: TrainingConfig,
    sim: TrainingSim,
    checkpoint: Checkpoint,
) -> dict[str, Any]:
    """Write trajectories.npz, policy.npz and, last, summary.json from the final checkpoint."""
    policy = checkpoint.result_policy
    assert policy is not None, "a finished run has learnt a generation"
    light = tuple(float(v) for v in sim.task.light)
    optimum = sim.optimum
    gait = checkpoint.gait
    np.savez_compressed(
        folder / folder.TRAJECTORIES,
        poses=checkpoint.poses,
        exact_poses=checkpoint.exact_poses,
        gait_postures=gait,
        gait_angles_deg=np.degrees([formation.posture_rad(p) for p in gait]),
        joint_names=np.array([j.name for j in formation.joints], dtype=str),
        gait_legs=leg_states(sim.layout, gait),
        leg_names=np.array([] if sim.layout is None else sim.layout.names, dtype=str),
        optimum_postures=np.zeros((0, len(formation.joints)), dtype=np.int64)
        if optimum is None
        else optimum.postures,
        light=np.array(light),
    )
    policy.save(folder / folder.POLICY)
    last = checkpoint.metrics[-1]
    best = checkpoint.metrics[checkpoint.result - 1]
    greedy_distance = float(best[METRIC_COLUMNS.index("greedy_distance_m")])
    distance = float(best[_GREEDY_EXACT])
    summary = {
        "formation": formation.name,
        **read_formation_record(folder.path).summary(),
        "world": sim.world.name,
        "memo_spots": sim.memo_spots(),
        "world_sha256": world_sha256(folder.path),
        "sim": config.sim,
        "preset": config.preset,
        "seed": config.seed,
        "generations": checkpoint.learner.completed,
        "trials_per_generation": config.agent.learning.trials,
        "trial_steps": config.task.trial_steps,
        "env_steps": checkpoint.env_steps,
        "sim_steps": int(last[_SIM_STEPS]),
        "distance_m": distance,
        "result_generation": checkpoint.result,
        "greedy_distance": greedy_distance,
        "prediction_error": _relative_error(greedy_distance, distance),
        "optimum": None if optimum is None else optimum.bound_m,
        "optimum_proven": None if optimum is None else optimum.proven,
        "greedy_over_optimum": None if optimum is None else distance / optimum.bound_m,
        "final_heading_deg": math.degrees(checkpoint.exact_poses[checkpoint.result - 1, -1, 2]),
        "light_xy": list(light),
        "wall_s": checkpoint.elapsed_s,
        "failed_commands_share": sim.failures.share,
        "most_common_failure": sim.failures.most_common,
        "warm_start": folder.read_warm_start(),
    }
    folder.write_json(folder.SUMMARY, summary)
    return summary


def _verify_path(
    sim: TrainingSim, verification: Verification, learner: QDSEGA, path: np.ndarray
) -> Rollout:
    """Play ``path`` (k, J), the path a warm start handed on, open loop with exact physics,
    and tell the learner and the local search how far it walked."""
    (trial,) = sim.play([SequencePolicy(commands=path)])
    sim.observe([trial], sim.provider.start_posture())
    verification.tell([trial])
    learner.verify(trial)
    return trial


def _verify_generation(
    sim: TrainingSim, verification: Verification, learner: QDSEGA, generation: Generation
) -> Rollout:
    """Play what the learner asks of exact physics for ``generation`` (nothing where its world
    is exact) and tell it; returns the greedy policy's exact trial."""
    if sim.exact is None:
        sim.count([generation.greedy])
        learner.verify(generation.greedy)
        return generation.greedy
    played = sim.play(verification.ask(learner, generation, sim.grounded))
    greedy = played[-1]
    verification.tell([greedy])
    searched = sim.play(verification.neighbours(generation.index, learner.levels))
    verification.tell(searched)
    sim.observe([*played[:-1], *searched, greedy], generation.space.postures[0])
    for trial in [greedy, *searched]:
        learner.verify(trial)
    return greedy


def _record_handed_on(folder: RunFolder, trial: Rollout) -> None:
    """Add to ``warm_start.json`` how far the handed-on path walked on this body with
    exact physics (``handed_on_m``, m), verified before the first generation, and the
    commands that took (``handed_on_steps``: its simulated steps)."""
    record = folder.read_warm_start()
    assert record is not None, "only a warm start hands a path on"
    record["handed_on_m"] = trial.distance_m
    record["handed_on_steps"] = len(trial.postures)
    folder.write_json(folder.WARM_START, record)


def _hopeless(failed: Failures, generation: int) -> str:
    """The one-line warning for a generation whose verified trials nearly all failed."""
    return (
        f"{failed.share:.0%} of the commands of generation {generation}'s verified trials "
        f"failed, most often: {failed.most_common}; the body may not be able to move (`qdsega "
        "assemble` checks that its joints reach their levels)"
    )


def table_misses(metrics: np.ndarray) -> int:
    """How many of the last generations in a row (``metrics.csv``'s rows) the learner's model
    mispredicted the greedy policy's exact distance by more than ``PREDICTION_TOLERANCE``."""
    misses = 0
    for row in metrics[::-1]:
        error = _relative_error(float(row[_GREEDY]), float(row[_GREEDY_EXACT]))
        if error is None or abs(error) <= PREDICTION_TOLERANCE:
            break
        misses += 1
    return misses


def _unheld(metrics: np.ndarray) -> str:
    """The one-line warning for a memo run whose table keeps mispredicting."""
    last = metrics[-MISSES_TO_WARN:]
    errors = [_relative_error(float(r[_GREEDY]), float(r[_GREEDY_EXACT])) for r in last]
    shown = ", ".join(f"{e:+.0%}" for e in errors if e is not None)
    first, end = int(last[0, 0]), int(last[-1, 0])
    return (
        f"generations {first}-{end}: the table's predictions were off exact physics by "
        f"{shown} (more than {PREDICTION_TOLERANCE:.0%}): it does not hold where this run goes "
        "(varied ground: docs/worlds.md); the run is judged in exact physics"
    )


def _relative_error(predicted: float, exact: float) -> float | None:
    """``(predicted - exact) / |exact|``, or None when the exact distance is 0."""
    return None if exact == 0 else (predicted - exact) / abs(exact)


def budget_overrides(
    *, generations: int | None, trials: int | None, seed: int | None
) -> dict[str, Any]:
    """CLI budget flags as a :func:`qdsega.training.config.resolve_config` override."""
    overrides: dict[str, Any] = {}
    if seed is not None:
        overrides["seed"] = seed
    if generations is not None:
        overrides.setdefault("agent", {})["genetic"] = {"generations": generations}
    if trials is not None:
        overrides.setdefault("agent", {})["learning"] = {"trials": trials}
    return overrides
