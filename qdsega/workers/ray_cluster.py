"""Workers as Ray actors: the pool behind ``--ray local|ADDRESS``.

Each actor is set up once by the pool's initializer (it builds its own PyBullet world, as a
worker process does) and then runs module-level functions on its arguments. Results come back
in the order the work was given, so what a pool computes does not depend on Ray.

``local`` starts a Ray instance on this machine for this process (stopped when it ends); any
other value is passed to ``ray.init(address=...)`` to join a running cluster (``auto``,
``HOST:PORT`` or ``ray://HOST:PORT``), whose nodes need the same qdsega installed. Ray is an
optional extra (``pip install -e '.[ray]'`` in the checkout). A local instance runs its workers
at normal priority (Ray's default, niceness 15, let any other load on this machine slow them
down 5x, measured here), unless ``RAY_worker_niceness`` is set.
"""

from __future__ import annotations

import argparse
import logging
import os
from collections.abc import Callable, Iterable, Iterator
from typing import Any

from qdsega.errors import WorkerError

LOCAL = "local"
"""The ``--ray`` value that starts a Ray instance on this machine."""


def add_ray_option(parser: argparse.ArgumentParser) -> None:
    """``--ray``, for a command whose runs :func:`run_jobs` spreads."""
    parser.add_argument(
        "--ray",
        metavar="local|ADDRESS",
        help="spread runs over Ray tasks instead of --jobs processes: local starts Ray here, an "
        "address joins a cluster (its nodes see the output folder on a shared file system)",
    )


def connect(address: str, *, cpus: int = 0) -> Any:
    """The ``ray`` module, connected to ``address`` (``local``: a new instance here), whose
    cluster has at least ``cpus`` CPUs.

    Raises:
        WorkerError: Ray is not installed, or the cluster has fewer CPUs.
    """
    try:
        import ray
    except ImportError:
        raise WorkerError("--ray needs Ray: pip install -e '.[ray]' in the checkout") from None
    if not ray.is_initialized():
        options: dict[str, Any] = {"include_dashboard": False, "logging_level": logging.ERROR}
        if address == LOCAL:
            options["num_cpus"] = os.cpu_count() or 1
            os.environ.setdefault("RAY_worker_niceness", "0")  # read by the raylet it starts
        ray.init(address=address, log_to_driver=False, **options)
    available = ray.cluster_resources().get("CPU", 0)
    if cpus > available:  # actors of one CPU each would wait forever
        raise WorkerError(f"{cpus} Ray workers need {cpus} CPUs; the Ray cluster has {available:g}")
    return ray


class _Actor:
    """One worker: set up by ``initializer(*initargs)``, then runs whatever it is given."""

    def __init__(self, initializer: Callable[..., None], initargs: tuple[Any, ...]) -> None:
        initializer(*initargs)

    def call(self, fn: Callable[..., Any], args: tuple[Any, ...]) -> Any:
        return fn(*args)


class RayPool:
    """``workers`` Ray actors, each set up by ``initializer(*initargs)``; a
    :class:`qdsega.workers.pool.Pool`.

    Args:
        workers: actors, one CPU each.
        initializer: a module-level function run once in each actor.
        initargs: its arguments (pickled to every actor).
        address: ``local`` or a cluster address (module docstring).
    """

    def __init__(
        self,
        workers: int,
        initializer: Callable[..., None],
        initargs: tuple[Any, ...],
        *,
        address: str,
    ) -> None:
        self._ray = connect(address, cpus=workers)
        from ray.util import ActorPool

        actor = self._ray.remote(num_cpus=1)(_Actor)
        self._actors = [actor.remote(initializer, initargs) for _ in range(workers)]
        self._pool = ActorPool(self._actors)

    def map(self, fn: Callable[..., Any], *iterables: Iterable[Any]) -> Iterator[Any]:
        """``fn`` over the zipped ``iterables`` in the actors; results in the given order."""
        work = list(zip(*iterables, strict=True))
        return self._pool.map(lambda actor, args: actor.call.remote(fn, args), work)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Stop the actors (the Ray instance stays for this process's other pools)."""
        for actor in self._actors:
            self._ray.kill(actor)
        self._actors = []
