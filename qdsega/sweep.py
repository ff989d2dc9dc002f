"""A sweep: a grid of trainings, each into its own run folder, evaluated, then one table.

A grid file (``GRID.yaml``)::

    formations: [snake5, quadruped]   # shipped names or files (relative to GRID.yaml)
    worlds: [flat, stairs]            # optional: shipped names or files; default the plane
    seeds: [0, 1, 2]                  # default [0]
    sim: memo                         # default memo
    presets: [memo-legged]            # default: each formation's own (default_preset)
    configs:                          # named settings over the preset (keys as in config.yaml)
      default: {}
      short: {agent: {genetic: {generations: 5}}}
    reference_trials: 600             # qdsega evaluate's CMA-ES budget (trials; 0: none)

Every combination formation x preset x config x seed is one run, trained (or resumed, or
kept: :func:`qdsega.training.run.train_or_resume`) into ``OUT/FORMATION-PRESET-CONFIG-seedS``
and evaluated, each in its own process: a run that fails is reported with its error, and the
others go on. A finished, evaluated run is kept, an unfinished one resumed, so running a
sweep again finishes what a crash left. The table (``OUT/sweep.csv``, ``OUT/sweep.md``) holds
only what the runs' files say, so the same grid gives the same table wherever it ran.

Runs go to local processes (``jobs`` at a time), or with ``ray`` to Ray tasks (one CPU each) on
this machine or a cluster, whose nodes need qdsega installed and ``OUT`` on a shared file system.
"""

from __future__ import annotations

import csv
import io
import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from qdsega.description import (
    Formation,
    World,
    load_formation,
    load_world,
    named_world,
    resolve_formation,
)
from qdsega.driver import error_line, run_jobs
from qdsega.errors import ConfigError, WorldError
from qdsega.folder_names import default_folder
from qdsega.progress import ProgressFactory
from qdsega.training.config import SIMULATORS, default_preset, resolve_config
from qdsega.training.run import TrainingInterrupted, train_or_resume
from qdsega.training.run_folder import RunFolder
from qdsega.yaml_reader import YamlDocument, load_yaml

GRID_KEYS = ("formations", "worlds", "seeds", "sim", "presets", "configs", "reference_trials")
"""The keys a grid file may have."""
TABLE_COLUMNS = (
    "run", "formation", "world", "preset", "config", "seed", "status", "distance_m",
    "memo_prediction_m", "ratio", "reference", "reference_m", "generations", "sim_steps",
    "error",
)  # fmt: skip
"""Columns of the sweep table: distances in metres; ``sim_steps`` upper-agent steps simulated
(memo transitions measured and exact trials' commands); ``ratio`` exact distance over the best
reference's; ``error`` the failed command's last line."""


@dataclass(frozen=True)
class SweepRun:
    """One run of a sweep.

    Attributes:
        name: its folder name, ``FORMATION[-WORLD]-PRESET-CONFIG-seedS`` (the world where the
            grid names worlds).
        formation: the formation file.
        world: the world file, or None for the flat plane.
        sim: the simulator (``msm``, ``memo``, ``pybullet``).
        preset: the preset it starts from.
        config: the name of its settings in the grid's ``configs``.
        config_file: those settings as a YAML file (``qdsega train --config``).
        seed: its seed.
        reference_trials: ``qdsega evaluate --reference-trials`` (None: evaluate's default).
    """

    name: str
    formation: Path
    world: Path | None
    sim: str
    preset: str
    config: str
    config_file: Path
    seed: int
    reference_trials: int | None


