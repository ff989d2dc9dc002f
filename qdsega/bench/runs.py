"""The runs of the benchmark: every task x method x seed, and where each one works."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

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


def bench_runs(tasks: Sequence[BenchTask]) -> list[BenchRun]:
    """Every run of ``tasks``, in report order.

    Raises:
        ValueError: a task names an unknown method.
    """
    for task in tasks:
        unknown = sorted(set(task.methods) - set(METHODS))
        if unknown:
            raise ValueError(f"{task.name}: unknown methods {unknown} (known: {list(METHODS)})")
    return [
        BenchRun(task, method, seed)
        for task in tasks
        for method in task.methods
        for seed in range(task.seeds)
    ]
