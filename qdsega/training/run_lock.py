"""One ``qdsega train`` at a time per run folder: an exclusive lock on ``RUN/train.lock``.

The lock is ``fcntl.flock`` on that file, not a file created with ``O_EXCL`` that holds a pid:
the kernel releases a flock when the process that holds it ends, however it ends (Ctrl-C,
SIGKILL, a crash), so a killed run never leaves a lock behind, and nothing has to guess
whether a recorded pid is still alive (pids are reused, and one from another machine sharing
the folder means nothing here). The file holds the holder's pid only to name it in the
refusal; it stays in the folder, unlocked, when the run ends. POSIX only, as ``make`` is.
"""

from __future__ import annotations

import fcntl
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from qdsega.errors import RunFolderError
from qdsega.training.run_folder import RunFolder

"""Locked by the process writing the run folder."""


@contextmanager
def run_lock(run: Path) -> Iterator[None]:
    """Hold the lock of the existing folder ``run`` for the block.

    Raises:
        RunFolderError: another process holds it.
    """
    descriptor = os.open(run / RunFolder.LOCK, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(descriptor, 32, 0).decode("ascii", "replace").strip()
            raise RunFolderError(
                f"another qdsega train (pid {holder or 'unknown'}) is writing this run folder; "
                "wait for it to end, or stop it and continue with --resume",
                file=run,
            ) from None
        os.ftruncate(descriptor, 0)
        os.pwrite(descriptor, f"{os.getpid()}\n".encode("ascii"), 0)
        yield
    finally:
        os.close(descriptor)
