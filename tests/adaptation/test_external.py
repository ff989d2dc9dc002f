"""The search ask/tell, and on a robot (``--external``): it asks for one gait until told how far
it went and follows the distances told; a robot is handed each gait as joint angles over time
and answers with a file; a rerun goes on from the folder, asking for no finished trial again;
an answer or a folder it cannot go on from is one line, exit 2."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from helpers import BIPED, run_cli

from qdsega.adaptation import trajectory
from qdsega.adaptation.adapt import Adaptation, MappedRepertoire
from qdsega.adaptation.external import external_step
from qdsega.adaptation.hidden_body import HiddenBody
from qdsega.adaptation.repertoire import load_repertoire
from qdsega.adaptation.trajectory import JointTrajectory
from qdsega.description import World, load_formation, resolve_formation
from qdsega.description.shipped import UNITS_DIR
from qdsega.errors import FormationError
from qdsega.training.joint_mapping import JointMapping


def three_gaits() -> MappedRepertoire:
    """Two gaits alike (the first the farthest on the intact body) and one unlike them."""
    quadruped = load_formation(resolve_formation("quadruped"))
    return MappedRepertoire(
        path=Path("repertoire"),
        record={"formation": "quadruped"},
        changed=quadruped,
        world=World(),
        mapping=JointMapping.between(quadruped, quadruped),
        cells=np.array([3, 5, 9]),
        gaits=[np.full((2, 8), k % 2) for k in range(3)],
        prior=np.array([1.0, 0.9, 0.2]),
        descriptors=np.array([[0.1, 0.1], [0.15, 0.1], [0.9, 0.9]]),
    )


def test_the_search_asks_for_one_gait_until_it_is_told_how_far_it_went():
    search = Adaptation(repertoire=three_gaits(), trials=3)
    first = search.ask()
    assert first is search.ask() and (first.index, first.cell, first.predicted_m) == (0, 3, 1.0)
    search.tell(0.4, failure="fell", wall_s=1.0)
    with pytest.raises(ValueError, match="tell needs a gait asked for"):
        search.tell(0.4, failure=None, wall_s=2.0)
    assert search.played == [{"cell": 3, "predicted_m": 1.0, "intact_m": 1.0, "distance_m": 0.4,
                               "failure": "fell", "wall_s": 1.0}]  # fmt: skip


def test_the_search_follows_the_distances_told():
    far = Adaptation(repertoire=three_gaits(), trials=3)
    far.ask()
    far.tell(5.0, failure=None, wall_s=0.0)  # beyond every gait's prior: nothing left to try
    assert far.ask() is None
    assert far.outcome()["stopped"] == "no untried gait was predicted to beat the best trial"
    poor = Adaptation(repertoire=three_gaits(), trials=3)
    poor.ask()
    poor.tell(0.0, failure=None, wall_s=0.0)  # its neighbour falls with it: the other gait next
    assert poor.ask().index == 2
    poor.tell(0.3, failure=None, wall_s=0.0)
    outcome = poor.outcome()
    assert (outcome["distance_m"], outcome["trial_found"], outcome["cell"]) == (0.3, 2, 9)
    assert poor.best().index == 2


def robot(gait: Path) -> float:
    """A made-up robot: how far a gait goes is a fixed function of the angles sent to it."""
    played = JointTrajectory.read(gait)
    return round(float(np.mean(played.angles_rad[:, 0]) - np.mean(played.angles_rad[:, 5])), 6)


@pytest.mark.slow  # the repertoire fixture: exact physics, seconds
def test_a_robot_is_handed_each_gait_as_joint_angles_and_its_distances_steer_the_search(
    quadruped_repertoire, tmp_path
):
    out = tmp_path / "robot"
    told = []
    while True:
        result = run_cli("adapt", quadruped_repertoire, "--external", "--trials", "4", "--out", out)
        assert result.returncode == 0, result.stderr
        if (out / "adapt.json").is_file():
            break
        gait = out / "trials" / f"{len(told) + 1:03d}.csv"
        assert result.stdout.startswith(f"trial {len(told) + 1}: play {gait}, then write the")
        told.append(robot(gait))
        (out / "trials" / f"{len(told):03d}.result").write_text(f"{told[-1]} a note\n")
    facts = json.loads((out / "external.json").read_text())
    quadruped = load_formation(resolve_formation("quadruped"))
    assert facts["joints"] == [j.name for j in quadruped.joints]
    assert facts["rest_rad"] == list(quadruped.posture_rad(quadruped.rest_levels()))
    found = json.loads((out / "adapt.json").read_text())
    assert found["mode"] == "external" and [t["distance_m"] for t in found["trials"]] == told
    assert {t["failure"] for t in found["trials"]} == {"a note"}
    # the first gait, as the lower agent commands it: the elite's cycle at the body's step
    archive, _ = load_repertoire(quadruped_repertoire)
    cycle = archive.gait(found["trials"][0]["cell"])
    commands = np.resize(cycle, (facts["commands"], 8))
    first = JointTrajectory.read(out / "trials" / "001.csv")
    assert first.joints == tuple(facts["joints"])
    assert np.allclose(first.times_s, np.arange(facts["commands"] + 1) * facts["step_s"])
    assert np.array_equal(first.commands_rad, [quadruped.posture_rad(p) for p in commands])
    assert np.array_equal(first.angles_rad[-1], first.angles_rad[-2])  # held to the end
    # the gaits asked for are the ones the search asks for, told the same distances
    search = Adaptation(repertoire=MappedRepertoire.unmapped(quadruped_repertoire), trials=4)
    for distance in told:
        assert search.ask() is not None
        search.tell(distance, failure=None, wall_s=0.0)
    assert search.ask() is None and [t["cell"] for t in found["trials"]] == [
        t["cell"] for t in search.played
    ]
    assert found["distance_m"] == max(told) and np.array_equal(found["gait"], search.best().cycle)
    assert {p.name for p in out.iterdir()} == {"adapt.json", "adaptation_curve.png",
                                               "external.json", "gait.csv", "report.html",
                                               "trials"}  # fmt: skip  # the robot: no film
    assert "the robot, the intact body&#x27;s gaits" in (out / "report.html").read_text()


@pytest.mark.slow  # the repertoire fixture: exact physics, seconds
def test_a_rerun_goes_on_from_the_folder_and_asks_for_no_finished_trial_again(
    quadruped_repertoire, tmp_path, monkeypatch
):
    out, trials = tmp_path / "robot", tmp_path / "robot" / "trials"
    assert external_step(quadruped_repertoire, out, trials=2).trial == 1
    (trials / "001.result").write_text("-0.5\n")  # below every gait's prior: it goes on
    assert external_step(quadruped_repertoire, out).trial == 2  # the folder's budget
    finished = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in trials.iterdir()}
    assert external_step(quadruped_repertoire, out).trial == 2  # no answer yet: asked again
    assert sorted(p.name for p in trials.iterdir()) == ["001.csv", "001.result", "002.csv"]
    (trials / "002.result").write_text("-0.5\n")
    assert external_step(quadruped_repertoire, out).result["stopped"] == "after 2 trials"

    def killed(self, path):
        path.with_name(".partial").write_text("half a gait")
        raise KeyboardInterrupt

    monkeypatch.setattr(trajectory.JointTrajectory, "write", killed)
    with pytest.raises(KeyboardInterrupt):  # a larger budget, killed as it writes the gait
        external_step(quadruped_repertoire, out, trials=3)
    monkeypatch.undo()
    step = external_step(quadruped_repertoire, out)
    assert step.trial == 3 and step.gait.is_file() and not step.answer.exists()
    assert not (out / "adapt.json").exists()  # not done after all
    for name, (content, mtime) in finished.items():
        assert ((trials / name).read_bytes(), (trials / name).stat().st_mtime_ns) == (
            content,
            mtime,
        )
    (trials / "003.result").write_text("-0.2\n")
    done = external_step(quadruped_repertoire, out).result
    assert [t["distance_m"] for t in done["trials"]] == [-0.5, -0.5, -0.2]
    assert done["trial_found"] == 3 and (out / "adapt.json").is_file()


@pytest.mark.slow  # the repertoire fixture: exact physics, seconds
def test_an_answer_or_a_folder_it_cannot_go_on_from_is_one_line(quadruped_repertoire, tmp_path):
    out = tmp_path / "robot"
    args = ("adapt", quadruped_repertoire, "--external", "--out", out)
    assert run_cli(*args).returncode == 0
    (out / "trials" / "001.result").write_text("fell over\n")
    result = run_cli(*args)
    assert result.returncode == 2 and len(result.stderr.splitlines()) == 1, result.stderr
    assert "001.result: expected the distance the robot walked (m), a number, got 'fell'" in (
        result.stderr
    )
    (out / "trials" / "001.result").write_text("0.0\n")
    assert run_cli(*args).returncode == 0
    shutil.copy(out / "trials" / "001.csv", out / "trials" / "002.csv")  # not what it asks for
    result = run_cli(*args)
    assert result.returncode == 2 and "002.csv: is not the gait the search asks for" in (
        result.stderr
    )
    other = tmp_path / "mapped"
    other.mkdir()
    (other / "adapt.json").write_text("{}")
    result = run_cli("adapt", quadruped_repertoire, "--external", "--out", other)
    assert result.returncode == 2 and "holds an adaptation played in exact physics" in (
        result.stderr
    )


def test_a_hidden_body_too_slow_for_the_commands_step_is_refused(tmp_path):
    slow = tmp_path / "units" / "slow_servo"
    shutil.copytree(UNITS_DIR / "servo", slow)
    unit = slow / "unit.yaml"
    unit.write_text(unit.read_text().replace("velocity_rad_s: 5.8", "velocity_rad_s: 0.5"))
    worn = BIPED.replace("{name: lift, unit: servo", "{name: lift, unit: slow_servo")
    (tmp_path / "worn.yaml").write_text("units_dir: units\n" + worn)
    body = load_formation(tmp_path / "worn.yaml")
    with pytest.raises(FormationError, match=r"lift_joint needs 1\.40 s to cross its levels"):
        HiddenBody(body=body, world=World(), step_s=0.5, commands=30)
