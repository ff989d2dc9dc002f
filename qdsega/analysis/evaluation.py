"""Evaluate a run with exact physics: its greedy policy against a reference gait.

``evaluation.json`` in the run folder holds:

* ``distance_m``: distance toward the light covered in one trial by the run's result policy,
  every step simulated in PyBullet (same lower agent, step duration and trial length as in
  training); ``failure`` says why the trial ended early, if it did;
* ``memo_prediction_m``: what the memo table predicted for that policy (memo runs);
* ``references``: reference gaits under the same rules (levels, lower agent, step duration,
  trial length, physics), each with its kind, parameters and distance (m): the best
  hand-designed one (for a snake, the best serpenoid wave of a grid over amplitude, phase lag
  and steps per cycle, snapped to the joint levels; for a legged body, the best of the classic
  gaits in the paper's four leg states, :mod:`qdsega.baselines.classic_gaits`), and a CPG
  gait CMA-ES found in a budget of exact trials (stated in trials and steps;
  :mod:`qdsega.baselines.reference_search`, cached by content hash); a gait that fails counts
  0 m;
* ``reference``: the best of them (which one won is its ``kind``);
* ``ratio``: ``distance_m / reference.distance_m`` (None when every reference is 0 m);
* ``postures``: the commanded postures (level indices), step by step;
* ``unit_xy_m``: every unit's centre of mass (x, y) (m) at the start and after each step,
  shape (steps + 1, units, 2): the body's shape over the trial (the snake pose strip);
* ``wave`` (formations with two or more joints): the period of the joint-angle sequence and the
  phase lag between neighbouring joints, measured from the commanded angles.

* ``world``: the name of the world it was judged in.

Given another ``world``, ``evaluate_run`` judges the run there instead (a gait learnt on flat
ground, judged on ice), references included, and writes ``evaluation-in-WORLD.json``, without
the memo table's prediction (the table knew the run's own world).

``evaluate_on`` replays the greedy policy on another formation instead (a changed body, its
joints matched by name, :mod:`qdsega.training.reconfiguration`) and writes
``evaluation-on-NAME.json`` (``evaluation-on-NAME-in-WORLD.json`` in another world):
``distance_m``, ``failure``, ``postures``, ``world`` and ``joints`` (the names matched,
dropped, locked and added).
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.agent.policy import GreedyPolicy, rollout
from qdsega.atomic import replaced_atomically
from qdsega.baselines import classic_gaits
from qdsega.baselines.reference_search import (
    DEFAULT_BUDGET_TRIALS,
    check_budget,
    reference_gait,
)
from qdsega.description import Formation, World, load_formation, resolve_formation
from qdsega.errors import ConfigError
from qdsega.locomotion.env import LocomotionEnv, replay_postures, rules_env
from qdsega.locomotion.env_model import EnvModel
from qdsega.locomotion.rules import ExactRules
from qdsega.progress import ProgressFactory
from qdsega.training.finished_run import FinishedRun
from qdsega.training.joint_mapping import JointMapping
from qdsega.training.run_folder import RunFolder
from qdsega.training.sims import check_sim


def evaluate_run(
    run: Path | str,
    *,
    reference_trials: int = DEFAULT_BUDGET_TRIALS,
    progress: ProgressFactory | None = None,
    world: World | None = None,
) -> dict[str, Any]:
    """Replay the run's greedy policy and the reference gaits; write ``evaluation.json``, or
    in another ``world`` ``evaluation-in-WORLD.json``.

    Args:
        run: the run folder.
        reference_trials: the CMA-ES reference search's budget in trials (0: no search).
        progress: shows the reference search's progress when it runs (None: silent).
        world: where to judge it (None: the run's own world).

    Raises:
        RunFolderError: missing or corrupt run folder; a negative search budget, or one below
            one CMA-ES generation.
        WorldError: a body that would start inside one of ``world``'s obstacles.
    """
    if reference_trials < 0:
        message = f"--reference-trials must be 0 (no search) or more, got {reference_trials}"
        raise ConfigError(message)
    run = Path(run)
    finished = replayable_run(run)
    summary, config, policy = finished.summary, finished.config, finished.policy
    formation = finished.formation if world is None else finished.formation_in(world)
    if reference_trials > 0:
        try:
            check_budget(formation, reference_trials)  # before any physics
        except ValueError as exc:
            raise ConfigError(f"reference search: {exc}") from None
    if world is not None:
        check_sim(formation, replace(config, sim="memo"), world)  # the body can start there
    rules = config.rules(finished.world if world is None else world)
    env = rules_env(formation, rules)
    try:
        learned = replay_policy(env, policy)
        candidates = [classic_reference(env, formation)]
        if reference_trials > 0:
            candidates.append(
                searched_reference(
                    env,
                    formation,
                    rules,
                    trials=reference_trials,
                    workers=config.workers,
                    progress=progress,
                )
            )
    finally:
        env.close()
    reference = max(candidates, key=lambda c: c["distance_m"])
    result: dict[str, Any] = {
        "formation": formation.name,
        "sim": config.sim,
        "distance_m": learned["distance_m"],
        "failure": learned["failure"],
        "memo_prediction_m": summary["greedy_distance"]
        if config.sim == "memo" and world is None
        else None,
        "reference": reference,
        "references": candidates,
        "ratio": learned["distance_m"] / reference["distance_m"]
        if reference["distance_m"] > 0
        else None,
        "postures": learned["postures"],
        "unit_xy_m": learned["unit_xy_m"],
        "world": rules.world.name,
    }
    if len(formation.joints) >= 2 and len(learned["postures"]) >= 4:
        result["wave"] = wave_of(formation, np.array(learned["postures"]))
    file = finished.folder.evaluation_file(world=None if world is None else world.name)
    with replaced_atomically(file) as partial:
        partial.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    return result


def evaluate_on(
    run: Path | str, other: Path | str, *, world: World | None = None
) -> tuple[dict[str, Any], Path]:
    """Replay the run's greedy policy on the formation ``other`` (a file or a shipped name)
    under the run's rules, in ``world`` (None: the run's own); write
    ``RUN/evaluation-on-NAME.json`` (``-in-WORLD`` in another world); return it and its path.

    Raises:
        RunFolderError: missing or corrupt run folder; a bad formation, or one the run's
            lower agent cannot drive.
        WorldError: a body that would start inside one of ``world``'s obstacles.
    """
    run = Path(run)
    finished = replayable_run(run)
    config, policy = finished.config, finished.policy
    source, place = finished.formation, finished.world if world is None else world
    target = load_formation(resolve_formation(other))
    target = config.with_light(place.lights(target))
    check_sim(target, replace(config, sim="memo"), world)  # the lower agent must drive it
    mapping = JointMapping.between(source, target)
    env = rules_env(target, config.rules(place))
    try:
        learned = replay_policy(env, mapping.policy(policy, target))
    finally:
        env.close()
    result = {
        "formation": target.name,
        "policy_of": source.name,
        "distance_m": learned["distance_m"],
        "failure": learned["failure"],
        "joints": mapping.report(),
        "postures": learned["postures"],
        "world": place.name,
    }
    file = finished.folder.evaluation_file(
        formation=target.name, world=None if world is None else world.name
    )
    with replaced_atomically(file) as partial:
        partial.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    return result, file


def replay_policy(env: LocomotionEnv, policy: GreedyPolicy) -> dict[str, Any]:
    """One trial of the greedy policy in ``env``: its distance (m), failure, commanded
    postures and every unit's centre of mass at the start and after each step."""
    world = EnvModel(env=env)
    units: list[list[list[float]]] = []
    trial = rollout(
        policy, world, steps=env.task.trial_steps, record=lambda: units.append(_unit_xy(env))
    )
    return {
        "distance_m": trial.distance_m,
        "failure": trial.failure,
        "postures": trial.postures.tolist(),
        "unit_xy_m": units,
    }


