"""``qdsega reform`` end to end on a tiny body at a tiny budget: killed with SIGKILL, then run
again, it keeps what it had finished and writes everything; bad input is one line, exit 2
and nothing written."""

from __future__ import annotations

import json
import signal
from collections import Counter
from pathlib import Path

import pytest
from helpers import BIPED, TINY_TRAINING, run_cli, start_cli, stop_when

from qdsega.description import load_formation

pytestmark = pytest.mark.slow


@pytest.fixture
def biped(tmp_path: Path) -> tuple[Path, Path]:
    """The tiny body and a --config for runs of two tiny generations."""
    body = tmp_path / "biped.yaml"
    body.write_text(BIPED)
    config = tmp_path / "tiny.yaml"
    config.write_text(TINY_TRAINING.replace("{population: 6}", "{population: 6, generations: 2}"))
    return body, config


def test_a_killed_reform_keeps_what_it_finished_and_ends_with_everything(
    biped: tuple[Path, Path], quadruped_repertoire: Path, tmp_path: Path
):
    body, config = biped
    repertoire = quadruped_repertoire  # a body whose legs L1 and R1 the biped has
    out = tmp_path / "reform"
    args = ("reform", body, "--config", config, "--screen", "1", "--rounds", "1", "--top", "1",
            "--repertoire", repertoire, "--jobs", "2", "--out", out)  # fmt: skip
    process = start_cli(*args)
    first = out / "runs" / "c00" / "metrics.csv"
    stop_when(process, first.is_file, signal.SIGKILL)
    process.communicate()
    screened = first.read_text()

    result = run_cli(*args)
    assert result.returncode == 0, result.stderr
    assert first.read_text().startswith(screened)  # kept, then learnt on from there
    record = json.loads((out / "reform.json").read_text())
    names = [row["name"] for row in record["candidates"]]
    assert names == ["c00", "c01", "c02", "c03"]  # as the candidate test finds them by hand
    assert all(row["estimate_m"] is not None for row in record["candidates"])
    adapted = record["current"]["adapted"]
    assert adapted["distance_m"] >= 0 and (out / "adapt" / "adapt.json").is_file()
    learnt = [row["name"] for row in record["candidates"] if row["distance_m"] is not None]
    assert learnt[0] == "c00" and len(learnt) == 2  # the body as it is, and the best other
    winner = record["winner"]
    assert winner["name"] in learnt
    assert winner["distance_m"] == max(
        row["distance_m"] for row in record["candidates"] if row["distance_m"] is not None
    )
    # the winner's file is a body of the material's units, no more
    material = Counter(u.unit_type.name for u in load_formation(body).units)
    won = load_formation(out / "winner.yaml")
    assert Counter(u.unit_type.name for u in won.units) <= material
    assert {u.name for u in won.units} <= {u.name for u in load_formation(body).units}
    run = out / "runs" / winner["name"]
    for name in ("evaluation.json", "gait.mp4", "report.html", "learning_curve.png"):
        assert (run / name).is_file(), name
    for name in learnt:
        assert (out / "stills" / f"{name}.png").is_file()
    plan = (out / "plan.md").read_text()
    moves = len(winner["moves"])
    assert plan.count("![before]") == moves and (out / "plan" / f"step{moves}.png").is_file()
    page = (out / "reform.html").read_text()
    assert page.count("<img") >= len(learnt) + 1 + 2 * moves and "<video" in page
    assert "c00" in (out / "reform.md").read_text()
    assert f"-> {out}/reform.md" in result.stdout


BLOCKED = BIPED.replace(
    "connector: left, side: left}",
    "connector: left, side: left,\n     overrides: {swing: {levels_deg: [-15, 90]}}}",
)
"""The biped with a swing level that hits the hub."""


def test_bad_input_is_one_line_and_writes_nothing(biped: tuple[Path, Path], tmp_path: Path):
    body, _ = biped
    locked = tmp_path / "locked.yaml"  # every joint locked: nothing can move
    locked.write_text(
        BIPED.replace("levels_deg: [-15, 15]}", "locked_deg: 0}")
        .replace("levels_deg: [-35, 5]}", "locked_deg: 0}")
        .replace("overrides: {swing: {levels_deg: [15, -15]}}", "")
    )
    blocked = tmp_path / "blocked.yaml"
    blocked.write_text(BLOCKED)
    cases = {
        "--spare gripper: unknown unit type 'gripper'": ("--spare", "gripper=1"),
        "--spare 'servo': expected TYPE=N": ("--spare", "servo"),
        "no candidate can move (c00: no working joint)": ("--formation", locked),
        "no such file, nor a shipped formation": ("--formation", "nope"),
        "cannot reach level 1 (90 deg): unit L1_lift hits unit body1": ("--formation", blocked),
        "no such file, nor a shipped world": ("--world", "moon"),
        "not a repertoire": ("--repertoire", tmp_path),
    }
    for message, (option, value) in cases.items():
        out = tmp_path / "out"
        given = (value,) if option == "--formation" else (body, option, value)
        result = run_cli("reform", *given, "--out", out)
        assert result.returncode == 2, (message, result.stderr)
        assert result.stderr.count("\n") == 1 and message in result.stderr, result.stderr
        assert not out.exists(), message


def test_allow_blocked_goes_on_with_the_body_as_it_is(biped: tuple[Path, Path], tmp_path: Path):
    """The refusal is a warning and the body as it is is screened (stopped once it is)."""
    _, config = biped
    blocked = tmp_path / "blocked.yaml"
    blocked.write_text(BLOCKED)
    out = tmp_path / "reform"
    process = start_cli(
        "reform", blocked, "--config", config, "--screen", "1", "--rounds", "1", "--top", "1",
        "--allow-blocked", "--out", out,
    )  # fmt: skip
    stop_when(process, (out / "runs" / "c00").is_dir, signal.SIGKILL)
    _, err = process.communicate()
    (warning,) = [line for line in err.splitlines() if ": warning: " in line]
    assert warning.startswith(f"qdsega reform: warning: {blocked}:")
    assert "cannot reach level 1 (90 deg): unit L1_lift hits unit body1" in warning
    assert (out / "candidates" / "c00.yaml").is_file()
    assert json.loads((out / "reform.json").read_text())["inputs"]["settings"]["allow_blocked"]
