"""A training run: learn a formation's locomotion and write the run folder.

The run folder holds:

* ``config.yaml``: the fully resolved :class:`~qdsega.training.config.TrainingConfig`;
* ``formation/`` and ``formation.json``: the run's own copy of the formation and its unit
  files, and their hashes (:mod:`qdsega.training.formation_copy`); written with
  ``config.yaml`` before anything slow, so ``--resume`` can start a run stopped at any moment;
* ``train.lock``: locked while a ``qdsega train`` writes the folder
  (:mod:`qdsega.training.run_lock`);
* ``warm_start.json`` and ``warm_start.npz`` (a warm-started run, ``--warm-start RUN``): where
  the run started from (the source run, its formation, seed and distance, how joints matched;
  in memo mode, once verified, ``handed_on_m``: its best path on this body) and what it starts
  from (the joint mapping, the source's last population, Q-table and best path,
  :mod:`qdsega.training.reconfiguration`); written with ``config.yaml``, so the run needs the
  source run no more;
* ``checkpoint.npz``: where the run stands after its last finished generation
  (:mod:`qdsega.training.checkpoint`); ``qdsega train --resume RUN`` continues from it;
* ``metrics.csv``: one row per finished generation (see :data:`METRIC_COLUMNS`);
* ``summary.json`` (written last: its presence means the run is finished): the outcome
  (``distance_m``: the run's result, the greedy policy that went farthest with exact
  physics over all generations (``result_generation``, from 1; ties: the earliest), and its
  distance; ``greedy_distance``: what the learner's world predicted for it; exact optimum,
  budget, wall time, seed; ``formation_file``, the original formation, and
  ``formation_sha256``, its content hash);
  ``optimum`` is the straight-walk optimum of :func:`qdsega.msm.msm_optimum`, exact
  (``optimum_exact``) for a light straight ahead, an upper reference otherwise; null in
  PyBullet worlds (``qdsega evaluate`` measures a reference gait there);
* ``policy.npz``: the result's greedy policy: ``q`` (states, A), ``actions`` (A, J),
  ``postures`` (interior states, J), ``next_interior`` (A,);
* ``transitions.npz`` (memo mode): every measured transition, reused when the run resumes;
* ``trajectories.npz``: what the figures need: ``poses`` (G, steps + 1, 3), the greedy trial
  of every generation in the learner's world (x m, y m, theta rad), and ``exact_poses``, the
  same policies with exact physics; ``gait_postures`` (k + 1, J) and ``gait_legs``
  (k + 1, n_legs), the result's exact trial as postures and as leg states 1..4;
  ``gait_angles_deg`` (k + 1, J) and ``joint_names`` (J,), the same trial as joint angles;
  ``optimum_postures`` (steps + 1, J), the optimum's witness; ``light`` (2,) (m).
"""

from __future__ import annotations

import csv
import json
import math
import shutil
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import numpy as np
import yaml

from qdsega.agent.learner import QDSEGA, Generation, LearnerState
from qdsega.agent.policy import Rollout
from qdsega.atomic import replaced_atomically
from qdsega.description import Formation, load_formation
from qdsega.errors import ConfigError, RunFolderError
from qdsega.training.checkpoint import (
    CHECKPOINT_FILE,
    Checkpoint,
    load_checkpoint,
    save_checkpoint,
)
from qdsega.training.config import TrainingConfig, read_run_config
from qdsega.training.formation_copy import (
    FormationSnapshot,
    load_run_formation,
    read_formation_record,
)
from qdsega.training.interrupt import InterruptWatch
from qdsega.training.reconfiguration import JointMapping, warm_record, warm_state
from qdsega.training.run_folder import (
    POLICY_FILE,
    SUMMARY_FILE,
    WARM_START_FILE,
    WARM_START_STATE,
    read_summary,
    require_finished,
)
from qdsega.training.run_lock import LOCK_FILE, run_lock
from qdsega.training.sims import TrainingSim, build_sim, check_sim, leg_states

