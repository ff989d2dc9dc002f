"""A reference gait that is hard to beat, for any formation: a CPG gait searched by CMA-ES.

The gait (:class:`qdsega.baselines.cpg.CPGGait`) has an offset, an amplitude and a phase per
joint and one period of ``PERIODS`` upper-agent steps. CMA-ES (the ``cma`` package, ask and
tell) searches them in exact physics: every candidate is one trial in the
:class:`qdsega.locomotion.env.LocomotionEnv` learning and evaluation use (same levels, lower
agent, step duration, trial length and physics settings), scored by the distance it covers
toward the light. Each CMA-ES generation is spread over worker processes; every trial starts
from its env's settled snapshot, which restores exactly, so the result depends on the seed
only, not on the number of workers or on which worker ran which trial.

The search space is the unit box: ``[0, 1]^(3J)`` for the oscillators
(:meth:`CPGGait.from_unit`, phases wrap around) and one more coordinate for the period, cut
into equal bins, one per period. A trial whose lower agent fails ranks below every trial that
completes (failed ones among themselves by how many steps they completed), and the reference
is the best trial that completed.

A search costs minutes, so its result is kept as one JSON file per key, the SHA-256 of a
canonical JSON of everything the result depends on: the assembled robot (URDF text, mesh
files, joints, levels, friction, legs, start posture), the light, the task, lower agent and
physics settings, the PyBullet version and the search settings. Look-up order: the references
shipped in ``qdsega/baselines/references/``, then the user cache
(``$QDSEGA_CACHE/references``, default ``~/.cache/qdsega/references``); else the search runs and its
result goes to the user cache.
"""

from __future__ import annotations

import dataclasses
import hashlib
import importlib.metadata
import importlib.resources
import json
import math
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.assembly import assemble
from qdsega.atomic import replaced_atomically
from qdsega.baselines.cpg import CPGGait
from qdsega.description import Formation
from qdsega.locomotion.env import Replay
from qdsega.locomotion.exact_trials import ExactTrials
from qdsega.locomotion.rules import ExactRules
from qdsega.progress import ProgressFactory, ProgressLine

FORMAT_VERSION = 1
"""Part of every key; bump it when a change of the search or the simulation changes results."""

PERIODS = (3, 4, 5, 6, 7, 8)
"""Periods the search chooses from (upper-agent steps)."""

DEFAULT_BUDGET_TRIALS = 600
"""Trials (CMA-ES candidates) per search."""

SIGMA0 = 0.3
"""Initial CMA-ES step size in the unit box (-)."""

FAILED_COST = 1000.0
"""Cost of a failed trial, above the cost ``-distance`` of any completed one (m)."""

SHIPPED_DIR = Path(str(importlib.resources.files("qdsega.baselines"))) / "references"
"""References computed at the default budget and shipped with the package."""


@dataclass(frozen=True, kw_only=True, eq=False)
class ReferenceGait:
    """The best gait a search found.

    Attributes:
        kind: what kind of gait (``cpg``).
        params: the gait's parameters.
        postures: its postures, one trial long, shape (trial_steps, J) (level indices).
        distance_m: distance toward the light it covers in one trial (m); it does not fail.
        budget_trials: trials the search was allowed (-).
        budget_steps: upper-agent steps those trials hold (-).
        evaluations: trials the search ran (-); at most ``budget_trials``.
        wall_s: wall-clock time of the search (s).
        history_m: the best distance so far after each CMA-ES iteration (m); None before a
            trial completed.
        key: the content hash the result is cached under.
        file: the cache file it was read from or written to; None when not cached.
    """

    kind: str
    params: CPGGait
    postures: np.ndarray
    distance_m: float
    budget_trials: int
    budget_steps: int
    evaluations: int
    wall_s: float
    history_m: tuple[float | None, ...]
    key: str
    file: Path | None


