"""``qdsega bench``: every method on every task for every seed, then the report.

Each run (task, method, seed) works in ``OUT/runs/TASK/METHOD-seedS/`` and leaves its curve in
``OUT/results/TASK/METHOD-seedS.json`` when it finishes; a re-run skips finished runs (and a
QDSEGA training run resumes where a crash left it), so a stopped benchmark continues. Runs go
to ``jobs`` worker processes, each run on one core. A run that fails is reported with its
error, the others go on, and the report leaves it out.
"""

from __future__ import annotations

import contextlib
import datetime
import multiprocessing
import os
import platform
import subprocess
import traceback
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from qdsega.bench.curve import Curve
from qdsega.bench.methods import METHODS
from qdsega.bench.tasks import BenchTask

if TYPE_CHECKING:
    from qdsega.bench.report import Provenance


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


def run_all(
    runs: Sequence[BenchRun], out: Path, *, jobs: int, log: Callable[[str], None] = print
) -> list[str]:
    """Run every unfinished run, ``jobs`` at a time; return the failed runs' one-line errors."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    todo = [run for run in runs if not run.result(out).is_file()]
    log(f"{len(runs) - len(todo)} of {len(runs)} runs finished before; running {len(todo)}")
    errors: list[str] = []
    context = multiprocessing.get_context("spawn")  # no simulator or torch state inherited
    with _one_thread_each(), ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
        futures = {pool.submit(_run_one, run, out): run for run in todo}
        for future in as_completed(futures):
            run = futures[future]
            label = f"{run.task.name} {run.name}"
            error = future.result()
            if error is None:
                curve = Curve.load(run.result(out))
                log(f"{label}: {curve.distance_m[-1]:.3f} m at {curve.steps[-1]} steps")
            else:
                errors.append(f"{label}: {error}")
                log(f"{label}: FAILED: {error}")
    return errors


ONE_THREAD = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
"""Environment variables that hold each worker's linear algebra to one thread."""


@contextlib.contextmanager
def _one_thread_each() -> Iterator[None]:
    """Workers started within hold their linear algebra to one thread: a run is one core's
    work, and with two threads per worker on two cores CMA-ES's eigendecompositions (73 x 73
    for legged12) took 96 ms instead of 1 ms each (threads waiting on each other)."""
    saved = {name: os.environ.get(name) for name in ONE_THREAD}
    os.environ.update(dict.fromkeys(ONE_THREAD, "1"))
    try:
        yield
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value


def _run_one(run: BenchRun, out: Path) -> str | None:
    """Run ``run`` and keep its curve; its error's last line if it fails."""
    try:
        folder = run.folder(out)
        folder.mkdir(parents=True, exist_ok=True)
        curve = METHODS[run.method](run.task, run.seed, folder)
        file = run.result(out)
        file.parent.mkdir(parents=True, exist_ok=True)
        curve.save(file)
        return None
    except Exception as exc:  # a failed run is reported, not fatal
        lines = traceback.format_exception_only(exc)
        return lines[-1].strip() if lines else repr(exc)


def load_curves(runs: Sequence[BenchRun], out: Path) -> dict[BenchRun, Curve]:
    """The curves of the finished runs."""
    return {run: Curve.load(run.result(out)) for run in runs if run.result(out).is_file()}


def run_bench(
    tasks: Sequence[BenchTask],
    out: Path,
    *,
    jobs: int,
    command: str,
    log: Callable[[str], None] = print,
) -> tuple[Path, list[str]]:
    """Run the benchmark into ``out`` and write its report; return the report's file and the
    failed runs' errors."""
    from qdsega.bench.report import write_report
    from qdsega.bench.throughput import throughput

    made = provenance(command)
    runs = bench_runs(tasks)
    errors = run_all(runs, out, jobs=jobs, log=log)
    log("measuring throughput")
    file = write_report(
        tasks=tasks,
        curves=load_curves(runs, out),
        yardsticks={task.name: task.yardstick() for task in tasks},
        throughput=throughput(),
        errors=errors,
        provenance=made,
        out=out,
    )
    return file, errors


def provenance(command: str) -> Provenance:
    """This machine, today, the checkout's commit, and ``command``."""
    from qdsega.bench.report import Provenance

    source = Path(__file__).resolve().parent
    commit = _git(source, "rev-parse", "--short", "HEAD") or "unknown (not a git checkout)"
    if _git(source, "status", "--porcelain", "--untracked-files=no"):
        commit += " + changes"
    machine = f"{platform.machine()} {platform.processor() or platform.system()}".strip()
    return Provenance(
        machine=f"{machine}, {os.cpu_count()} cores, Python {platform.python_version()}",
        date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        commit=commit,
        command=command,
    )


def _git(folder: Path, *args: str) -> str:
    try:
        done = subprocess.run(
            ["git", *args], cwd=folder, capture_output=True, text=True, check=True, timeout=30
        )
    except (OSError, subprocess.SubprocessError):
        return ""
    return done.stdout.strip()
