"""Helpers shared by tests (import as ``from helpers import ...``)."""

from __future__ import annotations

import contextlib
import copy
import csv
import fcntl
import io
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from qdsega.description.shipped import ASSEMBLIES_DIR, UNITS_DIR, WORLDS_DIR

SHIPPED_FORMATIONS = sorted(ASSEMBLIES_DIR.glob("*.yaml"))
SHIPPED_WORLDS = sorted(WORLDS_DIR.glob("*.yaml"))
SHIPPED_UNITS = sorted(p for p in UNITS_DIR.iterdir() if p.is_dir() and p.name != "__pycache__")
TINY_TRAINING = """\
workers: 1
local_search: 1
agent:
  learning: {trials: 20}
  genetic: {population: 6}
task: {trial_steps: 4}
"""
"""A --config file for training runs a test can afford (seconds): one neighbour of the best
trial replayed a generation, not the default's ten."""

BIPED = """\
name: biped
friction: {lateral: 1.0, anisotropic: [1.0, 1.0, 1.0]}
light: {distance_m: 50.0}
templates:
  leg:
    leg: {swing: swing, lift: lift}
    units:
      - {name: swing, unit: servo, axis: yaw, levels_deg: [-15, 15]}
      - {name: lift, unit: servo, parent: swing, connector: back, axis: pitch,
         levels_deg: [-35, 5]}
units:
  - {name: body1, unit: hub}
  - {name: L1, template: leg, parent: body1, connector: left, side: left}
  - {name: R1, template: leg, parent: body1, connector: right, side: right,
     overrides: {swing: {levels_deg: [15, -15]}}}
"""
"""A hub with a leg on each side: five units, four joints."""


