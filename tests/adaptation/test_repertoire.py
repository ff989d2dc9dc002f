"""A repertoire build: gaits that walk in exact physics fill the archive; the same seed gives
the same archive, and so does a build stopped and continued; bad input is one line, exit 2,
nothing written."""

import csv
import json
import shutil
import signal

import numpy as np
import pytest
from helpers import run_cli, start_cli, stop_when

from qdsega.adaptation.repertoire import (
    RepertoireSettings,
    build_repertoire,
    load_repertoire,
)
from qdsega.description import load_formation, resolve_formation
from qdsega.errors import RunFolderError
from qdsega.locomotion.exact_trials import ExactTrials
from qdsega.training.config import resolve_config

pytestmark = pytest.mark.slow  # exact physics: seconds a build

QUADRUPED = load_formation(resolve_formation("quadruped"))
SHORT = {"sim": "memo", "task": {"trial_steps": 10}}  # a third of the preset's trial: faster
RULES = resolve_config(overrides=SHORT, formation=QUADRUPED).rules()


def _build(out, evaluations):
    settings = RepertoireSettings(evaluations=evaluations, cells=16, batch=16, initial=16)
    return build_repertoire(QUADRUPED, out, rules=RULES, settings=settings, workers=1)


def test_a_build_stopped_and_continued_gives_the_same_archive(tmp_path):
    whole = _build(tmp_path / "whole", 32)
    assert whole["evaluations_done"] == 32 and whole["filled"] >= 1
    archive, record = load_repertoire(tmp_path / "whole")
    assert record["descriptor_names"] == ["L1", "L2", "R1", "R2"]
    best = archive.gait(archive.best())
    assert np.all(best >= 0) and archive.fitness[archive.best()] == whole["best_m"]
    _build(tmp_path / "parts", 16)
    _build(tmp_path / "parts", 32)  # as after a kill: it goes on from its last batch
    again, _ = load_repertoire(tmp_path / "parts")
    for name, value in archive.state().items():
        assert np.array_equal(value, again.state()[name], equal_nan=True), name


def test_the_command_killed_and_run_again_builds_the_same_archive_and_draws_it(
    quadruped_repertoire, tmp_path
):
    # the settings of quadruped_repertoire (built by the library, the whole to compare with)
    args = ("repertoire", "quadruped", "--fill", "pybullet", "--evaluations", "40", "--cells", "8",
            "--workers", "1")  # fmt: skip
    killed = tmp_path / "killed"
    process = start_cli(*args, "--out", killed)
    stop_when(process, (killed / "repertoire.npz").is_file, signal.SIGKILL)  # after a batch
    process.communicate(timeout=60)
    result = run_cli(*args, "--out", killed)
    assert result.returncode == 0, result.stderr
    record = json.loads((killed / "repertoire.json").read_text())
    assert record["evaluations_done"] == 40
    assert f"{record['filled']} cells of 8 filled" in result.stdout
    assert (killed / "archive.png").is_file() == (record["filled"] > 0)
    assert (killed / "formation.json").is_file()  # its own copy of the body, for adapt
    for name, value in load_repertoire(quadruped_repertoire)[0].state().items():
        assert np.array_equal(value, load_repertoire(killed)[0].state()[name], equal_nan=True)


def test_an_msm_build_keeps_its_elites_that_walk_in_exact_physics_and_resumes(tmp_path):
    settings = RepertoireSettings(fill="msm", evaluations=3000, cells=16, batch=4, initial=200)

    def build(out, stop_after=None):
        class Line:  # a progress line that stops the build after ``stop_after`` exact batches
            def __init__(self, label, total, initial=0):
                self.label, self.updates = label, 0

            def update(self, done, text):
                self.updates += self.label == "repertoire"
                if stop_after is not None and self.updates >= stop_after:
                    raise KeyboardInterrupt

            def close(self):
                pass

        return build_repertoire(QUADRUPED, out, rules=RULES, settings=settings, workers=1,
                                progress=Line)  # fmt: skip

    whole = build(tmp_path / "whole")
    archive, record = load_repertoire(tmp_path / "whole")
    assert record["descriptor"] == "commanded duty factor per leg (filled in the MSM)"
    assert 1 <= whole["filled"] <= whole["evaluations_done"] <= 16  # one exact trial an elite
    with ExactTrials(formation=QUADRUPED, rules=RULES, workers=1) as exact:
        for cell in archive.filled:
            (trial,) = exact.cycles([archive.gait(int(cell))], steps=10)
            assert not trial.rollout.failed and trial.rollout.distance_m == archive.fitness[cell]
    with pytest.raises(KeyboardInterrupt):
        build(tmp_path / "parts", stop_after=1)
    assert load_repertoire(tmp_path / "parts")[1]["evaluations_done"] == 4
    build(tmp_path / "parts")  # as after a kill: it goes on from its last batch
    for name, value in archive.state().items():
        assert np.array_equal(value, load_repertoire(tmp_path / "parts")[0].state()[name],
                              equal_nan=True), name  # fmt: skip


