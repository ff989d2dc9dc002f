"""Silence output that PyBullet's C code writes straight to the process's stdout or stderr."""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator


@contextlib.contextmanager
def native_output_silenced(fd: int) -> Iterator[None]:
    """Send file descriptor ``fd`` (1 stdout, 2 stderr) to /dev/null for the duration."""
    (sys.stdout if fd == 1 else sys.stderr).flush()
    saved = os.dup(fd)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
        yield
    finally:
        os.dup2(saved, fd)
        os.close(saved)
        os.close(devnull)
