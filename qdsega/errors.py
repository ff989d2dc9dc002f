"""The one error type for bad user input (formations, units, run folders)."""

from __future__ import annotations

from pathlib import Path


class FormationError(ValueError):
    """Bad input, reported as one line: ``FILE:LINE: KEY.PATH: what is wrong``.

    Args:
        message: what is wrong, in words a user can act on.
        file: the offending file.
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


class QdsegaWarning(UserWarning):
    """Something a user should know that does not stop the work (an edited formation, a
    missing renderer); the command line prints it as one line
    ``qdsega COMMAND: warning: ...``."""
