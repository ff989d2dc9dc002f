"""The driver of many runs: a job finished before is counted, reported and not run again."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from qdsega.driver import run_jobs


@dataclass(frozen=True)
class _Marker:
    """A job that leaves a file behind when it runs."""

    folder: Path
    name: str
    finished: bool

    def kept(self) -> bool:
        return self.finished

    def __call__(self) -> str | None:
        (self.folder / self.name).write_text("ran", encoding="utf-8")
        return None


def test_finished_jobs_are_reported_and_not_run(tmp_path: Path) -> None:
    jobs = [_Marker(tmp_path, f"job{index}", finished=True) for index in range(3)]
    reported: list[str] = []

    errors = run_jobs(jobs, processes=2, report=lambda job, error: reported.append(job.name))

    assert errors == [None, None, None]
    assert sorted(reported) == ["job0", "job1", "job2"]
    assert list(tmp_path.iterdir()) == []  # no job ran