def reference_gait(
    formation: Formation,
    *,
    rules: ExactRules,
    budget_trials: int = DEFAULT_BUDGET_TRIALS,
    seed: int = 0,
    workers: int = 2,
    cache: bool = True,
    progress: ProgressFactory | None = None,
) -> ReferenceGait:
    """The CMA-ES reference gait of ``formation`` under these rules: cached, else searched.

    Args:
        formation: the robot and its light.
        rules: the task (its trial length), the lower agent and the physics.
        budget_trials: trials the search may run (-).
        seed: seed of the search's random generator.
        workers: processes simulating trials in parallel (1 simulates in this process).
        cache: look the result up and store it (see the module docstring).
        progress: makes the line that shows a search's trials done of the budget and the
            best distance so far (None: silent); a cached result shows nothing.

    Raises:
        ValueError: bad settings, a formation the lower agent cannot drive, or no trial
            within the budget that completed without failing.
    """
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    rules.lower_agent.step_duration_for(formation)  # refuses a step too short for a joint
    check_budget(formation, budget_trials)
    inputs = _key_inputs(formation, rules, budget_trials, seed)
    key = _hash(inputs)
    name = f"{formation.name}-{key[:16]}.json"
    if cache:
        for folder in (SHIPPED_DIR, user_cache_dir()):
            found = _read(folder / name, key, formation)
            if found is not None:
                return found
    start = time.perf_counter()
    line = None if progress is None else progress("reference search", budget_trials)
    try:
        gait, distance, evaluations, history = _search(
            formation, rules, budget_trials, seed, workers, line
        )
    finally:
        if line is not None:
            line.close()
    steps = rules.task.trial_steps
    postures = gait.postures(formation, steps=steps)
    postures.setflags(write=False)
    result = ReferenceGait(
        kind="cpg",
        params=gait,
        postures=postures,
        distance_m=distance,
        budget_trials=budget_trials,
        budget_steps=budget_trials * steps,
        evaluations=evaluations,
        wall_s=time.perf_counter() - start,
        history_m=tuple(history),
        key=key,
        file=user_cache_dir() / name if cache else None,
    )
    if result.file is not None:
        _write(result, inputs)
    return result


def check_budget(formation: Formation, budget_trials: int) -> None:
    """Raise ValueError unless ``budget_trials`` holds at least one CMA-ES generation."""
    popsize = _popsize(formation)
    if budget_trials < popsize:
        raise ValueError(
            f"budget_trials must hold at least one CMA-ES generation ({popsize} trials for "
            f"{formation.name}), got {budget_trials}"
        )


def reference_key(
    formation: Formation,
    *,
    rules: ExactRules,
    budget_trials: int = DEFAULT_BUDGET_TRIALS,
    seed: int = 0,
) -> str:
    """The cache key (64 hex digits) of :func:`reference_gait` with these arguments."""
    return _hash(_key_inputs(formation, rules, budget_trials, seed))


def user_cache_dir() -> Path:
    """Where computed references are kept: ``$QDSEGA_CACHE/references``, default
    ``~/.cache/qdsega/references``."""
    root = os.environ.get("QDSEGA_CACHE")
    return (Path(root) if root else Path.home() / ".cache" / "qdsega") / "references"


# -- the rules: what a result depends on -----------------------------------------------------

_NOT_PHYSICS = ("name", "description", "file", "light")
"""What a world's key leaves out: its names and file change no trial (its light is the
formation's, already in the key)."""


def _rules(rules: ExactRules) -> dict[str, Any]:
    """The settings a posture sequence's distance depends on, as plain types (of the task, the
    trial length alone: an open-loop gait earns no reward and sees no exterior state)."""
    inputs = {
        "trial_steps": rules.task.trial_steps,
        "lower_agent": dataclasses.asdict(rules.lower_agent),
        "physics": dataclasses.asdict(rules.physics),
    }
    if not rules.world.is_flat:  # the flat plane keeps the keys of before worlds existed
        ground = dataclasses.asdict(rules.world)
        inputs["world"] = {k: v for k, v in ground.items() if k not in _NOT_PHYSICS}
    return inputs


# -- the key -----------------------------------------------------------------------------------


