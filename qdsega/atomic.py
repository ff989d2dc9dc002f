"""Files that are either whole or absent: write beside the target, then rename over it."""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def replaced_atomically(target: Path) -> Iterator[Path]:
    """A temporary path beside ``target`` (same folder, same suffix) to write to.

    When the block ends normally the temporary file is renamed over ``target`` (atomic on one
    file system); when it raises, including Ctrl-C, the temporary file is removed and
    ``target`` keeps its old content.
    """
    partial = target.with_name(f".{target.stem}.partial{target.suffix}")
    try:
        yield partial
        os.replace(partial, target)
    finally:
        partial.unlink(missing_ok=True)
