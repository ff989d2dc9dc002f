"""Relearning after a change of body: the old policy on it, a fresh run, a warm-started run.

Usage: .venv/bin/python experiments/reconfiguration/reconfiguration_table.py [--seeds 0 1 2]
           [--grid runs/grid] [--out runs/reconfiguration] [--workers 2]
           [--changes NEW ...] [--config FILE.yaml]

For each change (a shipped formation and its changed version, ``CHANGES``) and seed: the old
formation's run in ``GRID`` (memo mode, the body's own preset: the run
``experiments/grid/grid.yaml`` makes, ``GRID/OLD-PRESET-default-seedS``, or
``GRID/OLD-seedS`` where only that folder exists, as the older grid scripts named it; trained
there if neither exists), the old policy replayed on the changed body
(:func:`qdsega.analysis.evaluation.evaluate_on`), a fresh run of the changed body
``OUT/fresh/NEW-seedS`` and one warm-started from the old run ``OUT/warm/NEW-seedS`` (same
preset and seed). A finished run is kept, an unfinished one resumed
(:func:`qdsega.training.run.train_or_resume`), so running it again finishes what a crash left.
``--config`` adds YAML settings over each body's preset (as ``qdsega train --config``; a tiny
budget for a quick check).

Then the table, printed and written to ``OUT/table.md``: per seed, the old policy's exact
distance on the changed body, the fresh run's result F (its farthest exact generation), and
the generations (and simulated steps: memo transitions measured and exact trials' commands)
each run needs until its greedy policy covers 0.9 F with exact physics: 0 for a warm run
whose handed-on path already covers it when verified, before it learns at all. A second table
takes the median over the seeds of each change.
"""

from __future__ import annotations

import argparse
import statistics
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from qdsega.analysis.evaluation import evaluate_on
from qdsega.description import load_formation, resolve_formation
from qdsega.errors import QdsegaError
from qdsega.training.config import TrainingConfig, default_preset, resolve_config
from qdsega.training.run import train, train_or_resume
from qdsega.training.run_folder import RunFolder

CHANGES = (
    ("hexapod", "hexapod_lost_leg", "a front leg lost"),
    ("legged12", "legged12_locked_leg", "a leg locked"),
    ("snake5", "snake6", "a unit added"),
    ("quadruped", "quadruped_tripod", "a back leg lost (tripod)"),
)
"""(old formation, changed formation, what changed)."""
SIM = "memo"
GRID_CONFIG = "default"
"""The config name of ``experiments/grid/grid.yaml``'s runs (their folders' third part)."""

COLUMNS = (
    "change",
    "seed",
    "old policy on the new body (m)",
    "fresh final F (m)",
    "fresh: generations (steps) to 0.9 F",
    "warm: handed-on path verified (m)",
    "warm: first generation (m)",
    "warm: generations (steps) to 0.9 F",
    "warm / fresh generations",
    "warm final (m)",
)
AGGREGATE_COLUMNS = (
    "change",
    "seeds",
    "old policy on the new body (m)",
    "fresh final F (m)",
    "fresh generations to 0.9 F",
    "warm generations to 0.9 F",
    "median of warm / fresh generations",
    "median of warm / fresh simulated steps",
    "aim: warm <= 20 % of fresh",
)

Reach = tuple[int | None, int | None]


@dataclass(frozen=True)
class Change:
    """One seed of one change: the old policy on the new body (m), the fresh run's result
    F (m, its farthest exact generation), the (generation, simulated steps) at which the
    fresh and the warm run first reach 0.9 F, and warm over fresh generations."""

    moved_m: float
    fresh_m: float
    fresh: Reach
    warm: Reach
    share: float | None


@dataclass(frozen=True)
class Settings:
    """How every run of the table is configured: ``workers`` processes, and the YAML file
    ``config`` (None: none) over each body's preset."""

    workers: int
    config: Path | None

    def of(self, formation_file: Path, seed: int) -> TrainingConfig:
        """Memo mode, the body's own preset, ``seed``."""
        preset = default_preset(load_formation(formation_file), SIM)
        overrides = {"sim": SIM, "seed": seed, "workers": self.workers}
        return resolve_config(preset=preset, file=self.config, overrides=overrides)


def old_run(grid: Path, name: str, config: TrainingConfig) -> Path:
    """The folder of formation ``name``'s run in ``grid``: the sweep's
    ``NAME-PRESET-default-seedS``, else the older ``NAME-seedS`` where only that one exists."""
    sweep = grid / f"{name}-{config.preset}-{GRID_CONFIG}-seed{config.seed}"
    legacy = grid / f"{name}-seed{config.seed}"
    return legacy if not RunFolder(sweep).started and RunFolder(legacy).started else sweep


def warm_run(formation_file: Path, config: TrainingConfig, out: Path, source: Path) -> None:
    """Make ``out`` a finished run warm-started from the finished run ``source``: kept when
    finished, resumed when started (its warm start is in the folder), else trained."""
    if RunFolder(out).started:
        train_or_resume(formation_file, config, out)
    else:
        train(formation_file, config, out, warm_start=source)


