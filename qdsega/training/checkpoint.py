"""The checkpoint of a training run: written after every generation, read by ``--resume``.

``checkpoint.npz`` in the run folder holds the learner's state between two generations
(:class:`qdsega.agent.learner.LearnerState`: population, random generator state, the last
Q-table), everything the run has recorded so far (metrics rows, greedy trajectories) and its
result so far (the greedy policy of the generation that went farthest with exact physics), so a
run stopped at any moment (Ctrl-C, SIGKILL, power loss) continues from its last finished
generation and ends exactly as it would have without the stop. It is written to a temporary
file and renamed over the old one, so it is always whole.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from qdsega.agent.learner import LearnerState
from qdsega.agent.policy import GreedyPolicy
from qdsega.agent.space import ExplorationSpace
from qdsega.atomic import replaced_atomically
from qdsega.errors import RunFolderError
from qdsega.training.run_folder import RunFolder


@dataclass(frozen=True)
class Checkpoint:
    """A run between two generations.

    Attributes:
        learner: the learner's state.
        metrics: one row per finished generation, columns of
            :data:`qdsega.training.run_folder.METRIC_COLUMNS`, shape (G, columns).
        poses: each finished generation's greedy trial in the learner's model (x m, y m,
            theta rad), shape (G, steps + 1, 3).
        exact_poses: the same policies replayed with exact physics, shape (G, steps + 1, 3).
        gait: the postures the result's exact replay went through, start posture first,
            shape (k + 1, J).
        result: the run's result so far: the generation (from 1) whose greedy policy went
            farthest with exact physics (``greedy_exact_m``; ties: the earliest); 0 before
            the first generation.
        result_policy: that generation's greedy policy; None before the first generation.
        world: what the run put into its world (grounded observations), as arrays.
        env_steps: learning steps (commands) so far.
        elapsed_s: wall time spent so far (s), over all sessions of the run.
    """

    learner: LearnerState
    metrics: np.ndarray
    poses: np.ndarray
    exact_poses: np.ndarray
    gait: np.ndarray
    world: dict[str, np.ndarray]
    env_steps: int
    elapsed_s: float
    result: int
    result_policy: GreedyPolicy | None


def save_checkpoint(run: Path, checkpoint: Checkpoint) -> None:
    """Write ``checkpoint.npz`` into ``run``: a temporary file, then a rename."""
    state = checkpoint.learner
    arrays: dict[str, np.ndarray] = {
        "population": state.population,
        "metrics": checkpoint.metrics,
        "poses": checkpoint.poses,
        "exact_poses": checkpoint.exact_poses,
        "gait": checkpoint.gait,
        "elite": state.elite[0],
        **{f"world_{name}": array for name, array in checkpoint.world.items()},
    }
    if state.elite_path is not None:
        arrays["elite_path"] = state.elite_path
    if state.previous is not None:
        space, q = state.previous
        arrays.update(space.arrays("previous_"), previous_q=q)
    if checkpoint.result_policy is not None:
        policy = checkpoint.result_policy
        arrays.update(
            result_q=policy.q,
            result_actions=policy.actions,
            result_postures=policy.postures,
            result_next_interior=policy.next_interior,
        )
    meta = {
        "completed": state.completed,
        "rng_state": state.rng_state,
        "env_steps": checkpoint.env_steps,
        "elapsed_s": checkpoint.elapsed_s,
        "elite_m": state.elite[1],
        "result": checkpoint.result,
    }
    with replaced_atomically(run / RunFolder.CHECKPOINT) as partial:
        # numpy's stubs match **arrays against savez's allow_pickle: bool
        np.savez(partial, meta=np.array(json.dumps(meta)), **arrays)  # type: ignore[arg-type]


def _elite(data: np.lib.npyio.NpzFile, meta: dict[str, Any]) -> tuple[np.ndarray, float | None]:
    """The elite of a checkpoint; none in one written before elitism existed."""
    if "elite" not in data:
        return np.zeros((0, data["population"].shape[1]), dtype=np.int64), None
    return data["elite"], meta["elite_m"]


def _result(
    data: np.lib.npyio.NpzFile,
    meta: dict[str, Any],
    metrics: np.ndarray,
    previous: tuple[ExplorationSpace, np.ndarray] | None,
) -> tuple[int, GreedyPolicy | None]:
    """The result of a checkpoint; in one written before results were kept, the last
    generation (what such a run reported)."""
    if "result" not in meta:
        return (0, None) if previous is None else (len(metrics), GreedyPolicy.of(*previous))
    policy = None
    if "result_q" in data:  # none before the first generation
        policy = GreedyPolicy(
            q=data["result_q"],
            actions=data["result_actions"],
            postures=data["result_postures"],
            next_interior=data["result_next_interior"],
        )
    return int(meta["result"]), policy


def load_checkpoint(run: Path) -> Checkpoint | None:
    """Read ``run``'s checkpoint; None when it has none yet (the run stopped before its
    first was written).

    Raises:
        RunFolderError: a checkpoint that does not parse.
    """
    file = run / RunFolder.CHECKPOINT
    if not file.is_file():
        return None
    try:
        with np.load(file) as data:
            meta = json.loads(str(data["meta"]))
            previous = None
            if "previous_q" in data:
                previous = (ExplorationSpace.from_arrays(data, "previous_"), data["previous_q"])
            result, result_policy = _result(data, meta, data["metrics"], previous)
            return Checkpoint(
                learner=LearnerState(
                    completed=int(meta["completed"]),
                    population=data["population"],
                    rng_state=meta["rng_state"],
                    previous=previous,
                    elite=_elite(data, meta),
                    elite_path=data.get("elite_path"),
                ),
                metrics=data["metrics"],
                poses=data["poses"],
                exact_poses=data["exact_poses"],
                gait=data["gait"],
                world={
                    name.removeprefix("world_"): data[name]
                    for name in data.files
                    if name.startswith("world_")
                },
                env_steps=int(meta["env_steps"]),
                elapsed_s=float(meta["elapsed_s"]),
                result=result,
                result_policy=result_policy,
            )
    except (OSError, ValueError, KeyError, TypeError, zipfile.BadZipFile) as exc:
        message = f"corrupt {RunFolder.CHECKPOINT} ({exc.__class__.__name__}: {exc})"
        raise RunFolderError(message, file=run) from None
