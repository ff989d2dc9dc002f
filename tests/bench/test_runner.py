"""The benchmark continues where it stopped: a finished run is kept, a run made under other
settings (or before keys) runs again, and runs go seed by seed."""

from __future__ import annotations

import dataclasses

from qdsega.bench import runner
from qdsega.bench.curve import Curve
from qdsega.bench.runs import BenchRun, bench_runs
from qdsega.bench.tasks import QUICK

MSM, SNAKE = QUICK
CURVE = Curve.of([(10, 0.1, 1.0)])


def test_runs_go_seed_by_seed_every_method_first():
    two = dataclasses.replace(MSM, seeds=2, methods=("qdsega", "cma-cpg"))
    one = dataclasses.replace(SNAKE, seeds=1, methods=("qdsega",))
    names = [(run.task.name, run.name) for run in bench_runs([two, one])]
    assert names == [
        ("legged12-msm", "qdsega-seed0"),
        ("legged12-msm", "cma-cpg-seed0"),
        ("snake5-pybullet", "qdsega-seed0"),
        ("legged12-msm", "qdsega-seed1"),
        ("legged12-msm", "cma-cpg-seed1"),
    ]


def test_a_run_depends_on_its_settings_not_on_the_reports():
    run = BenchRun(MSM, "qdsega", 0)
    assert run.key() == BenchRun(dataclasses.replace(MSM, seeds=9, forced="x"), "qdsega", 0).key()
    for other in (
        BenchRun(MSM, "qdsega", 1),
        BenchRun(MSM, "cma-cpg", 0),
        BenchRun(dataclasses.replace(MSM, budget_steps=MSM.budget_steps + 1), "qdsega", 0),
        BenchRun(dataclasses.replace(MSM, trials=7), "qdsega", 0),
    ):
        assert other.key() != run.key()


def test_only_a_result_of_the_same_key_is_kept(tmp_path, monkeypatch):
    run = BenchRun(MSM, "qdsega", 0)
    played = []

    def method(task, seed, folder):
        played.append(seed)
        return CURVE

    monkeypatch.setitem(runner.METHODS, "qdsega", method)
    file = run.result(tmp_path)
    file.parent.mkdir(parents=True)
    file.write_text('{"steps": [1], "distance_m": [9.0], "wall_s": [1.0]}\n')  # before keys
    stale = BenchRun(dataclasses.replace(MSM, budget_steps=1), "qdsega", 0)
    assert runner.load_curves([run], tmp_path) == {}
    job = runner.BenchJob(run, tmp_path)
    assert not job.kept()
    for _ in range(2):
        assert job() is None
    assert job.kept() and played == [0]  # run once, then kept
    assert runner.load_curves([run], tmp_path)[run].distance_m.tolist() == [0.1]
    assert runner.load_curves([stale], tmp_path) == {}


def test_a_work_folder_of_other_settings_is_emptied_and_one_of_the_same_kept(tmp_path, monkeypatch):
    run = BenchRun(MSM, "qdsega", 0)
    seen = []

    def method(task, seed, folder):
        seen.append(sorted(path.name for path in folder.iterdir()))
        (folder / "left").write_text("a run's work")
        raise RuntimeError("killed")

    monkeypatch.setitem(runner.METHODS, "qdsega", method)
    folder = run.folder(tmp_path)
    folder.mkdir(parents=True)
    (folder / "old").write_text("a run of before keys")
    job = runner.BenchJob(run, tmp_path)
    assert "killed" in job() and "killed" in job()
    assert seen == [["key"], ["key", "left"]]  # emptied, then kept for the same key


def test_a_report_of_the_runs_finished_so_far_runs_nothing(tmp_path):
    run = BenchRun(MSM, "qdsega", 0)
    run.result(tmp_path).parent.mkdir(parents=True)
    CURVE.save(run.result(tmp_path), key=run.key())
    file, errors = runner.run_bench(
        QUICK, tmp_path, jobs=1, command="qdsega bench", report_only=True, log=lambda line: None
    )
    report = file.read_text()
    assert errors == [] and "| qdsega | 1 of 1 |" in report
    assert "## snake5-pybullet\n\nNo run of this task has finished yet." in report
    assert sorted(path.name for path in (tmp_path / "results").rglob("*.json")) == [
        "qdsega-seed0.json"
    ]  # nothing ran