def transfer(base: Path, new: str) -> float:
    """The exact distance (m) of ``base``'s greedy policy on the formation ``new`` (replayed
    once, then read from ``base``)."""
    name = load_formation(resolve_formation(Path(new))).name
    file = RunFolder(base).evaluation_file(formation=name)
    if file.is_file():
        result: dict[str, Any] = RunFolder(base).read_json(file.name)
    else:
        result, _ = evaluate_on(base, new)
    return float(result["distance_m"])


def handed_on(run: Path) -> str:
    """How far a warm run's handed-on path walked when verified (m), or why it is unknown."""
    record = RunFolder(run).read_warm_start() or {}
    if "handed_on_m" not in record:
        return "not recorded"
    return f"{record['handed_on_m']:.3f}"


def first_exact(run: Path) -> float:
    """The first generation's exact distance (m)."""
    return float(RunFolder(run).read_metrics()["greedy_exact_m"][0])


def markdown(header: tuple[str, ...], rows: list[list[str]]) -> str:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def _count(generations: int | None, steps: int | None) -> str:
    return "not reached" if generations is None else f"{generations} ({steps:,})"


def measure(
    change: tuple[str, str, str], seed: int, grid: Path, out: Path, settings: Settings
) -> tuple[Change, list[str]]:
    """Make (or keep) the three runs of one change and seed; its facts and its table row."""
    old, new, what = change
    old_file, new_file = resolve_formation(Path(old)), resolve_formation(Path(new))
    old_config, new_config = settings.of(old_file, seed), settings.of(new_file, seed)
    base = old_run(grid, old, old_config)
    fresh = out / "fresh" / f"{new}-seed{seed}"
    warm = out / "warm" / f"{new}-seed{seed}"
    train_or_resume(old_file, old_config, base)
    moved = transfer(base, new)
    final = train_or_resume(new_file, new_config, fresh)["distance_m"]
    warm_run(new_file, new_config, warm, base)
    target = 0.9 * final
    fresh_reach, warm_reach = RunFolder(fresh).reached(target), RunFolder(warm).reached(target)
    share = (
        warm_reach[0] / fresh_reach[0]
        if warm_reach[0] is not None and fresh_reach[0] is not None
        else None
    )
    warm_final = RunFolder(warm).read_summary()["distance_m"]
    row = [
        what, str(seed), f"{moved:.3f}", f"{final:.3f}", _count(*fresh_reach), handed_on(warm),
        f"{first_exact(warm):.3f}", _count(*warm_reach),
        "" if share is None else f"{share:.2f}", f"{warm_final:.3f}",
    ]  # fmt: skip
    return Change(moved, final, fresh_reach, warm_reach, share), row


def aggregate(what: str, found: list[Change]) -> list[str]:
    """Medians over the seeds of one change. A warm run that never reaches 0.9 F leaves the
    share undefined and the aim missed."""
    fresh = [c.fresh[0] for c in found if c.fresh[0] is not None]
    warm = [c.warm[0] for c in found if c.warm[0] is not None]
    shares = [c.share for c in found if c.share is not None]
    steps = [c.warm[1] / c.fresh[1] for c in found if c.warm[1] and c.fresh[1]]
    median_share = statistics.median(shares) if len(shares) == len(found) else None
    return [
        what,
        str(len(found)),
        f"{statistics.median(c.moved_m for c in found):.3f}",
        f"{statistics.median(c.fresh_m for c in found):.3f}",
        f"{statistics.median(fresh):g}" if fresh else "not reached",
        f"{statistics.median(warm):g}" if len(warm) == len(found) else "not reached by every seed",
        "" if median_share is None else f"{median_share:.2f}",
        f"{statistics.median(steps):.2f}" if steps else "",
        "MISSED" if median_share is None or median_share > 0.2 else "met",
    ]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    parser.add_argument("--grid", type=Path, default=Path("runs/grid"), help="the old runs")
    parser.add_argument("--out", type=Path, default=Path("runs/reconfiguration"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument(
        "--changes",
        nargs="+",
        choices=[c[1] for c in CHANGES],
        default=[c[1] for c in CHANGES],
        help="changed formations",
    )
    parser.add_argument(
        "--config", type=Path, metavar="FILE.yaml", help="settings over each body's preset"
    )
    args = parser.parse_args()
    settings = Settings(args.workers, args.config)
    rows, aggregates = [], []
    try:
        for change in (c for c in CHANGES if c[1] in args.changes):
            found = []
            for seed in args.seeds:
                facts, row = measure(change, seed, args.grid, args.out, settings)
                found.append(facts)
                rows.append(row)
            aggregates.append(aggregate(change[2], found))
    except QdsegaError as exc:
        parser.error(str(exc))
    text = markdown(COLUMNS, rows) + "\n\n" + markdown(AGGREGATE_COLUMNS, aggregates)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "table.md").write_text(text + "\n", encoding="utf-8")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
