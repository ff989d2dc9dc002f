"""Reading a run folder's plain files: the checks and messages every command shares."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from qdsega.errors import RunFolderError

SUMMARY_FILE = "summary.json"
"""Written last by ``qdsega train``: its presence means the run is finished."""
EVALUATION_FILE = "evaluation.json"
"""Written by ``qdsega evaluate``."""
POLICY_FILE = "policy.npz"
"""The run's result: the greedy policy (:class:`qdsega.agent.policy.GreedyPolicy`) of its
farthest generation with exact physics, written by train."""
WARM_START_FILE = "warm_start.json"
"""A warm-started run: where it started from (written by train)."""
WARM_START_STATE = "warm_start.npz"
"""A warm-started run: the joint mapping and the learner state it starts from."""


def require_finished(run: Path, *names: str) -> None:
    """Check that ``run`` is a folder holding a summary and every file in ``names``.

    Raises:
        RunFolderError: no such folder, or a file missing.
    """
    if not run.is_dir():
        raise RunFolderError("run folder not found", file=run)
    for name in (SUMMARY_FILE, *names):
        if not (run / name).is_file():
            raise RunFolderError(f"not a finished run folder (no {name})", file=run)


def read_summary(run: Path) -> dict[str, Any]:
    """The run's ``summary.json`` (call :func:`require_finished` first).

    Raises:
        RunFolderError: the file does not parse or is not a summary.
    """
    summary = _read_json(run, SUMMARY_FILE)
    if not isinstance(summary, dict) or not {"formation", "formation_file"} <= summary.keys():
        raise RunFolderError(f"corrupt run folder ({SUMMARY_FILE} is not a summary)", file=run)
    return summary


def read_evaluation(run: Path) -> dict[str, Any] | None:
    """The run's ``evaluation.json``, or None before ``qdsega evaluate``.

    Raises:
        RunFolderError: the file does not parse or is not an evaluation.
    """
    if not (run / EVALUATION_FILE).is_file():
        return None
    evaluation = _read_json(run, EVALUATION_FILE)
    if not isinstance(evaluation, dict) or not {"postures", "reference"} <= evaluation.keys():
        message = f"corrupt run folder ({EVALUATION_FILE} is not an evaluation)"
        raise RunFolderError(message, file=run)
    return evaluation


def _read_json(run: Path, name: str) -> Any:
    try:
        return json.loads((run / name).read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise RunFolderError(f"corrupt run folder ({name}: {exc})", file=run) from None
