"""The driver of many runs: a job finished before is counted, reported and not run again; a
job whose driver is killed ends, however the driver was started."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

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


@dataclass(frozen=True)
class _Endless:
    """A job that says its process id, then never ends by itself."""

    folder: Path

    def kept(self) -> bool:
        return False

    def __call__(self) -> str | None:
        (self.folder / "pid").write_text(str(os.getpid()), encoding="utf-8")
        while True:
            time.sleep(0.05)


DRIVER = (
    "import sys; from pathlib import Path; from test_driver import _Endless; "
    "from qdsega.driver import run_jobs; run_jobs([_Endless(Path(sys.argv[1]))])"
)


def _running(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0]
    except FileNotFoundError:
        return False
    return state != "Z"  # a zombie has ended; only its parent has not reaped it


def test_a_job_ends_when_its_driver_is_killed_even_started_with_sigint_ignored(
    tmp_path: Path,
) -> None:
    """A background job of a script starts with SIGINT ignored (as ``nohup qdsega bench &``);
    a driver started in the foreground is the sweep's test."""
    tests = str(Path(__file__).parent)
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([tests, *sys.path])}
    driver = subprocess.Popen(
        [sys.executable, "-c", DRIVER, str(tmp_path)],
        env=environment,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),
    )
    pid = tmp_path / "pid"
    deadline = time.monotonic() + 60
    while not pid.is_file():
        assert driver.poll() is None and time.monotonic() < deadline, "the job did not start"
        time.sleep(0.05)
    driver.kill()  # the driver alone: its job's process is orphaned
    driver.wait()
    job = int(pid.read_text())
    deadline = time.monotonic() + 15
    while _running(job):
        if time.monotonic() > deadline:
            os.kill(job, signal.SIGKILL)
            pytest.fail("the job went on after its driver was killed")
        time.sleep(0.1)
