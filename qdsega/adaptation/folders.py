"""A repertoire's folder and an adaptation's: where each of their files goes, as
:class:`~qdsega.training.run_folder.RunFolder` is for a run."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from qdsega.training.run_folder import RunFolder


@dataclass(frozen=True)
class RepertoireFolder:
    """The repertoire folder at ``path`` (``qdsega repertoire``'s), which may not exist yet.

    Like a run folder it also holds its own copy of the formation and of the world, under a
    run folder's names.
    """

    path: Path

    @property
    def archive(self) -> Path:
        """The archive with the search's state and count, replaced after every batch."""
        return self.path / "repertoire.npz"

    @property
    def record(self) -> Path:
        """What the repertoire is of and how it was built, replaced after every batch."""
        return self.path / "repertoire.json"

    @property
    def archive_map(self) -> Path:
        """The figure of the archive's elites, drawn once a cell is filled."""
        return self.path / "archive.png"

    @property
    def elites(self) -> Path:
        """The elites as CSV, a row each (``qdsega repertoire --export``)."""
        return self.path / "elites.csv"


@dataclass(frozen=True)
class AdaptationFolder:
    """The adaptation folder at ``path`` (``qdsega adapt``'s), which may not exist yet."""

    path: Path

    @property
    def result(self) -> Path:
        """The trials, the gait found, why the search stopped, the joints' mapping."""
        return self.path / "adapt.json"

    @property
    def gait(self) -> Path:
        """The gait found, repeated for a trial's commands: a posture of level indices a row."""
        return self.path / "gait.csv"

    @property
    def curve(self) -> Path:
        """The figure of each trial's distance against the trials."""
        return self.path / "adaptation_curve.png"

    @property
    def video(self) -> Path:
        """The film of the gait found (none with ``--no-video``)."""
        return self.path / RunFolder.VIDEO

    @property
    def report(self) -> Path:
        """The page ``qdsega report`` writes, named as a run's."""
        return self.path / RunFolder.REPORT

    @property
    def external(self) -> Path:
        """What a robot needs to play an external adaptation's gaits (``--external``): the
        joints, the rest posture, the timing, the repertoire it is adapted from."""
        return self.path / "external.json"

    def trial_gait(self, trial: int) -> Path:
        """The gait to try in external trial ``trial`` (from 1): joint angles over time, CSV."""
        return self.path / "trials" / f"{trial:03d}.csv"

    def trial_result(self, trial: int) -> Path:
        """What the robot did in external trial ``trial``: the distance it walked (m), written
        by the robot's side."""
        return self.path / "trials" / f"{trial:03d}.result"