def test_another_body_or_a_corrupt_archive_is_refused_in_one_line(tmp_path):
    out = tmp_path / "rep"
    _build(out, 16)
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    result = run_cli("repertoire", "hexapod", "--evaluations", "16", "--out", out)
    assert result.returncode == 2 and len(result.stderr.splitlines()) == 1, result.stderr
    assert "another body" in result.stderr
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before  # no write
    snake = run_cli("repertoire", "snake5", "--fill", "msm", "--out", tmp_path / "snake")
    assert snake.returncode == 2 and len(snake.stderr.splitlines()) == 1, snake.stderr
    assert "needs a legged formation" in snake.stderr and not (tmp_path / "snake").exists()
    broken = tmp_path / "broken"
    shutil.copytree(out, broken)
    (broken / "repertoire.npz").write_bytes(b"not an archive")
    with pytest.raises(RunFolderError, match="corrupt repertoire"):
        load_repertoire(broken)
    record = json.loads((out / "repertoire.json").read_text())
    (broken / "repertoire.json").write_text(json.dumps({**record, "joints": ["one"]}))
    shutil.copy(out / "repertoire.npz", broken / "repertoire.npz")
    with pytest.raises(RunFolderError, match="do not fit"):
        load_repertoire(broken)
    old = tmp_path / "old"  # built before the descriptor was measured
    shutil.copytree(out, old)
    commanded = {**record, "descriptor": "duty factor per leg"}
    (old / "repertoire.json").write_text(json.dumps(commanded))
    kept = {p: p.read_bytes() for p in old.rglob("*") if p.is_file()}
    with pytest.raises(RunFolderError, match="another body, world, descriptor"):
        _build(old, 32)
    assert {p: p.read_bytes() for p in old.rglob("*") if p.is_file()} == kept


def test_a_run_seeds_the_repertoire_with_its_verified_gaits_and_export_writes_its_elites(
    tiny_run, tmp_path
):
    out = tmp_path / "rep"
    result = run_cli("repertoire", tiny_run, "--evaluations", "3", "--cells", "4",
                     "--workers", "1", "--out", out, "--export")  # fmt: skip
    assert result.returncode == 0, result.stderr
    record = json.loads((out / "repertoire.json").read_text())
    assert record["formation"] == "snake5" and record["trial_steps"] == 4  # the run's rules
    assert record["seeds"]["run"] == str(tiny_run.resolve()) and record["seeds"]["gaits"] >= 1
    summary = json.loads((tiny_run / "summary.json").read_text())
    assert record["best_m"] >= summary["distance_m"] - 1e-9  # its verified gait, played again
    archive, _ = load_repertoire(out)
    assert record["qd_score"] == archive.qd_score and record["qd_offset_m"] == -10.0
    assert f"QD-score {record['qd_score']:.2f} (offset -10 m)" in result.stdout
    with (out / "elites.csv").open(newline="") as stream:
        rows = list(csv.DictReader(stream))
    assert len(rows) == record["filled"] >= 1
    assert [float(r["distance_m"]) for r in rows] == sorted(archive.fitness[archive.filled])[::-1]
    assert {"descriptor_turn", "descriptor_drift"} <= set(rows[0])  # snake5: no legs
    again = run_cli("repertoire", tiny_run, "--world", "ice", "--out", tmp_path / "other")
    assert again.returncode == 2 and "the run's world" in again.stderr
    assert not (tmp_path / "other").exists()

    (out / "elites.csv").unlink()  # exported again from the folder, nothing built
    built = {p: p.read_bytes() for p in out.rglob("*.npz")}
    exported = run_cli("repertoire", out, "--export")
    assert exported.returncode == 0, exported.stderr
    assert f"{out / 'elites.csv'}" in exported.stdout and "QD-score" in exported.stdout
    with (out / "elites.csv").open(newline="") as stream:
        assert list(csv.DictReader(stream)) == rows
    assert {p: p.read_bytes() for p in out.rglob("*.npz")} == built
    for args in ((), ("--export", "--cells", "8")):
        refused = run_cli("repertoire", out, *args)
        assert refused.returncode == 2 and len(refused.stderr.splitlines()) == 1, args
