"""Adaptation: a repertoire's gaits mapped onto a changed body and tried in exact physics; the
same repertoire and body give the same trials; played unmapped on the body hidden from the
search (``--blind``), or by a robot (``--external``) that is that body, they give the same
trials again; a body with no joint in common, or a corrupt repertoire, is one line, exit 2,
and nothing written."""

import argparse
import json

import numpy as np
import pytest
from helpers import run_cli

from qdsega.adaptation.adapt import adapt, adapt_blind
from qdsega.adaptation.hidden_body import HiddenBody
from qdsega.adaptation.repertoire import RepertoireSettings, build_repertoire
from qdsega.adaptation.trajectory import JointTrajectory
from qdsega.analysis import render
from qdsega.analysis.render import read_postures
from qdsega.commands import adapt as adapt_command
from qdsega.description import load_formation, resolve_formation
from qdsega.training.config import resolve_config
from qdsega.training.formation_copy import load_run_world

pytestmark = pytest.mark.slow  # exact physics: seconds


@pytest.fixture(scope="module")
def repertoire(tmp_path_factory):
    quadruped = load_formation(resolve_formation("quadruped"))
    short = {"sim": "memo", "task": {"trial_steps": 10}}  # a third of the preset's trial
    rules = resolve_config(overrides=short, formation=quadruped).rules()
    out = tmp_path_factory.mktemp("repertoire")
    settings = RepertoireSettings(evaluations=48, cells=16, batch=16, initial=16)
    build_repertoire(quadruped, out, rules=rules, settings=settings, workers=1)
    return out


def test_a_leg_lost_is_adapted_to_with_the_mapped_gaits_and_the_same_trials_twice(
    repertoire, tmp_path
):
    tripod = load_formation(resolve_formation("quadruped_tripod"))
    first = adapt(repertoire, tripod, tmp_path / "a", trials=3)
    assert first["joints"]["dropped"] == ["R2_swing_joint", "R2_lift_joint"]
    assert 1 <= len(first["trials"]) <= 3 and first["formation"] == "quadruped_tripod"
    assert first["distance_m"] == max(t["distance_m"] for t in first["trials"])
    commands = read_postures(tmp_path / "a" / "gait.csv", len(tripod.joints))
    assert len(commands) == 30 and np.array_equal(commands[: len(first["gait"])], first["gait"])
    second = adapt(repertoire, tripod, tmp_path / "b", trials=3)
    strip = [{k: v for k, v in t.items() if k != "wall_s"} for t in first["trials"]]
    assert strip == [{k: v for k, v in t.items() if k != "wall_s"} for t in second["trials"]]


def test_the_gaits_played_blind_on_the_hidden_body_or_by_it_as_a_robot_are_the_mapped_ones(
    repertoire, tmp_path
):
    # A lost leg's commands reach nothing, as the mapping drops them: the same trials.
    tripod = load_formation(resolve_formation("quadruped_tripod"))
    mapped = adapt(repertoire, tripod, tmp_path / "mapped", trials=2)
    blind = adapt_blind(repertoire, tripod, tmp_path / "blind", trials=2)
    assert blind["mode"] == "blind" and blind["formation"] == "quadruped_tripod"
    played = [{k: v for k, v in t.items() if k != "wall_s"} for t in mapped["trials"]]
    assert played == [{k: v for k, v in t.items() if k != "wall_s"} for t in blind["trials"]]
    assert blind["gait"] == mapped["gait"] and blind["joints"] == mapped["joints"]
    gait = read_postures(tmp_path / "blind" / "gait.csv", len(tripod.joints))  # the tripod's
    assert np.array_equal(gait, read_postures(tmp_path / "mapped" / "gait.csv", 6))
    # The robot's side, played by the tripod: each gait file read, played, its distance written.
    out = tmp_path / "robot"
    command = ("adapt", repertoire, "--external", "--trials", "2", "--out", out)
    assert run_cli(*command).returncode == 0
    facts = json.loads((out / "external.json").read_text())
    world = load_run_world(repertoire)
    with HiddenBody(body=tripod, world=world, step_s=facts["step_s"],
                    commands=facts["commands"]) as robot:  # fmt: skip
        trial = 1
        while not (out / "adapt.json").is_file():
            played_on = robot.play(JointTrajectory.read(out / "trials" / f"{trial:03d}.csv"))
            answer = f"{played_on.distance_m!r} {played_on.failure or ''}"
            (out / "trials" / f"{trial:03d}.result").write_text(answer)
            result = run_cli(*command)
            assert result.returncode == 0, result.stderr
            trial += 1
    external = json.loads((out / "adapt.json").read_text())
    assert [(t["cell"], t["distance_m"], t["failure"]) for t in external["trials"]] == [
        (t["cell"], t["distance_m"], t["failure"]) for t in blind["trials"]
    ]
    assert external["formation"] == "quadruped" and len(external["gait"][0]) == 8  # its joints


