"""A run folder: the name of every file in it, and the readers and writers of its plain files.

The files and what they hold are specified once, in ``docs/run-folder.md``. Formats with a
module of their own (the checkpoint, the formation's copy, the memo table, the policy) take
their file names from here.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from qdsega.atomic import replaced_atomically
from qdsega.errors import RunFolderError

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
"""The columns of ``metrics.csv``, one row per finished generation (``docs/run-folder.md``)."""

_FLOAT_COLUMNS = {
    "best_distance_m",
    "mean_distance_m",
    "greedy_distance_m",
    "greedy_exact_m",
    "wall_s",
}


@dataclass(frozen=True)
class RunFolder:
    """The run folder at ``path``, which may not exist yet."""

    path: Path

    CONFIG: ClassVar[str] = "config.yaml"
    FORMATION_DIR: ClassVar[str] = "formation"
    FORMATION_RECORD: ClassVar[str] = "formation.json"
    WORLD: ClassVar[str] = "world.yaml"
    """The run's copy of the world file it trains in; none for the flat plane."""
    LOCK: ClassVar[str] = "train.lock"
    WARM_START: ClassVar[str] = "warm_start.json"
    WARM_START_STATE: ClassVar[str] = "warm_start.npz"
    CHECKPOINT: ClassVar[str] = "checkpoint.npz"
    METRICS: ClassVar[str] = "metrics.csv"
    TRANSITIONS: ClassVar[str] = "transitions.npz"
    POLICY: ClassVar[str] = "policy.npz"
    TRAJECTORIES: ClassVar[str] = "trajectories.npz"
    SUMMARY: ClassVar[str] = "summary.json"
    """Written last by ``qdsega train``: its presence means the run is finished."""
    EVALUATION: ClassVar[str] = "evaluation.json"
    REPORT: ClassVar[str] = "report.html"
    VIDEO: ClassVar[str] = "gait.mp4"
    """Where a run's film goes when it goes in the run folder (``render -o`` names its own)."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "path", Path(self.path))

    def __truediv__(self, name: str) -> Path:
        return self.path / name

    @property
    def started(self) -> bool:
        """``train`` has written the configuration: ``--resume`` can continue it."""
        return (self.path / self.CONFIG).is_file()

    @property
    def finished(self) -> bool:
        return (self.path / self.SUMMARY).is_file()

    def evaluation_file(self, *, formation: str | None = None, world: str | None = None) -> Path:
        """Where ``evaluate`` writes: :attr:`EVALUATION`; the policy's trial on another body
        (``--formation``) ``evaluation-on-FORMATION.json``; judged in another world
        (``--world``) ``evaluation-in-WORLD.json``; both, ``evaluation-on-FORMATION-in-WORLD``."""
        if formation is None and world is None:
            return self.path / self.EVALUATION
        on = "" if formation is None else f"-on-{formation}"
        place = "" if world is None else f"-in-{world}"
        return self.path / f"evaluation{on}{place}.json"

    def require_finished(self, *names: str) -> None:
        """Check that the folder holds a summary and every file in ``names``.

        Raises:
            RunFolderError: no such folder, or a file missing.
        """
        if not self.path.is_dir():
            raise RunFolderError("run folder not found", file=self.path)
        for name in (self.SUMMARY, *names):
            if not (self.path / name).is_file():
                raise RunFolderError(f"not a finished run folder (no {name})", file=self.path)

    def read_summary(self) -> dict[str, Any]:
        """``summary.json`` (call :meth:`require_finished` first).

        Raises:
            RunFolderError: the file does not parse or is not a summary.
        """
        summary = self.read_json(self.SUMMARY)
        if not isinstance(summary, dict) or not {"formation", "formation_file"} <= summary.keys():
            raise RunFolderError(
                f"corrupt run folder ({self.SUMMARY} is not a summary)", file=self.path
            )
        return summary

    def read_evaluation(self) -> dict[str, Any] | None:
        """``evaluation.json``, or None before ``qdsega evaluate``.

        Raises:
            RunFolderError: the file does not parse or is not an evaluation.
        """
        if not (self.path / self.EVALUATION).is_file():
            return None
        evaluation = self.read_json(self.EVALUATION)
        if not isinstance(evaluation, dict) or not {"postures", "reference"} <= evaluation.keys():
            message = f"corrupt run folder ({self.EVALUATION} is not an evaluation)"
            raise RunFolderError(message, file=self.path)
        return evaluation

    def read_warm_start(self) -> dict[str, Any] | None:
        """``warm_start.json`` of a warm-started run, else None."""
        if not (self.path / self.WARM_START).is_file():
            return None
        return self.read_json(self.WARM_START)

    def reached(self, target_m: float) -> tuple[int | None, int | None]:
        """The first generation whose greedy policy covers ``target_m`` in exact physics, and
        the run's simulated steps by its end. A warm run whose handed-on path, verified before
        generation 1, already covers it reached it at generation 0, in that one trial's
        commands. (None, None) when no generation does."""
        record = self.read_warm_start()
        if record is not None and record.get("handed_on_m", -1.0) >= target_m:
            return 0, int(record["handed_on_steps"])
        metrics = self.read_metrics()
        hits = np.flatnonzero(metrics["greedy_exact_m"] >= target_m)
        if not hits.size:
            return None, None
        return int(metrics["generation"][hits[0]]), int(metrics["sim_steps"][hits[0]])

    def read_json(self, name: str) -> Any:
        """The JSON file ``name``.

        Raises:
            RunFolderError: missing or not JSON.
        """
        try:
            return json.loads((self.path / name).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise RunFolderError(f"corrupt run folder ({name}: {exc})", file=self.path) from None

    def write_json(self, name: str, data: Any) -> None:
        """Write the JSON file ``name`` (a temporary file, then a rename)."""
        with replaced_atomically(self.path / name) as partial:
            partial.write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")

    def write_metrics(self, rows: np.ndarray) -> None:
        """``metrics.csv`` from rows of :data:`METRIC_COLUMNS`, written then renamed."""
        with (
            replaced_atomically(self.path / self.METRICS) as partial,
            partial.open("w", newline="", encoding="utf-8") as stream,
        ):
            writer = csv.writer(stream)
            writer.writerow(METRIC_COLUMNS)
            for row in rows:
                writer.writerow(
                    f"{value:.6f}" if name in _FLOAT_COLUMNS else str(int(value))
                    for name, value in zip(METRIC_COLUMNS, row, strict=True)
                )

    def read_metrics(self) -> dict[str, np.ndarray]:
        """``metrics.csv`` as one array per column.

        Raises:
            RunFolderError: the file is missing, empty or does not parse.
        """
        try:
            with (self.path / self.METRICS).open(encoding="utf-8") as stream:
                rows = list(csv.DictReader(stream))
            if not rows:
                raise ValueError(f"{self.METRICS} has no rows")
            return {name: np.array([float(row[name]) for row in rows]) for name in rows[0]}
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise RunFolderError(f"corrupt run folder ({exc})", file=self.path) from None