def _unit_xy(env: LocomotionEnv) -> list[list[float]]:
    """Every unit's centre of mass (x, y) (m), in formation order, rounded to 0.1 mm."""
    centres, _ = env.sim.unit_states()
    return centres[:, :2].round(4).tolist()


def classic_reference(env: LocomotionEnv, formation: Formation) -> dict[str, Any]:
    """The best hand-designed gait for ``formation`` under ``env``'s rules: the serpenoid grid
    for a legless body, the classic leg gaits for a legged one; 0 m when every one fails."""
    steps = env.task.trial_steps
    if formation.legs:
        candidates = [
            ({"gait": gait}, classic_gaits.leg_gait(formation, gait=gait, steps=steps))
            for gait in classic_gaits.LEG_GAITS
        ]
        kind = "classic leg gait"
    else:
        candidates = list(classic_gaits.serpenoid_grid(formation, steps=steps))
        kind = "serpenoid travelling wave"
    best: dict[str, Any] = {"kind": kind, "params": None, "distance_m": 0.0}
    for params, postures in candidates:
        replay = replay_postures(env, postures)
        if replay.failure is None and replay.distance_m > best["distance_m"]:
            best = {"kind": kind, "params": params, "distance_m": replay.distance_m}
    return best


def searched_reference(
    env: LocomotionEnv,
    formation: Formation,
    rules: ExactRules,
    *,
    trials: int,
    workers: int,
    progress: ProgressFactory | None = None,
) -> dict[str, Any]:
    """The CPG gait CMA-ES finds in ``trials`` exact trials on ``workers`` processes under
    ``rules`` (cached by content hash, :mod:`qdsega.baselines.reference_search`), replayed in
    ``env``; a search shows its progress through ``progress`` (None: silent)."""
    try:
        found = reference_gait(
            formation,
            rules=rules,
            budget_trials=trials,
            workers=workers,
            progress=progress,
        )
    except ValueError as exc:
        raise ConfigError(f"reference search: {exc}") from None
    replay = replay_postures(env, found.postures)
    return {
        "kind": "CPG gait searched by CMA-ES",
        "params": found.params.to_dict(),
        "distance_m": replay.distance_m if replay.failure is None else 0.0,
        "budget_trials": found.budget_trials,
        "budget_steps": found.budget_steps,
        "cache_key": found.key,
    }


