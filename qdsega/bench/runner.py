"""``qdsega bench``: every method on every task for every seed, then the report.

Each run (task, method, seed) works in ``OUT/runs/TASK/METHOD-seedS/`` and leaves its curve in
``OUT/results/TASK/METHOD-seedS.json`` when it finishes; a re-run skips finished runs (and a
QDSEGA training run resumes where a crash left it), so a stopped benchmark continues. Runs go
to ``jobs`` worker processes, each run on one core. A run that fails is reported with its
error, the others go on, and the report leaves it out.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import traceback
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from qdsega.bench.curve import Curve
from qdsega.bench.methods import METHODS
from qdsega.bench.report import provenance, write_report
from qdsega.bench.runs import BenchRun, bench_runs
from qdsega.bench.tasks import BenchTask
from qdsega.bench.throughput import throughput
from qdsega.progress import ProgressFactory


def run_all(
    runs: Sequence[BenchRun],
    out: Path,
    *,
    jobs: int,
    log: Callable[[str], None] = print,
    progress: ProgressFactory | None = None,
) -> list[str]:
    """Run every unfinished run, ``jobs`` at a time; return the failed runs' one-line errors.
    ``progress`` makes a line of runs finished of all, with an ETA (None: silent)."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    todo = [run for run in runs if not run.result(out).is_file()]
    before = len(runs) - len(todo)
    log(f"{before} of {len(runs)} runs finished before; running {len(todo)}")
    errors: list[str] = []
    line = None if progress is None or not todo else progress("bench", len(runs), initial=before)
    context = multiprocessing.get_context("spawn")  # no simulator or torch state inherited
    try:
        with (
            _one_thread_each(),
            ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool,
        ):
            futures = {pool.submit(_run_one, run, out): run for run in todo}
            for done, future in enumerate(as_completed(futures), start=before + 1):
                run = futures[future]
                label = f"{run.task.name} {run.name}"
                error = future.result()
                if error is None:
                    curve = Curve.load(run.result(out))
                    log(f"{label}: {curve.distance_m[-1]:.3f} m at {curve.steps[-1]} steps")
                else:
                    errors.append(f"{label}: {error}")
                    log(f"{label}: FAILED: {error}")
                if line is not None:
                    line.update(done, f"{len(errors)} failed")
    finally:
        if line is not None:
            line.close()
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
    progress: ProgressFactory | None = None,
) -> tuple[Path, list[str]]:
    """Run the benchmark into ``out`` and write its report; return the report's file and the
    failed runs' errors. ``progress``: as :func:`run_all`'s."""

    made = provenance(command)
    runs = bench_runs(tasks)
    errors = run_all(runs, out, jobs=jobs, log=log, progress=progress)
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