def test_the_command_writes_the_result_the_curve_and_a_page(repertoire, tmp_path):
    out = tmp_path / "adapt"
    result = run_cli("adapt", repertoire, "--formation", "quadruped_tripod", "--trials", "2",
                     "--no-video", "--out", out)  # fmt: skip  # filming: qdsega render's tests
    assert result.returncode == 0, result.stderr
    assert "quadruped_tripod: " in result.stdout and "with exact physics at trial" in result.stdout
    written = {p.name for p in out.iterdir()}
    assert written == {"adapt.json", "gait.csv", "adaptation_curve.png", "report.html"}
    page = (out / "report.html").read_text()
    assert "qdsega adapt: quadruped_tripod from quadruped&#x27;s repertoire" in page
    assert "6 joints matched, 2 dropped (R2_swing_joint, R2_lift_joint)" in page
    assert f"No video: <code>qdsega render FORMATION --postures {out / 'gait.csv'}" in page
    trials = json.loads((out / "adapt.json").read_text())["trials"]
    assert page.count("<tr><td>") == len(trials)  # a row per trial


def test_the_command_films_the_gait_found_in_the_repertoires_world(
    repertoire, tmp_path, monkeypatch
):
    filmed = {}

    def film(formation, postures, out, camera, *, world=None):  # stands in for PyBullet's
        filmed.update(formation=formation.name, postures=postures, world=world.name)
        out.write_bytes(b"video")

    monkeypatch.setattr(render, "render_postures", film)
    out = tmp_path / "adapt"
    args = argparse.Namespace(repertoire=repertoire, formation="quadruped_tripod", blind=None,
                              external=False, trials=1, fresh=None, no_video=False,
                              out=out)  # fmt: skip
    assert adapt_command.run(args) == 0
    gait = read_postures(out / "gait.csv", 6)
    assert filmed["formation"] == "quadruped_tripod" and filmed["world"] == "flat"
    assert np.array_equal(filmed["postures"], gait)
    assert "<video" in (out / "report.html").read_text()


def test_train_goes_on_from_the_gait_found_and_refuses_another_bodys(repertoire, tmp_path):
    tripod = load_formation(resolve_formation("quadruped_tripod"))
    found = adapt(repertoire, tripod, tmp_path / "adapt", trials=2)
    # The body's own trial rules (the adaptation's), a tiny learner.
    (tmp_path / "tiny.yaml").write_text("workers: 1\nagent: {learning: {trials: 20}, "
                                        "genetic: {population: 6}}\n")  # fmt: skip
    run = tmp_path / "warm"
    result = run_cli(
        "train", "quadruped_tripod", "--sim", "memo", "--generations", "1", "--quiet",
        "--config", tmp_path / "tiny.yaml", "--warm-start", tmp_path / "adapt", "--out", run,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    record = json.loads((run / "warm_start.json").read_text())
    assert record["adapt_trials"] == len(found["trials"])
    assert record["handed_on_m"] == pytest.approx(found["distance_m"])  # the same trial again
    assert run_cli("report", run).returncode == 0
    assert "started from the adaptation" in (run / "report.html").read_text()
    other = run_cli("train", "quadruped", "--sim", "memo", "--warm-start", tmp_path / "adapt",
                    "--out", tmp_path / "other")  # fmt: skip
    assert other.returncode == 2 and "an adaptation of quadruped_tripod" in other.stderr
    assert not (tmp_path / "other").exists()


def test_a_body_with_no_joint_in_common_or_a_corrupt_repertoire_is_refused(repertoire, tmp_path):
    out = tmp_path / "adapt"
    result = run_cli("adapt", repertoire, "--formation", "snake5", "--out", out)
    assert result.returncode == 2 and len(result.stderr.splitlines()) == 1, result.stderr
    assert "no actuated joint in common" in result.stderr and not out.exists()
    result = run_cli("adapt", repertoire, "--blind", "snake5", "--out", out)
    assert result.returncode == 2 and "no actuated joint in common" in result.stderr
    assert not out.exists()
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "repertoire.npz").write_bytes(b"junk")
    (broken / "repertoire.json").write_text(json.dumps({"joints": []}))
    result = run_cli("adapt", broken, "--formation", "quadruped_tripod", "--out", out)
    assert result.returncode == 2 and "corrupt repertoire" in result.stderr and not out.exists()
