"""The one reader of a finished run: its configuration, formation, world, checkpoint and policy,
each read on first use through the one function that reads it.

It lives beside :mod:`qdsega.training.run_folder` rather than in it because the readers of the
configuration, the formation's copy and the checkpoint take their file names from there.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

from qdsega.agent.policy import GreedyPolicy
from qdsega.description import Formation, World
from qdsega.errors import RunFolderError
from qdsega.training.checkpoint import Checkpoint, load_checkpoint
from qdsega.training.config import TrainingConfig, read_run_config
from qdsega.training.formation_copy import load_run_formation, load_run_world
from qdsega.training.run_folder import RunFolder


@dataclass(frozen=True)
class FinishedRun:
    """The run folder at ``path``, read piece by piece, each piece once."""

    path: Path

    def __post_init__(self) -> None:
        object.__setattr__(self, "path", Path(self.path))

    @classmethod
    def open(cls, run: Path | str, *names: str) -> FinishedRun:
        """The finished run at ``run``, checked to hold its summary and every file in ``names``.

        Raises:
            RunFolderError: no such folder, or a file missing.
        """
        finished = cls(Path(run))
        finished.folder.require_finished(*names)
        return finished

    @property
    def folder(self) -> RunFolder:
        """Its files by name, and the readers of its plain files."""
        return RunFolder(self.path)

    @cached_property
    def summary(self) -> dict[str, Any]:
        """``summary.json`` (:meth:`RunFolder.read_summary`)."""
        return self.folder.read_summary()

    @cached_property
    def config(self) -> TrainingConfig:
        """The configuration it was trained with (:func:`read_run_config`)."""
        return read_run_config(self.path)

    @cached_property
    def formation(self) -> Formation:
        """Its formation, from its copy, lit as its configuration says
        (:func:`load_run_formation`)."""
        return load_run_formation(self.path, self.config)

    def formation_in(self, world: World) -> Formation:
        """Its formation, from its copy, lit as its configuration says in another ``world``
        (:func:`load_run_formation`)."""
        return load_run_formation(self.path, self.config, world=world)

    @cached_property
    def world(self) -> World:
        """Its world, from its copy; the flat plane where it has none (:func:`load_run_world`)."""
        return load_run_world(self.path)

    @cached_property
    def checkpoint(self) -> Checkpoint | None:
        """Its last checkpoint; None where it has none (:func:`load_checkpoint`)."""
        return load_checkpoint(self.path)

    @cached_property
    def policy(self) -> GreedyPolicy:
        """Its greedy policy, the result's.

        Raises:
            RunFolderError: a policy file that does not read.
        """
        try:
            return GreedyPolicy.load(self.folder / RunFolder.POLICY)
        except ValueError as exc:
            raise RunFolderError(f"corrupt run folder ({exc})", file=self.path) from None