def run_cli(*args: str | Path, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``qdsega ARGS`` in this process (``cli.main``, as fast as a function call) and
    capture its text output."""
    argv = [str(a) for a in args]
    from qdsega.cli import main

    out, err = io.StringIO(), io.StringIO()
    here = Path.cwd()
    try:
        if cwd is not None:
            os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(argv)
            except SystemExit as exit:  # argparse's usage errors
                code = exit.code if isinstance(exit.code, int) else 2
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess(argv, code, out.getvalue(), err.getvalue())


def made_once(
    tmp_path_factory: pytest.TempPathFactory, name: str, make: Callable[[Path], None]
) -> Path:
    """The folder ``name`` that ``make(folder)`` fills, made once for all test processes (the
    first makes it, under a lock, the others wait and share it): what costs seconds is paid
    once however xdist spreads the tests that read it. Copy it before changing it."""
    shared = tmp_path_factory.getbasetemp()
    if "PYTEST_XDIST_WORKER" in os.environ:
        shared = shared.parent  # this session's folder, above each worker's own
    folder, done = shared / name, shared / f"{name}.done"
    with open(shared / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.is_file():
            shutil.rmtree(folder, ignore_errors=True)  # a process killed while it made it
            folder.mkdir()
            make(folder)
            done.touch()
    return folder


def save_result(result: subprocess.CompletedProcess[str], file: Path) -> None:
    """Keep what a command returned and printed, for :func:`load_result` in another process."""
    kept = {"returncode": result.returncode, "stdout": result.stdout, "stderr": result.stderr}
    file.write_text(json.dumps(kept))


def load_result(file: Path) -> subprocess.CompletedProcess[str]:
    """What :func:`save_result` kept, as the command's result."""
    kept = json.loads(file.read_text())
    return subprocess.CompletedProcess([], kept["returncode"], kept["stdout"], kept["stderr"])


def start_cli(*args: str | Path) -> subprocess.Popen[str]:
    """``qdsega ARGS`` in its own process group, with Ctrl-C's default action (as a
    terminal's foreground job), even where the tests themselves run with SIGINT ignored (a
    background job of a non-interactive shell, e.g. ``make test &``)."""
    return subprocess.Popen(
        [sys.executable, "-m", "qdsega.cli", *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def finished_generations(run: Path) -> int:
    metrics = run / "metrics.csv"
    return len(metrics.read_text().splitlines()) - 1 if metrics.is_file() else 0


def stop_after(process: subprocess.Popen[str], run: Path, generations: int, sig: int) -> None:
    """Send ``sig`` to the process group once ``generations`` are finished."""
    stop_when(process, lambda: finished_generations(run) >= generations, sig)


def stop_when(process: subprocess.Popen[str], ready: Callable[[], bool], sig: int) -> None:
    """Send ``sig`` to the process group as soon as ``ready()``."""
    deadline = time.monotonic() + 240
    while not ready():
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "training did not progress"
        time.sleep(0.005)
    os.killpg(process.pid, sig)


def metrics_without_wall_time(run: Path) -> list[dict[str, str]]:
    rows = list(csv.DictReader((run / "metrics.csv").open()))
    return [{k: v for k, v in row.items() if k != "wall_s"} for row in rows]


def assert_same_result(a: Path, b: Path, why: str = "") -> None:
    assert metrics_without_wall_time(a) == metrics_without_wall_time(b), why
    for name in ("policy.npz", "trajectories.npz"):
        with np.load(a / name) as x, np.load(b / name) as y:
            assert sorted(x) == sorted(y)
            for key in x:
                assert np.array_equal(x[key], y[key]), f"{name}:{key} {why}"
    sa, sb = (json.loads((r / "summary.json").read_text()) for r in (a, b))
    assert {**sa, "wall_s": None} == {**sb, "wall_s": None}, why
    if (a / "transitions.npz").is_file():
        with np.load(a / "transitions.npz") as x, np.load(b / "transitions.npz") as y:
            assert np.array_equal(x["pairs"], y["pairs"]), why
            assert np.array_equal(x["values"], y["values"]), why


# Mutants of YAML data (formations, worlds): one change each.
KeyPath = tuple[str | int, ...]
SCALAR_MUTATIONS = {
    "negative": lambda v: -v if isinstance(v, int | float) and v != 0 else -1,
    "huge": lambda v: 1.0e300,
    "huge-integer": lambda v: 10**400,
    "nan": lambda v: math.nan,
    "nonsense": lambda v: "zzz nonsense",
}


def _nodes(data: Any, path: KeyPath = ()) -> Iterator[tuple[KeyPath, Any]]:
    """Every node of plain YAML data with its path, parents first."""
    yield path, data
    if isinstance(data, dict | list):
        for key, value in data.items() if isinstance(data, dict) else enumerate(data):
            yield from _nodes(value, (*path, key))


def _mutated(data: Any, path: KeyPath, change: Any) -> Any:
    """A deep copy of ``data`` with ``change(node)`` applied to the node at ``path``."""
    mutant = copy.deepcopy(data)
    parent = mutant
    for key in path[:-1]:
        parent = parent[key]
    if not path:
        return change(mutant)
    parent[path[-1]] = change(parent[path[-1]])
    return mutant


def _without(container: dict | list, key: str | int) -> dict | list:
    container = copy.copy(container)
    del container[key]
    return container


def mutants(data: Any) -> Iterator[tuple[str, Any]]:
    """(label, mutant) pairs: every single-point mutation of ``data``."""
    for path, node in _nodes(data):
        where = ".".join(map(str, path)) or "(top)"
        if isinstance(node, dict):
            for key in node:
                yield f"{where}: -{key}", _mutated(data, path, lambda n, k=key: _without(n, k))
            yield f"{where}: +unknown", _mutated(data, path, lambda n: {**n, "colour": "red"})
        elif isinstance(node, list):
            for index in range(len(node)):
                yield (
                    f"{where}: -[{index}]",
                    _mutated(data, path, lambda n, i=index: _without(n, i)),
                )
        else:
            for label, change in SCALAR_MUTATIONS.items():
                yield f"{where}={label}", _mutated(data, path, change)
