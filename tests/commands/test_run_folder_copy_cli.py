"""A run folder is self-contained: moved elsewhere, with its formation's files deleted or
edited, it evaluates and renders to the same numbers."""

from __future__ import annotations

import json
import shutil

import pytest
from helpers import run_cli

from qdsega.description.shipped import ASSEMBLIES_DIR

pytestmark = pytest.mark.slow  # end to end: make test-fast leaves it out

TINY = "task: {trial_steps: 6}\n"
NO_SEARCH = ("--reference-trials", "0")  # the classic gaits only: this test is about files


def test_a_moved_run_folder_evaluates_the_same_without_its_formation_files(project, tmp_path):
    formation = project / "assemblies" / "walker.yaml"
    original = (ASSEMBLIES_DIR / "quadruped.yaml").read_text() + "units_dir: ../units\n"
    formation.write_text(original)
    config = tmp_path / "tiny.yaml"
    config.write_text(TINY)
    run = tmp_path / "run"
    trained = run_cli(
        "train", formation, "--config", config, "--generations", "2", "--trials", "50",
        "--out", run, "--quiet",
    )  # fmt: skip
    assert trained.returncode == 0, trained.stderr
    summary = json.loads((run / "summary.json").read_text())
    assert summary["formation_file"] == str(formation.resolve())
    assert len(summary["formation_sha256"]) == 64
    evaluated = run_cli("evaluate", run, *NO_SEARCH)
    assert evaluated.returncode == 0 and evaluated.stderr == "", evaluated.stderr
    expected = json.loads((run / "evaluation.json").read_text())

    moved = tmp_path / "elsewhere" / "run"
    shutil.copytree(run, moved)
    (moved / "evaluation.json").unlink()
    shutil.rmtree(project / "units")
    formation.unlink()
    again = run_cli("evaluate", moved, *NO_SEARCH)
    assert again.returncode == 0 and again.stderr == "", again.stderr
    assert json.loads((moved / "evaluation.json").read_text()) == expected

    formation.write_text(original.replace("distance_m: 50.0", "distance_m: 5.0"))
    edited = run_cli("evaluate", moved, *NO_SEARCH)
    assert edited.returncode == 0, edited.stderr
    assert edited.stderr.startswith(f"qdsega evaluate: warning: {formation.resolve()} ")
    assert "changed since this run copied" in edited.stderr
    assert len(edited.stderr.strip().splitlines()) == 1
    assert json.loads((moved / "evaluation.json").read_text()) == expected

    (moved / "evaluation.json").unlink()  # render replays the policy from the copy
    gif = tmp_path / "moved.gif"
    rendered = run_cli("render", moved, "-o", gif, "--fps", "2", "--width", "32", "--height", "24")
    assert rendered.returncode == 0, rendered.stderr
    assert "changed since" in rendered.stderr and gif.is_file()

    (moved / "formation.json").unlink()
    refused = run_cli("evaluate", moved, *NO_SEARCH)
    assert refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1
    assert "no copy of the formation" in refused.stderr and "--overwrite" in refused.stderr
