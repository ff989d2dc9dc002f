"""The runs of the benchmark: every task x method x seed, where each one works, and what its
result was made under (a result made under other settings is run again)."""

from __future__ import annotations

import dataclasses
import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from qdsega.bench.methods import METHODS
from qdsega.bench.tasks import BenchTask


@dataclass(frozen=True)
class BenchRun:
    """One run of the benchmark.

    Attributes:
        task: the task.
        method: a name of :data:`qdsega.bench.methods.METHODS`.
        seed: the run's seed.
    """

    task: BenchTask
    method: str
    seed: int

    @property
    def name(self) -> str:
        return f"{self.method}-seed{self.seed}"

    def result(self, out: Path) -> Path:
        """Where its curve is kept."""
        return out / "results" / self.task.name / f"{self.name}.json"

    def folder(self, out: Path) -> Path:
        """Where it works."""
        return out / "runs" / self.task.name / self.name

    def key(self) -> str:
        """What its result depends on, hashed: the method, the seed, the task's budgets and
        the whole training configuration its preset resolves to (a changed default included)."""
        task = {
            field: value
            for field, value in dataclasses.asdict(self.task).items()
            if field not in _REPORT_ONLY
        }
        inputs: dict[str, Any] = {
            "method": self.method,
            "seed": self.seed,
            "task": task,
            "config": dataclasses.asdict(self.task.config(seed=self.seed)),
        }
        text = json.dumps(inputs, sort_keys=True, default=str)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


_REPORT_ONLY = ("name", "seeds", "methods", "budgets", "forced")
"""A task's fields that change what the report shows, not what one run does."""


def bench_runs(tasks: Sequence[BenchTask]) -> list[BenchRun]:
    """Every run of ``tasks``, seed by seed (every method's seed 0 first), so that a benchmark
    stopped part way compares every method on the seeds it finished.

    Raises:
        ValueError: a task names an unknown method.
    """
    for task in tasks:
        unknown = sorted(set(task.methods) - set(METHODS))
        if unknown:
            raise ValueError(f"{task.name}: unknown methods {unknown} (known: {list(METHODS)})")
    return [
        BenchRun(task, method, seed)
        for seed in range(max(task.seeds for task in tasks))
        for task in tasks
        for method in task.methods
        if seed < task.seeds
    ]