METRIC_COLUMNS = (
    "generation",
    "actions",
    "interior_states",
    "q_entries",
    "best_distance_m",
    "mean_distance_m",
    "greedy_distance_m",
    "greedy_exact_m",
    "penalties",
    "steps",
    "sim_steps",
    "wall_s",
)
"""metrics.csv: Q-table actions (columns), interior states and entries (states x actions),
best and mean trial distance toward the light in the learner's world (m), the greedy policy's
distance there (m: the table's prediction in memo mode) and with exact physics (m), trials that
ended in a fall, learning steps (commands), upper-agent steps simulated in PyBullet by the run
so far (memo transitions measured and exact trials' commands; every learning step in exact
mode; 0 in the MSM), wall seconds of the generation (the exact replay included)."""

_SIM_STEPS = METRIC_COLUMNS.index("sim_steps")
_GREEDY_EXACT = METRIC_COLUMNS.index("greedy_exact_m")
_FLOAT_COLUMNS = {
    "best_distance_m",
    "mean_distance_m",
    "greedy_distance_m",
    "greedy_exact_m",
    "wall_s",
}


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

    def generation(self, report: GenerationReport) -> None: ...


def train(
    formation_file: Path | str,
    config: TrainingConfig,
    out: Path | str,
    *,
    overwrite: bool = False,
    progress: Progress | None = None,
    warm_start: Path | None = None,
    allow_unmatched: bool = False,
) -> dict[str, Any]:
    """Train with ``config`` and write the new run folder ``out``; return the summary.

    ``config.yaml`` and the formation's copy are written first, before anything slow, so that
    :func:`resume` can continue a run stopped at any moment.

    Args:
        overwrite: delete the run folder ``out`` first if it exists.
        warm_start: a finished run folder to start from: its last population and Q-table,
            mapped onto this formation by joint name
            (:mod:`qdsega.training.reconfiguration`).
        allow_unmatched: warm-start even from a run that shares no joint name with this
            formation.

    Raises:
        RunFolderError: ``out`` exists (and ``overwrite`` is not set, or it is not a run
            folder), or another process is writing it; unreadable formation, or one the chosen
            world cannot model; a warm start from a missing or unfinished run, from one whose
            exterior states differ, or (without ``allow_unmatched``) from an unrelated body.
        TrainingInterrupted: Ctrl-C; ``out`` holds the last finished generation.
    """
    out = Path(out)
    original = load_formation(formation_file)
    check_sim(config.with_light(original), config)
    warm = None
    if warm_start is not None:
        warm = _warm_source(Path(warm_start), original, config, allow_unmatched)
    snapshot = FormationSnapshot.of(original)
    if out.exists() and not out.is_dir():
        raise RunFolderError("not a folder; choose another --out", file=out)
    if _contents(out) and not (out / "config.yaml").is_file():
        raise RunFolderError("not empty and not a run folder (no config.yaml)", file=out)
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
        with replaced_atomically(out / "config.yaml") as partial:
            partial.write_text(yaml.safe_dump(config.to_dict(), sort_keys=False), encoding="utf-8")
        snapshot.write(out)
        if warm is not None:
            record, mapping, source = warm
            mapping.save(out / WARM_START_STATE, source)
            with replaced_atomically(out / WARM_START_FILE) as partial:
                partial.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
        return _run(out, load_run_formation(out, config), config, None, progress)


def _warm_source(
    run: Path, formation: Formation, config: TrainingConfig, allow_unmatched: bool
) -> tuple[dict[str, Any], JointMapping, LearnerState]:
    """What a warm start from ``run`` needs: its record, the joint mapping onto
    ``formation`` and the run's last learner state.

    Raises:
        RunFolderError: see :func:`train`.
    """
    require_finished(run, "config.yaml", CHECKPOINT_FILE)
    source_config = read_run_config(run)
    checkpoint = load_checkpoint(run)
    if checkpoint is None or checkpoint.learner.previous is None:
        raise RunFolderError(f"not a finished run folder (no {CHECKPOINT_FILE})", file=run)
    if source_config.task.exterior_bin_edges_deg != config.task.exterior_bin_edges_deg:
        raise ConfigError(
            "its exterior states (task.exterior_bin_edges_deg) differ from this run's; its "
            "Q-table cannot carry over",
            file=run,
        )
    source_formation = load_run_formation(run, source_config)
    mapping = JointMapping.between(source_formation, formation)
    if not mapping.matched and not allow_unmatched:
        raise RunFolderError(
            f"{source_formation.name} shares no joint name with {formation.name}; nothing "
            "carries over (give --allow-unmatched to start from it anyway)",
            file=run,
        )
    return warm_record(run, read_summary(run), mapping), mapping, checkpoint.learner


