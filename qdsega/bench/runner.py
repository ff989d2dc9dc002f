"""``qdsega bench``: every method on every task for every seed, then the report.

Each run (task, method, seed) works in ``OUT/runs/TASK/METHOD-seedS/`` and leaves its curve in
``OUT/results/TASK/METHOD-seedS.json`` when it finishes, with the key of what it was made under
(:meth:`BenchRun.key`); a re-run skips finished runs of the same key (and a QDSEGA training
run resumes where a crash left it), so a stopped benchmark continues, and a run whose settings
changed runs again. Runs go to ``jobs`` worker processes, each run on one core, or to Ray. A
run that fails is reported with its error, the others go on, and the report leaves it out.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from qdsega.bench.curve import Curve
from qdsega.bench.methods import METHODS
from qdsega.bench.report import provenance, write_report
from qdsega.bench.runs import BenchRun, bench_runs
from qdsega.bench.tasks import BenchTask
from qdsega.bench.throughput import throughput
from qdsega.driver import error_line, run_jobs
from qdsega.progress import ProgressFactory
from qdsega.training.run import TrainingInterrupted

KEY_FILE = "key"
"""The file of a run's work folder that holds its key (:meth:`BenchRun.key`)."""


@dataclass(frozen=True)
class BenchJob:
    """A benchmark run as the driver's job: run it in its folder and keep its curve."""

    run: BenchRun
    out: Path

    @property
    def name(self) -> str:
        return f"{self.run.task.name} {self.run.name}"

    def kept(self) -> bool:
        return Curve.key_of(self.run.result(self.out)) == self.run.key()

    def __call__(self) -> str | None:
        if self.kept():
            return None
        try:
            folder = self._fresh_folder()
            curve = METHODS[self.run.method](self.run.task, self.run.seed, folder)
            file = self.run.result(self.out)
            file.parent.mkdir(parents=True, exist_ok=True)
            curve.save(file, key=self.run.key())
            return None
        except TrainingInterrupted:
            raise
        except Exception as exc:  # a failed run is reported, not fatal
            return error_line(exc)

    def _fresh_folder(self) -> Path:
        """The run's work folder, holding its key: what an interrupted run of the same key left
        is kept (a training run resumes from it), a folder of other settings emptied first."""
        folder = self.run.folder(self.out)
        key_file = folder / KEY_FILE
        key = self.run.key()
        if folder.exists() and (not key_file.is_file() or key_file.read_text() != key):
            shutil.rmtree(folder)
        folder.mkdir(parents=True, exist_ok=True)
        key_file.write_text(key)
        return folder


def run_all(
    runs: Sequence[BenchRun],
    out: Path,
    *,
    jobs: int,
    ray: str | None = None,
    log: Callable[[str], None] = print,
    progress: ProgressFactory | None = None,
) -> list[str]:
    """Run every unfinished run, ``jobs`` at a time or as Ray tasks (``ray``: ``local`` or an
    address, :func:`qdsega.driver.run_jobs`); return the failed runs' one-line errors.
    ``progress``: as the driver's."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    bench_jobs = [BenchJob(run, out) for run in runs]
    kept = {job.name for job in bench_jobs if job.kept()}
    log(f"{len(kept)} of {len(runs)} runs finished before; running {len(runs) - len(kept)}")

    def ended(job: BenchJob, error: str | None) -> None:
        if job.name in kept:
            return
        if error is None:
            curve = Curve.load(job.run.result(out))
            log(f"{job.name}: {curve.distance_m[-1]:.3f} m at {curve.steps[-1]} steps")
        else:
            log(f"{job.name}: FAILED: {error}")

    errors = run_jobs(
        bench_jobs,
        processes=jobs,
        ray=ray,
        label="bench",
        report=ended,
        progress=None if len(kept) == len(runs) else progress,
    )
    return [f"{job.name}: {error}" for job, error in zip(bench_jobs, errors, strict=True) if error]


def load_curves(runs: Sequence[BenchRun], out: Path) -> dict[BenchRun, Curve]:
    """The curves of the runs finished under their current settings."""
    return {
        run: Curve.load(run.result(out))
        for run in runs
        if Curve.key_of(run.result(out)) == run.key()
    }


def run_bench(
    tasks: Sequence[BenchTask],
    out: Path,
    *,
    jobs: int,
    command: str,
    ray: str | None = None,
    report_only: bool = False,
    log: Callable[[str], None] = print,
    progress: ProgressFactory | None = None,
) -> tuple[Path, list[str]]:
    """Run the benchmark into ``out`` (``report_only``: nothing more) and write its report from
    the runs finished; return the report's file and the failed runs' errors. ``progress``: as
    :func:`run_all`'s."""

    made = provenance(command)
    runs = bench_runs(tasks)
    errors = (
        [] if report_only else run_all(runs, out, jobs=jobs, ray=ray, log=log, progress=progress)
    )
    curves = load_curves(runs, out)
    started = {run.task.name for run in curves}
    log("measuring throughput")
    file = write_report(
        tasks=tasks,
        curves=curves,
        yardsticks={task.name: task.yardstick() for task in tasks if task.name in started},
        throughput=throughput(),
        errors=errors,
        provenance=made,
        out=out,
    )
    return file, errors