def wave_of(formation: Formation, postures: np.ndarray) -> dict[str, Any]:
    """The rhythm of a posture sequence (steps, J): its period (steps) and the phase lag (deg)
    between neighbouring joints, from the commanded joint angles.

    The period is the shortest shift that maps most postures onto equal postures; the lag
    between joints ``i`` and ``i + 1`` is the shift (in steps, within one period) that best
    aligns joint ``i + 1``'s angles onto joint ``i``'s, as a fraction of the period.
    """
    angles = np.array([formation.posture_rad(row) for row in postures])
    period = _period(postures)
    centred = angles - angles.mean(axis=0)
    steps = len(centred)
    lags = []
    for i in range(centred.shape[1] - 1):
        a, b = centred[:, i], centred[:, i + 1]
        if period == 0 or not (a.any() and b.any()):
            continue
        scores = [float(np.dot(a[: steps - k], b[k:])) / (steps - k) for k in range(period)]
        lags.append(360.0 * int(np.argmax(scores)) / period)
    return {
        "period_steps": period,
        "phase_lag_deg": lags,
        "mean_phase_lag_deg": float(np.mean(lags)) if lags else None,
        "joint_angles_deg": np.degrees(angles).round(3).tolist(),
    }


def _period(postures: np.ndarray) -> int:
    """Shortest shift p (2 .. steps/2) with the largest share of t where posture t equals
    posture t + p; 0 when no shift repeats at least half the postures."""
    steps = len(postures)
    best, best_share = 0, 0.5
    for shift in range(2, steps // 2 + 1):
        share = float(np.mean(np.all(postures[:-shift] == postures[shift:], axis=1)))
        if share > best_share + 1e-12:
            best, best_share = shift, share
    return best


def replayable_run(run: Path) -> FinishedRun:
    """A finished run folder with a greedy policy to replay: its configuration, summary and
    policy are read here, in that order, so that a corrupt one fails before any physics.

    Raises:
        RunFolderError: missing folder or files, or files that do not parse.
    """
    finished = FinishedRun.open(run, RunFolder.CONFIG, RunFolder.POLICY)
    _ = finished.config, finished.summary, finished.policy
    return finished