def resume(run: Path | str, *, progress: Progress | None = None) -> dict[str, Any]:
    """Continue the run folder ``run`` from its checkpoint, or from its start when it stopped
    before the first one; return the summary.

    Raises:
        RunFolderError: missing, corrupt or finished run folder; another process is writing it.
        TrainingInterrupted: Ctrl-C; ``run`` holds the last finished generation.
    """
    run = Path(run)
    if not run.is_dir():
        raise RunFolderError("run folder not found", file=run)
    if not (run / "config.yaml").is_file():
        raise RunFolderError(
            "nothing to resume (no config.yaml); start the run with "
            f"qdsega train FORMATION --out {run}",
            file=run,
        )
    config = read_run_config(run)
    with run_lock(run):
        if (run / SUMMARY_FILE).is_file():
            raise RunFolderError(
                f"run is finished ({SUMMARY_FILE} exists); nothing to resume", file=run
            )
        formation = load_run_formation(run, config)
        return _run(run, formation, config, load_checkpoint(run), progress)


def _contents(folder: Path) -> list[Path]:
    """What ``folder`` holds besides its lock file (nothing when it does not exist)."""
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if p.name != LOCK_FILE)


def _run(
    out: Path,
    formation: Formation,
    config: TrainingConfig,
    checkpoint: Checkpoint | None,
    progress: Progress | None,
) -> dict[str, Any]:
    session_start = time.perf_counter()
    world = build_sim(formation, config, out)
    try:
        learner = QDSEGA(
            config=config.agent,
            levels=np.array([len(j.levels_rad) for j in formation.joints]),
            world=world.provider,
            task=world.task,
            rng=np.random.default_rng(config.seed),
        )
        if checkpoint is None:
            if (out / WARM_START_STATE).is_file():
                mapping, source = JointMapping.load(out / WARM_START_STATE)
                learner.restore(
                    warm_state(
                        mapping,
                        source,
                        levels=learner.levels,
                        start=world.provider.start_posture(),
                        population=config.agent.genetic.population,
                        rng=learner.rng,
                    )
                )
            checkpoint = _first_checkpoint(formation, config, learner)
            save_checkpoint(out, checkpoint)
        else:
            try:
                learner.restore(checkpoint.learner)
                world.restore(checkpoint.world)
            except ValueError as exc:
                message = f"checkpoint.npz does not fit config.yaml ({exc})"
                raise RunFolderError(message, file=out) from None
        first_elapsed, resumed_at = checkpoint.elapsed_s, checkpoint.learner.completed
        simulated = int(checkpoint.metrics[-1, _SIM_STEPS]) if len(checkpoint.metrics) else 0
        if progress is not None:
            progress.start(completed=resumed_at, generations=config.agent.genetic.generations)
        with InterruptWatch() as watch:
            try:
                while learner.completed < config.agent.genetic.generations:
                    handed_on = world.verify_untried(learner)
                    if handed_on is not None:
                        _record_handed_on(out, handed_on)
                    generation = learner.step()
                    trials = world.replay(generation, learner)
                    exact = trials[0]  # the greedy replay
                    for trial in trials:
                        learner.verify(trial)
                    elapsed = first_elapsed + time.perf_counter() - session_start
                    sim_steps = simulated + world.simulated_steps()
                    checkpoint = _advance(
                        checkpoint, generation, exact, learner, world, sim_steps, elapsed
                    )
                    world.save(out)
                    save_checkpoint(out, checkpoint)
                    _write_metrics(out, checkpoint.metrics)
                    if progress is not None:
                        report = _report(
                            checkpoint, generation, exact, config, session_start, resumed_at
                        )
                        progress.generation(report)
                return _finish(out, formation, config, world, checkpoint)
            except BaseException as exc:
                if not (watch.interrupted or isinstance(exc, KeyboardInterrupt)):
                    raise
                world.save(out)  # transitions measured since the checkpoint are kept too
                raise TrainingInterrupted(out, checkpoint.learner.completed) from None
    finally:
        world.close()


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
    world: TrainingSim,
    sim_steps: int,
    elapsed_s: float,
) -> Checkpoint:
    """The checkpoint after ``generation`` and its exact replay (the learner has already
    reproduced); ``sim_steps``: the run's simulated steps so far. The generation becomes the
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
        world=world.state(),
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


def _write_metrics(out: Path, metrics: np.ndarray) -> None:
    """metrics.csv from the checkpoint's rows, written then renamed."""
    with (
        replaced_atomically(out / "metrics.csv") as partial,
        partial.open("w", newline="", encoding="utf-8") as stream,
    ):
        writer = csv.writer(stream)
        writer.writerow(METRIC_COLUMNS)
        for row in metrics:
            writer.writerow(
                f"{value:.6f}" if name in _FLOAT_COLUMNS else str(int(value))
                for name, value in zip(METRIC_COLUMNS, row, strict=True)
            )


