"""A reform's folder: where each of its files goes (``docs/commands.md#reform`` says what each
holds)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class ReformFolder:
    """The reform folder at ``path``, which may not exist yet."""

    path: Path

    @property
    def record(self) -> Path:
        """``reform.json``: the inputs first, then every candidate, the winner and its plan."""
        return self.path / "reform.json"

    @property
    def config(self) -> Path:
        """The settings over each candidate's preset (a copy of ``--config``), if given."""
        return self.path / "config.yaml"

    def candidate(self, name: str) -> Path:
        """A candidate's formation file."""
        return self.path / "candidates" / f"{name}.yaml"

    def run(self, name: str) -> Path:
        """A candidate's run folder (screened: stopped early; learnt: finished, evaluated)."""
        return self.path / "runs" / name

    @property
    def adaptation(self) -> Path:
        """The body as it is, adapted from the repertoire (``qdsega adapt``'s folder)."""
        return self.path / "adapt"

    @property
    def winner(self) -> Path:
        """The winner's formation file."""
        return self.path / "winner.yaml"

    @property
    def summary(self) -> Path:
        return self.path / "reform.md"

    @property
    def plan(self) -> Path:
        return self.path / "plan.md"

    @property
    def page(self) -> Path:
        """One page that shows all of it."""
        return self.path / "reform.html"

    def still(self, name: str) -> Path:
        """Where a learnt candidate's evaluated trial ended."""
        return self.path / "stills" / f"{name}.png"

    def plan_picture(self, step: int) -> Path:
        """The body after ``step`` moves of the plan (0: as it is)."""
        return self.path / "plan" / f"step{step}.png"
