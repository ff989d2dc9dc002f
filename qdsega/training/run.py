"""A training run: learn a formation's locomotion and write the run folder.

The run folder holds:

* ``config.yaml``: the fully resolved :class:`~qdsega.training.config.TrainingConfig`;
* ``metrics.csv``: one row per generation (see :data:`METRIC_COLUMNS`);
* ``summary.json``: the outcome (greedy distance, exact optimum, budget, wall time, seed);
  ``optimum`` is the straight-walk optimum of :func:`qdsega.msm.msm_optimum`, exact
  (``optimum_exact``) for a light straight ahead, an upper reference otherwise; null in
  PyBullet worlds (``qdsega evaluate`` measures a reference gait there);
* ``policy.npz``: the final generation's greedy policy: ``q`` (states, A), ``actions`` (A, J),
  ``postures`` (interior states, J), ``next_interior`` (A,);
* ``transitions.npz`` (memo mode): every measured transition, reused when the run resumes;
* ``trajectories.npz``: what the figures need: ``poses`` (G, steps + 1, 3), the greedy trial
  of every generation (x m, y m, theta rad); ``gait_postures`` (k + 1, J) and ``gait_legs``
  (k + 1, n_legs), the last generation's greedy trial as postures and as leg states 1..4;
  ``gait_angles_deg`` (k + 1, J) and ``joint_names`` (J,), the same trial as joint angles;
  ``optimum_postures`` (steps + 1, J), the optimum's witness; ``light`` (2,) (m).
"""

from __future__ import annotations

import csv
import json
import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from qdsega.agent.learner import QDSEGA
from qdsega.description import Formation, Light, load_formation
from qdsega.training.config import TrainingConfig
from qdsega.training.worlds import TrainingWorld, build_world, leg_states, light_of

METRIC_COLUMNS = (
    "generation",
    "actions",
    "best_distance_m",
    "mean_distance_m",
    "greedy_distance_m",
    "penalties",
    "steps",
    "wall_s",
)
"""metrics.csv: Q-table actions, best and mean trial distance toward the light, the greedy
policy's distance, trials that ended in a fall, learning steps, wall seconds."""


def prepare_formation(file: Path | str, config: TrainingConfig) -> Formation:
    """Load the formation and move its light as ``config.light_bearing_deg`` says."""
    formation = load_formation(file)
    if config.light_bearing_deg is not None:
        light = Light(formation.light.distance_m, math.radians(config.light_bearing_deg))
        formation = formation.with_light(light)
    return formation


def train(
    formation_file: Path | str,
    config: TrainingConfig,
    out: Path | str,
    *,
    log: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Train with ``config`` and write the run folder ``out``; return the summary.

    Raises:
        FormationError: unreadable formation, or one the chosen world cannot model.
    """
    start = time.perf_counter()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    formation = prepare_formation(formation_file, config)
    world = build_world(formation, config, out)
    try:
        return _train(formation, config, out, world, start, log)
    finally:
        world.close()


def _train(
    formation: Formation,
    config: TrainingConfig,
    out: Path,
    world: TrainingWorld,
    start: float,
    log: Callable[[str], None] | None,
) -> dict[str, Any]:
    light = light_of(formation)
    steps_per_trial = config.agent.learning.trial_steps
    optimum = world.optimum
    (out / "config.yaml").write_text(
        yaml.safe_dump(config.to_dict(), sort_keys=False), encoding="utf-8"
    )
    learner = QDSEGA(
        config=config.agent,
        levels=np.array([len(j.levels_rad) for j in formation.joints]),
        world=world.provider,
        light_xy=light,
        rng=np.random.default_rng(config.seed),
    )
    poses, env_steps = [], 0
    with (out / "metrics.csv").open("w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(METRIC_COLUMNS)
        for generation in learner.run():
            env_steps += generation.steps
            poses.append(generation.greedy_poses)
            writer.writerow(
                [
                    generation.index,
                    generation.space.n_actions,
                    f"{generation.distances.max():.6f}",
                    f"{generation.distances.mean():.6f}",
                    f"{generation.greedy_distance:.6f}",
                    int(generation.fell.sum()),
                    generation.steps,
                    f"{generation.wall_s:.4f}",
                ]
            )
            stream.flush()
            world.save(out)
            if log is not None:
                oracle = "" if optimum is None else f" (optimum {optimum.bound_m:.3f} m)"
                log(
                    f"generation {generation.index}: {generation.space.n_actions} actions, "
                    f"greedy {generation.greedy_distance:.3f} m{oracle}"
                )
    gait = generation.greedy_postures()
    layout = world.layout
    np.savez_compressed(
        out / "trajectories.npz",
        poses=np.array(poses),
        gait_postures=gait,
        gait_angles_deg=np.degrees([formation.posture_rad(p) for p in gait]),
        joint_names=np.array([j.name for j in formation.joints], dtype=str),
        gait_legs=leg_states(layout, gait),
        leg_names=np.array([] if layout is None else layout.names, dtype=str),
        optimum_postures=np.zeros((0, len(formation.joints)), dtype=np.int64)
        if optimum is None
        else optimum.postures,
        light=np.array(light),
    )
    np.savez_compressed(
        out / "policy.npz",
        q=generation.q,
        actions=generation.space.actions,
        postures=generation.space.postures,
        next_interior=generation.space.next_interior,
    )
    summary = {
        "formation": formation.name,
        "formation_file": str(Path(formation.file).resolve()),
        "sim": config.sim,
        "preset": config.preset,
        "seed": config.seed,
        "generations": generation.index,
        "trials_per_generation": config.agent.learning.trials,
        "trial_steps": steps_per_trial,
        "env_steps": env_steps,
        "greedy_distance": generation.greedy_distance,
        "greedy_fell": generation.greedy_fell,
        "optimum": None if optimum is None else optimum.bound_m,
        "optimum_exact": None if optimum is None else optimum.exact,
        "greedy_over_optimum": None
        if optimum is None
        else generation.greedy_distance / optimum.bound_m,
        "final_heading_deg": math.degrees(generation.greedy_poses[-1, 2]),
        "light_xy": list(light),
        "wall_s": time.perf_counter() - start,
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    return summary


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