def _finish(
    out: Path,
    formation: Formation,
    config: TrainingConfig,
    world: TrainingSim,
    checkpoint: Checkpoint,
) -> dict[str, Any]:
    """Write trajectories.npz, policy.npz and, last, summary.json from the final checkpoint."""
    policy = checkpoint.result_policy
    assert policy is not None, "a finished run has learnt a generation"
    light = tuple(float(v) for v in world.task.light)
    optimum = world.optimum
    gait = checkpoint.gait
    np.savez_compressed(
        out / "trajectories.npz",
        poses=checkpoint.poses,
        exact_poses=checkpoint.exact_poses,
        gait_postures=gait,
        gait_angles_deg=np.degrees([formation.posture_rad(p) for p in gait]),
        joint_names=np.array([j.name for j in formation.joints], dtype=str),
        gait_legs=leg_states(world.layout, gait),
        leg_names=np.array([] if world.layout is None else world.layout.names, dtype=str),
        optimum_postures=np.zeros((0, len(formation.joints)), dtype=np.int64)
        if optimum is None
        else optimum.postures,
        light=np.array(light),
    )
    policy.save(out / POLICY_FILE)
    last = checkpoint.metrics[-1]
    best = checkpoint.metrics[checkpoint.result - 1]
    greedy_distance = float(best[METRIC_COLUMNS.index("greedy_distance_m")])
    distance = float(best[_GREEDY_EXACT])
    summary = {
        "formation": formation.name,
        **read_formation_record(out).summary(),
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
        "optimum_exact": None if optimum is None else optimum.exact,
        "greedy_over_optimum": None if optimum is None else distance / optimum.bound_m,
        "final_heading_deg": math.degrees(checkpoint.exact_poses[checkpoint.result - 1, -1, 2]),
        "light_xy": list(light),
        "wall_s": checkpoint.elapsed_s,
        "warm_start": _read_warm_record(out),
    }
    with replaced_atomically(out / SUMMARY_FILE) as partial:
        partial.write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    return summary


def _read_warm_record(run: Path) -> dict[str, Any] | None:
    """``warm_start.json`` of a warm-started run, else None."""
    file = run / WARM_START_FILE
    return json.loads(file.read_text(encoding="utf-8")) if file.is_file() else None


def _record_handed_on(run: Path, trial: Rollout) -> None:
    """Add to ``warm_start.json`` how far the handed-on path walked on this body with
    exact physics (``handed_on_m``, m), verified before the first generation, and the
    commands that took (``handed_on_steps``: its simulated steps)."""
    record = _read_warm_record(run)
    assert record is not None, "only a warm start hands a path on"
    record["handed_on_m"] = trial.distance_m
    record["handed_on_steps"] = len(trial.postures)
    with replaced_atomically(run / WARM_START_FILE) as partial:
        partial.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")


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