def _key_inputs(
    formation: Formation,
    rules: ExactRules,
    budget_trials: int,
    seed: int,
) -> dict[str, Any]:
    """Everything the search's result depends on, as plain types (the URDF as text)."""
    robot = assemble(formation)
    return {
        "format": FORMAT_VERSION,
        "formation": formation.name,
        "urdf": robot.urdf,
        "assets_sha256": {
            name: hashlib.sha256(path.read_bytes()).hexdigest()
            for name, path in sorted(robot.assets.items())
        },
        "joints": [
            {
                "name": joint.name,
                "levels_rad": list(joint.levels_rad),
                "effort_nm": joint.spec.effort_nm,
                "velocity_rad_s": joint.spec.velocity_rad_s,
            }
            for joint in formation.joints
        ],
        "friction": {
            unit.name: [unit.friction.lateral, *unit.friction.anisotropic]
            for unit in formation.units
        },
        "legs": [dataclasses.asdict(leg) for leg in formation.legs],
        "start_levels": list(formation.rest_levels()),
        "light_m": list(formation.light.position_m),
        **_rules(rules),
        "pybullet": importlib.metadata.version("pybullet"),
        "search": {
            "budget_trials": budget_trials,
            "seed": seed,
            "periods": list(PERIODS),
            "sigma0": SIGMA0,
        },
    }


