"""Worker processes for simulations: the one way the toolkit starts them.

Workers are spawned (not forked: each builds its own PyBullet client), leave Ctrl-C to their
parent, which stops the pool, and end as soon as their parent is gone, however it ended: a
parent killed with SIGKILL would otherwise leave them waiting for work forever.

With ``ray`` given, the same workers are Ray actors instead
(:mod:`qdsega.workers.ray_cluster`), on this machine or spread over a cluster; the work and its
results are the same.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ProcessPoolExecutor
from typing import Any, Protocol

PARENT_CHECK_S = 1.0
"""How often a worker checks that its parent is alive (s)."""


class Pool(Protocol):
    """What the toolkit asks of a pool of workers (a ``ProcessPoolExecutor`` is one)."""

    def map(self, fn: Callable[..., Any], *iterables: Iterable[Any]) -> Iterator[Any]:
        """``fn`` over the zipped ``iterables`` in the workers; results in the given order."""
        ...

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Stop the workers."""
        ...


def worker_pool(
    workers: int,
    initializer: Callable[..., None],
    initargs: tuple[Any, ...],
    *,
    ray: str | None = None,
) -> Pool:
    """A pool of ``workers`` workers, each set up by ``initializer(*initargs)``: spawned
    processes, or Ray actors when ``ray`` is ``"local"`` (a Ray instance started on this
    machine) or the address of a Ray cluster to join.

    Raises:
        WorkerError: ``ray`` given but Ray is not installed.
    """
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    if ray is not None:
        from qdsega.workers.ray_cluster import RayPool  # imports Ray: only when asked for

        return RayPool(workers, initializer, initargs, address=ray)
    return ProcessPoolExecutor(
        workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_start_worker,
        initargs=(os.getpid(), initializer, initargs),
    )


def _start_worker(parent: int, initializer: Callable[..., None], initargs: tuple[Any, ...]) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_exit_with, args=(parent,), daemon=True).start()
    initializer(*initargs)


def _exit_with(parent: int) -> None:
    """End this process once ``parent`` is no longer its parent (it died; we were adopted)."""
    while os.getppid() == parent:
        time.sleep(PARENT_CHECK_S)
    os._exit(0)