def read_grid(file: Path, out: Path) -> list[SweepRun]:
    """The runs of the grid ``file``, with their settings written to ``OUT/configs/``.

    Raises:
        ConfigError: unreadable grid, unknown key, a formation that does not load, a bad
            preset or setting (all checked before anything runs).
    """
    document = load_yaml(Path(file), error_type=ConfigError)
    grid = document.data
    if not isinstance(grid, dict) or "formations" not in grid:
        raise document.error((), "a grid is a mapping with at least formations: [...]")
    unknown = sorted(set(grid) - set(GRID_KEYS))
    if unknown:
        message = f"unknown key {unknown[0]!r} (known: {', '.join(GRID_KEYS)})"
        raise document.error((unknown[0],), message)
    sim = grid.get("sim", "memo")
    if sim not in SIMULATORS:
        raise document.error(("sim",), f"sim must be one of {', '.join(SIMULATORS)}")
    seeds = _list_of(grid.get("seeds", [0]), int, document, "seeds")
    presets = _list_of(grid.get("presets", [None]), str, document, "presets", optional=True)
    configs = grid.get("configs", {"default": {}})
    if not isinstance(configs, dict) or not configs:
        raise document.error(("configs",), "expected a mapping of names to settings")
    trials = grid.get("reference_trials")
    if trials is not None and (isinstance(trials, bool) or not isinstance(trials, int)):
        raise document.error(("reference_trials",), "expected an integer")
    formations = []
    for given in _list_of(grid["formations"], str, document, "formations"):
        path = Path(given)
        if not path.is_absolute() and (file.parent / path).is_file():
            path = file.parent / path
        path = resolve_formation(path)
        formations.append((path, load_formation(path)))
    settings_of = {}
    for name, settings in configs.items():
        if not str(name).replace("_", "").replace("-", "").isalnum():
            message = f"config name {name!r}: letters, digits, - and _ only (it names folders)"
            raise document.error(("configs", name), message)
        if not isinstance(settings or {}, dict):
            raise document.error(("configs", name), "expected a mapping")
        settings_of[str(name)] = settings or {}
        axes = sorted({"preset", "sim", "seed"} & set(settings_of[str(name)]))
        if axes:
            message = f"{axes[0]} is the grid's to set (presets, sim, seeds), not a config's"
            raise document.error(("configs", name), message)
        for preset in presets:
            overrides = {**settings_of[str(name)], "sim": sim}
            try:
                resolve_config(preset=preset or "paper-legged", overrides=overrides)
            except ConfigError as exc:
                raise document.error(("configs", name), str(exc)) from None
    worlds = _worlds(document, grid, sim)
    try:
        return grid_runs(formations, worlds, presets, settings_of, seeds, sim, trials, out)
    except ConfigError as exc:
        raise ConfigError(exc.message, file=file) from None


def grid_runs(
    formations: Sequence[tuple[Path, Formation]],
    worlds: Sequence[World | None],
    presets: Sequence[str | None],
    configs: dict[str, dict[str, Any]],
    seeds: Sequence[int],
    sim: str,
    reference_trials: int | None,
    out: Path,
) -> list[SweepRun]:
    """Every run of the grid formations x worlds x presets x configs x seeds (a preset None:
    each formation's own), with each config's settings written to ``OUT/configs/NAME.yaml``;
    everything is read and checked already.

    Raises:
        ConfigError: two formations share a file name (their runs would share a folder).
    """
    runs = []
    for (path, formation), world, preset, name, seed in itertools.product(
        formations, worlds, presets, configs, seeds
    ):
        preset = preset or default_preset(formation, sim)
        where = None if world is None or world.file is None else world.file.resolve()
        label = default_folder(path.stem, world=where, settings=[preset, name], seed=seed).name
        config_file = out / "configs" / f"{name}.yaml"
        runs.append(
            SweepRun(
                label, path.resolve(), where, sim, preset, name, config_file, seed, reference_trials
            )
        )
    names = [r.name for r in runs]
    if len(set(names)) != len(names):
        raise ConfigError("two formations share a file name: their runs would share a folder")
    for name, settings in configs.items():  # written once everything is checked
        (out / "configs").mkdir(parents=True, exist_ok=True)
        text = yaml.safe_dump(settings, sort_keys=True)
        (out / "configs" / f"{name}.yaml").write_text(text, encoding="utf-8")
    return runs


def _worlds(document: YamlDocument, grid: dict[str, Any], sim: str) -> list[World | None]:
    """The grid's worlds, each read and checked now (None: the grid names none, the plane)."""
    if "worlds" not in grid:
        return [None]
    worlds: list[World | None] = []
    for i, given in enumerate(_list_of(grid["worlds"], str, document, "worlds")):
        path = Path(given)
        if not path.is_absolute() and (document.file.parent / path).is_file():
            path = document.file.parent / path
        try:
            worlds.append(named_world(path))
        except WorldError as exc:
            raise document.error(("worlds", i), str(exc)) from None
    if sim == "msm" and any(w is not None and not w.is_flat for w in worlds):
        raise document.error(("worlds",), "the MSM knows no terrain: use sim: memo")
    return worlds


def _list_of(
    value: Any, kind: type, document: YamlDocument, key: str, *, optional: bool = False
) -> list[Any]:
    items = value if isinstance(value, list) else [value]
    if not items or not all(
        (isinstance(v, kind) and not isinstance(v, bool)) or (optional and v is None) for v in items
    ):
        raise document.error((key,), f"expected a list of {kind.__name__}")
    return items


