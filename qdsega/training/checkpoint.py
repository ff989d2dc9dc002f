"""The checkpoint of a training run: written after every generation, read by ``--resume``.

``checkpoint.npz`` in the run folder holds the learner's state between two generations
(:class:`qdsega.agent.learner.LearnerState`: population, random generator state, the last
Q-table) and everything the run has recorded so far (metrics rows, greedy trajectories), so a
run stopped at any moment (Ctrl-C, SIGKILL, power loss) continues from its last finished
generation and ends exactly as it would have without the stop. It is written to a temporary
file and renamed over the old one, so it is always whole.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from qdsega.agent.learner import LearnerState
from qdsega.agent.space import ExplorationSpace
from qdsega.atomic import replaced_atomically
from qdsega.errors import FormationError

CHECKPOINT_FILE = "checkpoint.npz"


@dataclass(frozen=True)
class Checkpoint:
    """A run between two generations.

    Attributes:
        learner: the learner's state.
        metrics: one row per finished generation, columns of
            :data:`qdsega.training.run.METRIC_COLUMNS`, shape (G, columns).
        poses: each finished generation's greedy trial in the learner's world (x m, y m,
            theta rad), shape (G, steps + 1, 3).
        exact_poses: the same policies replayed with exact physics, shape (G, steps + 1, 3).
        gait: the postures the last exact replay went through, start posture first,
            shape (k + 1, J).
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
    if state.previous is not None:
        space, q = state.previous
        arrays.update(
            previous_actions=space.actions,
            previous_action_of=space.action_of,
            previous_postures=space.postures,
            previous_next_interior=space.next_interior,
            previous_q=q,
        )
    meta = {
        "completed": state.completed,
        "rng_state": state.rng_state,
        "env_steps": checkpoint.env_steps,
        "elapsed_s": checkpoint.elapsed_s,
        "elite_m": state.elite[1],
    }
    with replaced_atomically(run / CHECKPOINT_FILE) as partial:
        np.savez(partial, meta=np.array(json.dumps(meta)), **arrays)


def _elite(data: np.lib.npyio.NpzFile, meta: dict) -> tuple[np.ndarray, float | None]:
    """The elite of a checkpoint; none in one written before elitism existed."""
    if "elite" not in data:
        return np.zeros((0, data["population"].shape[1]), dtype=np.int64), None
    return data["elite"], meta["elite_m"]


def load_checkpoint(run: Path) -> Checkpoint | None:
    """Read ``run``'s checkpoint; None when it has none yet (the run stopped before its
    first was written).

    Raises:
        FormationError: a checkpoint that does not parse.
    """
    file = run / CHECKPOINT_FILE
    if not file.is_file():
        return None
    try:
        with np.load(file) as data:
            meta = json.loads(str(data["meta"]))
            previous = None
            if "previous_q" in data:
                space = ExplorationSpace(
                    actions=data["previous_actions"],
                    action_of=data["previous_action_of"],
                    postures=data["previous_postures"],
                    next_interior=data["previous_next_interior"],
                )
                previous = (space, data["previous_q"])
            return Checkpoint(
                learner=LearnerState(
                    completed=int(meta["completed"]),
                    population=data["population"],
                    rng_state=meta["rng_state"],
                    previous=previous,
                    elite=_elite(data, meta),
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
            )
    except (OSError, ValueError, KeyError, TypeError, zipfile.BadZipFile) as exc:
        message = f"corrupt {CHECKPOINT_FILE} ({exc.__class__.__name__}: {exc})"
        raise FormationError(message, file=run) from None
