"""The errors a user can act on, and the warning they should see.

Every one is :class:`QdsegaError`: one line, ``FILE:LINE: KEY.PATH: what is wrong``, which the
command line prints as ``qdsega COMMAND: error: ...`` before exiting with status 2. Catch the
subclass that names what was wrong.
"""

from __future__ import annotations

from pathlib import Path


class QdsegaError(ValueError):
    """Bad input, reported as one line: ``FILE:LINE: KEY.PATH: what is wrong``.

    Args:
        message: what is wrong, in words a user can act on.
        file: the offending file or folder.
        line: 1-based line in ``file`` where known.
        key_path: dotted path to the offending key, e.g. ``units[3].parent``.
    """

    def __init__(
        self,
        message: str,
        *,
        file: Path | str | None = None,
        line: int | None = None,
        key_path: str | None = None,
    ) -> None:
        self.message = message
        self.file = None if file is None else Path(file)
        self.line = line
        self.key_path = key_path
        super().__init__(str(self))

    def __str__(self) -> str:
        where = ""
        if self.file is not None:
            where = str(self.file)
            if self.line is not None:
                where += f":{self.line}"
            where += ": "
        key = f"{self.key_path}: " if self.key_path else ""
        return f"{where}{key}{self.message}"


class FormationError(QdsegaError):
    """A formation or unit file that cannot be read, or a body that cannot be built or moved."""


class WorldError(QdsegaError):
    """A world file that cannot be read, or a world a body cannot start in."""


class ConfigError(QdsegaError):
    """A training configuration, preset, sweep grid or combination of options that does not
    hold together."""


class RunFolderError(QdsegaError):
    """A run folder that is missing, unfinished, corrupt, busy, or not what the command needs."""


class WorkerError(QdsegaError):
    """Workers that cannot start: Ray missing, or a cluster that cannot be reached."""


class QdsegaWarning(UserWarning):
    """Something a user should know that does not stop the work (an edited formation, a
    missing renderer); the command line prints it as one line
    ``qdsega COMMAND: warning: ...``."""