@dataclass(frozen=True)
class SweepJob:
    """A sweep run as the driver's job: train (or resume, or keep) it in ``folder``, then
    evaluate it."""

    run: SweepRun
    folder: Path

    @property
    def name(self) -> str:
        return self.run.name

    def kept(self) -> bool:
        return (self.folder / RunFolder.EVALUATION).is_file()

    def __call__(self) -> str | None:
        return _train_and_evaluate(self.run, self.folder)


def _train_and_evaluate(run: SweepRun, folder: Path) -> str | None:
    """None, or the step that failed and its error."""
    from qdsega.analysis.evaluation import evaluate_run  # starts PyBullet: in the run's process

    step = "train"
    try:
        overrides = {"sim": run.sim, "seed": run.seed}
        config = resolve_config(preset=run.preset, file=run.config_file, overrides=overrides)
        world = None if run.world is None else load_world(run.world)
        train_or_resume(run.formation, config, folder, world=world)
        if RunFolder(folder).read_evaluation() is None:
            step = "evaluate"
            if run.reference_trials is None:
                evaluate_run(folder)
            else:
                evaluate_run(folder, reference_trials=run.reference_trials)
    except TrainingInterrupted:
        raise
    except Exception as exc:  # a failed run is a row of the table; the others go on
        return f"{step}: {error_line(exc)}"
    return None


def run_sweep(
    runs: Sequence[SweepRun],
    out: Path,
    *,
    jobs: int = 1,
    ray: str | None = None,
    report: Callable[[SweepRun, str], None] = lambda run, status: None,
    progress: ProgressFactory | None = None,
) -> list[dict[str, Any]]:
    """Run every run into ``OUT/NAME`` (:func:`qdsega.driver.run_jobs`: ``jobs`` at a time, or
    as Ray tasks when ``ray`` is ``local`` or an address); write and return the table's rows.
    ``report(run, status)`` is called as each run ends, with ``"ok"`` or the step that failed
    and its error; ``progress``: as the driver's."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    out = out.resolve()
    sweep_jobs = [SweepJob(run, out / run.name) for run in runs]
    errors = run_jobs(
        sweep_jobs,
        processes=jobs,
        ray=ray,
        label="sweep",
        report=lambda job, error: report(job.run, error or "ok"),
        progress=progress,
    )
    rows = [
        _row(job.run, job.folder, error or "ok")
        for job, error in zip(sweep_jobs, errors, strict=True)
    ]
    write_table(rows, out)
    return rows


def _row(run: SweepRun, folder: Path, status: str) -> dict[str, Any]:
    row: dict[str, Any] = dict.fromkeys(TABLE_COLUMNS)
    row.update(run=run.name, formation=run.formation.stem, preset=run.preset, config=run.config)
    row["world"] = "flat" if run.world is None else run.world.stem
    row["seed"] = run.seed
    if status != "ok":
        row.update(status="failed", error=status)
        return row
    summary, evaluation = RunFolder(folder).read_summary(), RunFolder(folder).read_evaluation()
    assert evaluation is not None, "a run reported ok was evaluated"
    row.update(
        status="ok",
        distance_m=evaluation["distance_m"],
        memo_prediction_m=evaluation["memo_prediction_m"],
        ratio=evaluation["ratio"],
        reference=evaluation["reference"]["kind"],
        reference_m=evaluation["reference"]["distance_m"],
        generations=summary["generations"],
        sim_steps=summary["sim_steps"],
    )
    return row


def write_table(rows: Sequence[dict[str, Any]], out: Path) -> None:
    """``OUT/sweep.csv`` (full precision) and ``OUT/sweep.md`` (4 decimals)."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, TABLE_COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    (out / "sweep.csv").write_text(buffer.getvalue(), encoding="utf-8")
    (out / "sweep.md").write_text(markdown_table(rows), encoding="utf-8")


def markdown_table(rows: Sequence[dict[str, Any]]) -> str:
    """The rows as a Markdown table (numbers to 4 decimals, empty cells for missing values)."""

    def cell(value: Any) -> str:
        if value is None:
            return ""
        if isinstance(value, float):
            return f"{value:.4f}"
        return str(value).replace("|", "/")

    lines = ["| " + " | ".join(TABLE_COLUMNS) + " |", "|" + "---|" * len(TABLE_COLUMNS)]
    lines += ["| " + " | ".join(cell(row[c]) for c in TABLE_COLUMNS) + " |" for row in rows]
    return "\n".join(lines) + "\n"