def _hash(inputs: dict[str, Any]) -> str:
    text = json.dumps(inputs, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


# -- the cache file ----------------------------------------------------------------------------


def _write(result: ReferenceGait, inputs: dict[str, Any]) -> None:
    """Store ``result`` in ``result.file`` atomically, with a summary of its key's inputs."""
    assert result.file is not None
    summary = {k: v for k, v in inputs.items() if k != "urdf"}
    summary["urdf_sha256"] = hashlib.sha256(inputs["urdf"].encode("utf-8")).hexdigest()
    data = {
        "key": result.key,
        "inputs": summary,
        "kind": result.kind,
        "params": result.params.to_dict(),
        "postures": result.postures.tolist(),
        "distance_m": result.distance_m,
        "budget_trials": result.budget_trials,
        "budget_steps": result.budget_steps,
        "evaluations": result.evaluations,
        "wall_s": result.wall_s,
        "history_m": list(result.history_m),
    }
    result.file.parent.mkdir(parents=True, exist_ok=True)
    with replaced_atomically(result.file) as partial:
        partial.write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")


def _read(file: Path, key: str, formation: Formation) -> ReferenceGait | None:
    """The result stored in ``file`` under ``key``; None when there is none. A file that does
    not hold a consistent result is ignored with a one-line warning."""
    if not file.is_file():
        return None
    try:
        data = json.loads(file.read_text(encoding="utf-8"))
        if data["key"] != key:
            raise ValueError("it holds another key")
        params = CPGGait.from_dict(data["params"])
        postures = np.array(data["postures"], dtype=np.int64)
        steps = len(postures)
        if steps < 1 or not np.array_equal(postures, params.postures(formation, steps=steps)):
            raise ValueError("its postures are not its gait's")
        postures.setflags(write=False)
        return ReferenceGait(
            kind=str(data["kind"]),
            params=params,
            postures=postures,
            distance_m=float(data["distance_m"]),
            budget_trials=int(data["budget_trials"]),
            budget_steps=int(data["budget_steps"]),
            evaluations=int(data["evaluations"]),
            wall_s=float(data["wall_s"]),
            history_m=tuple(None if d is None else float(d) for d in data["history_m"]),
            key=key,
            file=file,
        )
    except (OSError, ValueError, KeyError, TypeError) as exc:
        print(f"qdsega: warning: ignoring corrupt reference {file} ({exc})", file=sys.stderr)
        return None


# -- the search --------------------------------------------------------------------------------


def _popsize(formation: Formation) -> int:
    """CMA-ES's default population for the search's dimension, 4 + floor(3 ln n)."""
    return 4 + int(3 * math.log(3 * len(formation.joints) + 1))


def _gait(formation: Formation, x: np.ndarray) -> CPGGait:
    """The gait at a CMA-ES point ``x``, shape (3J + 1,): unit-box oscillators (phases wrap
    around), then the period's coordinate in [0, 1]."""
    n = len(formation.joints)
    unit = np.concatenate([x[: 2 * n], np.mod(x[2 * n : 3 * n], 1.0)])
    period = PERIODS[min(int(x[-1] * len(PERIODS)), len(PERIODS) - 1)]
    return CPGGait.from_unit(formation, unit, period_steps=period)


def _search(
    formation: Formation,
    rules: ExactRules,
    budget_trials: int,
    seed: int,
    workers: int,
    line: ProgressLine | None = None,
) -> tuple[CPGGait, float, int, list[float | None]]:
    """:func:`search_cpg` in exact physics, spread over ``workers`` processes; its progress
    on ``line``.

    Returns:
        the best completed gait, its distance (m), trials run, best distance per iteration.
    """
    with ExactTrials(formation=formation, rules=rules, workers=workers) as trials:
        found = search_cpg(
            formation,
            replay=trials.replays,
            trial_steps=rules.task.trial_steps,
            budget_trials=budget_trials,
            seed=seed,
            on_iteration=None if line is None else partial(_show, line),
        )
    if found.best is None:
        raise ValueError(
            f"{formation.name}: none of {found.evaluations} trials completed without the lower "
            "agent failing"
        )
    return found.best[1], found.best[0], found.evaluations, found.history_m


def _show(line: ProgressLine, evaluations: int, best_m: float | None) -> None:
    """Trials done and the best distance so far on ``line``."""
    line.update(evaluations, "no trial completed yet" if best_m is None else f"best {best_m:.3f} m")


@dataclass(frozen=True)
class CPGSearch:
    """What :func:`search_cpg` found.

    Attributes:
        best: the best completed trial's distance (m) and gait; None when none completed.
        evaluations: trials run (-).
        popsize: trials per CMA-ES iteration (-).
        history_m: the best distance so far after each iteration (m; None before a trial
            completed), one entry per ``popsize`` trials.
    """

    best: tuple[float, CPGGait] | None
    evaluations: int
    popsize: int
    history_m: list[float | None]


def search_cpg(
    formation: Formation,
    *,
    replay: Callable[[list[np.ndarray]], Sequence[Replay]],
    trial_steps: int,
    budget_trials: int,
    seed: int,
    on_iteration: Callable[[int, float | None], None] | None = None,
) -> CPGSearch:
    """CMA-ES over whole generations within the budget, every candidate one trial played by
    ``replay`` (posture sequences (trial_steps, J) -> their outcomes, in order: exact
    physics, or a table model); when CMA-ES stops (every candidate the same gait), it
    restarts from a random point with what is left of the budget. ``on_iteration(trials run,
    best distance so far or None)`` is called after each iteration (to show progress)."""
    import cma  # here: it loads scipy.stats (about 0.6 s), which a cached reference needs not

    n = len(formation.joints)
    rng = np.random.default_rng(seed)
    steps = trial_steps
    unbounded = [None] * n  # phases wrap around
    options = {
        "bounds": [[0.0] * (2 * n) + unbounded + [0.0], [1.0] * (2 * n) + unbounded + [1.0]],
        "popsize": _popsize(formation),
        "randn": lambda *shape: rng.standard_normal(shape),
        "seed": math.nan,  # cma then leaves numpy's global generator alone
        "verbose": -9,
        "verb_log": 0,
        "verb_disp": 0,
    }
    mean = np.full(3 * n + 1, 0.5)
    es = cma.CMAEvolutionStrategy(mean, SIGMA0, options)
    best: tuple[float, CPGGait] | None = None
    history: list[float | None] = []
    evaluations = 0
    while evaluations + es.popsize <= budget_trials:
        if es.stop():
            es = cma.CMAEvolutionStrategy(rng.uniform(size=3 * n + 1), SIGMA0, options)
        points = es.ask()
        gaits = [_gait(formation, np.asarray(x)) for x in points]
        outcomes = replay([g.postures(formation, steps=steps) for g in gaits])
        costs = []
        for gait, outcome in zip(gaits, outcomes, strict=True):
            if outcome.failure is not None:
                costs.append(FAILED_COST + (steps - outcome.completed) / steps)
                continue
            costs.append(-outcome.distance_m)
            if best is None or outcome.distance_m > best[0]:
                best = (outcome.distance_m, gait)
        es.tell(points, costs)
        evaluations += len(points)
        history.append(None if best is None else best[0])
        if on_iteration is not None:
            on_iteration(evaluations, history[-1])
    return CPGSearch(best, evaluations, _popsize(formation), history)
