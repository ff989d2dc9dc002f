"""One driver for many runs: ``sweep``, ``match``, ``bench`` and ``reform`` hand it jobs, and it
runs each in a fresh process of its own (``processes`` at a time) or as a Ray task (one CPU
each, here or on a cluster), says as each one ends, and shows the jobs finished with the
time left.

A job is a picklable callable that does its work where it runs and returns None, or its
error in one line: a job that fails is reported, and the others go on. Jobs resume what a
crash left (their folders hold their state), so running the same jobs again finishes them;
one that was finished before (:meth:`Job.kept`) counts as done from the start and is not run
again. Ctrl-C stops every job, each keeping its last checkpoint; a job whose driver is killed
stops too.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Protocol, TypeVar

from qdsega.errors import QdsegaError
from qdsega.progress import ProgressFactory
from qdsega.training.run import TrainingInterrupted

PARENT_CHECK_S = 1.0
"""How often a job's process checks that the driver that started it is still there (s)."""
ONE_THREAD = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
"""Environment variables that hold each job's linear algebra to one thread: a job is one
core's work (with two threads per job on two cores, CMA-ES's eigendecompositions for legged12
took 96 ms instead of 1 ms each, threads waiting on each other)."""


class Job(Protocol):
    """One run of many."""

    @property
    def name(self) -> str: ...

    def __call__(self) -> str | None:
        """Do the work (in the job's own process): None, or what went wrong in one line."""
        ...

    def kept(self) -> bool:
        """Whether it was finished before (the driver counts it done at once)."""
        ...


_JobT = TypeVar("_JobT", bound=Job)


def error_line(exc: Exception) -> str:
    """A job's error in one line: a user's mistake as the command line words it, anything else
    with its type."""
    return str(exc) if isinstance(exc, QdsegaError) else f"{type(exc).__name__}: {exc}"


class Stopped(KeyboardInterrupt):
    """Ctrl-C reached a job: the driver stops every job."""


def run_jobs(
    jobs: Sequence[_JobT],
    *,
    processes: int = 1,
    ray: str | None = None,
    label: str = "runs",
    report: Callable[[_JobT, str | None], None] = lambda job, error: None,
    progress: ProgressFactory | None = None,
) -> list[str | None]:
    """Run every job, ``processes`` at a time, or as Ray tasks when ``ray`` is ``local`` or an
    address; return each job's error (None: it went well), in the jobs' order.

    ``report(job, error)`` is called as each job ends (on local processes in the order they
    end); ``progress`` makes a line ``label`` of jobs finished of all, with the time left
    (None: silent).

    Raises:
        ValueError: ``processes`` below 1.
        KeyboardInterrupt: Ctrl-C; the jobs not started never start.
    """
    if processes < 1:
        raise ValueError(f"processes must be at least 1, got {processes}")
    kept = {index for index, job in enumerate(jobs) if job.kept()}
    line = None if progress is None else progress(label, len(jobs), initial=len(kept))
    errors: list[str | None] = [None] * len(jobs)
    counts = {"done": len(kept), "failed": 0}

    def ended(index: int, error: str | None) -> None:
        errors[index] = error
        report(jobs[index], error)
        counts["failed"] += error is not None
        if index in kept:  # counted from the start: the line shows nothing new
            return
        counts["done"] += 1
        if line is not None:
            line.update(counts["done"], f"{counts['failed']} failed")

    for index in sorted(kept):  # finished before: nothing to run
        ended(index, None)
    todo = [index for index in range(len(jobs)) if index not in kept]
    try:
        with one_thread_each():
            if todo and ray is not None:
                from qdsega.workers.ray_cluster import connect

                cluster = connect(ray)
                remote = cluster.remote(num_cpus=1)(run_job)
                pending = {index: remote.remote(jobs[index]) for index in todo}
                for index, task in pending.items():
                    ended(index, cluster.get(task))
            elif todo:
                spawn = multiprocessing.get_context("spawn")  # a fresh process for each job
                with ProcessPoolExecutor(
                    processes, mp_context=spawn, initializer=_stop_with_the_driver
                ) as pool:
                    futures = {pool.submit(run_job, jobs[index]): index for index in todo}
                    try:
                        for future in as_completed(futures):
                            ended(futures[future], future.result())
                    except BaseException:  # Ctrl-C: the jobs not started never start
                        pool.shutdown(cancel_futures=True)
                        raise
    finally:
        if line is not None:
            line.close()
    return errors


@contextlib.contextmanager
def one_thread_each() -> Iterator[None]:
    """Processes started within hold their linear algebra to one thread (:data:`ONE_THREAD`)."""
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


_driver: int | None = None
"""In a job's process: the process id of the driver that started it."""


def _stop_with_the_driver() -> None:
    """In a job's process: once the driver that started it is gone (killed, not stopped by
    Ctrl-C), stop the job as Ctrl-C would (its checkpoint kept), then end the process, so
    that nothing goes on writing a folder without the driver."""
    global _driver
    _driver = os.getppid()
    # A driver started in the background of a script has SIGINT ignored, and its jobs inherit
    # that: without Python's own handler, the SIGINT below would change nothing.
    signal.signal(signal.SIGINT, signal.default_int_handler)

    def watch() -> None:
        while not _driver_gone():
            time.sleep(PARENT_CHECK_S)
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=watch, name="driver-watch", daemon=True).start()


def _driver_gone() -> bool:
    return _driver is not None and os.getppid() != _driver


_stopped = False
"""Whether this process saw Ctrl-C: a job handed to it after that (a process pool queues one
ahead) does not start."""


def run_job(job: Job) -> str | None:
    """Run ``job`` where this is called (a pool's process, a Ray task). Ctrl-C stops the
    driver, not just this job: it raises :class:`Stopped` here and in every later call in
    this process."""
    global _stopped
    if _stopped:
        raise Stopped
    try:
        return job()
    except (KeyboardInterrupt, TrainingInterrupted):
        _stopped = True
        if _driver_gone():  # the job stopped and saved; nothing waits for this process now
            os._exit(130)
        raise Stopped from None
