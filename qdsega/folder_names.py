"""The one rule for the folder a command writes into when ``--out`` does not name one:
``runs/[COMMAND-]BODY[-WORLD][-SETTING...][-seedS]``."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

RUNS = Path("runs")
"""Where default output folders go, relative to the working directory."""


def default_folder(
    body: str,
    *,
    command: str | None = None,
    world: Path | None = None,
    settings: Sequence[str] = (),
    seed: int | None = None,
) -> Path:
    """``runs/[COMMAND-]BODY[-WORLD][-SETTING...][-seedS]``: ``body`` is the formation file's
    stem (or a label for a bag of units), ``world`` the world file (None on flat ground, which
    adds nothing), ``settings`` what else tells runs of one body apart (the simulator, the
    preset)."""
    parts = [*([command] if command else []), body]
    parts += [world.stem] if world is not None else []
    parts += [*settings, *([f"seed{seed}"] if seed is not None else [])]
    return RUNS / "-".join(parts)
