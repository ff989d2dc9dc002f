"""Tables of evaluated runs: prediction against exact physics, the reference, medians per group.

Usage: .venv/bin/python experiments/grid/formation_table.py RUN_OR_SWEEP [RUN_OR_SWEEP ...]

Each argument is a run folder that ``qdsega train`` finished and ``qdsega evaluate`` replayed,
or the folder a ``qdsega sweep`` wrote (``runs/grid`` for ``experiments/grid/grid.yaml``): its
runs that finished, in the order of its ``sweep.csv``. The first table is Markdown, one row per
run: formation, seed, budget, wall time of training, the final greedy policy's distance as the
learner's model predicted it and with exact physics, the prediction's error, the share of
generations whose prediction was within 10 % of their exact replay, the last generation's
exact distance over the first's, the classic and the best reference gait, the ratio
learnt/best reference and the rhythm (period, phase lags). The second table aggregates the
runs of each group, the run folder's name without its ``-seedS`` (a sweep's
``FORMATION-PRESET-CONFIG``; else the formation): median exact distance and ratio, worst seed's
ratio over the median, and the aims of the physics-fidelity issue. What ``qdsega sweep``'s own
``sweep.md`` lacks: the rhythm, the wall time, the generations within 10 % and these medians.
"""

from __future__ import annotations

import argparse
import csv
import re
import statistics
import sys
from dataclasses import dataclass
from pathlib import Path

from qdsega.errors import QdsegaError, RunFolderError
from qdsega.training.finished_run import FinishedRun
from qdsega.training.run_folder import RunFolder

COLUMNS = (
    "formation",
    "seed",
    "population x generations x trials",
    "training",
    "predicted (m)",
    "exact (m)",
    "error",
    "generations within 10 %",
    "last / first",
    "classic reference (m)",
    "best reference (m)",
    "ratio",
    "rhythm",
)
AGGREGATE_COLUMNS = (
    "formation",
    "runs",
    "median exact (m)",
    "median ratio",
    "worst / median ratio",
    "final error within 10 %",
    "generations within 10 %",
    "median last / first",
)
_SEED_SUFFIX = re.compile(r"^(?P<group>.+)-seed\d+$")


@dataclass(frozen=True)
class Run:
    """The facts of one evaluated run folder."""

    group: str
    exact_m: float
    predicted_m: float
    ratio: float | None
    within: int
    generations: int
    growth: float | None
    cells: list[str]


def read_run(run: Path) -> Run:
    """The row of the evaluated run folder ``run``.

    Raises:
        RunFolderError: not a finished, evaluated run folder.
    """
    finished = FinishedRun.open(run, RunFolder.CONFIG, RunFolder.METRICS)
    summary, evaluation = finished.summary, finished.folder.read_evaluation()
    if evaluation is None:
        raise RunFolderError(f"not evaluated (no {RunFolder.EVALUATION})", file=run)
    population = finished.config.agent.genetic.population
    metrics = finished.folder.read_metrics()
    pairs = list(zip(metrics["greedy_distance_m"], metrics["greedy_exact_m"], strict=True))
    within = sum(abs(p - e) <= 0.1 * abs(e) for p, e in pairs)
    first, last = pairs[0][1], pairs[-1][1]
    growth = last / first if first > 0 else None
    minutes, seconds = divmod(round(summary["wall_s"]), 60)
    predicted = summary["greedy_distance"]
    exact = evaluation["distance_m"]
    wave = evaluation.get("wave") or {}
    lags = ", ".join(f"{lag:.0f}" for lag in wave.get("phase_lag_deg", []))
    rhythm = f"period {wave.get('period_steps')}, lags [{lags}] deg" if wave else ""
    reference = evaluation["reference"]
    classic = evaluation.get("references", [reference])[0]  # the hand-designed one comes first
    failure = f" ({evaluation['failure']})" if evaluation["failure"] else ""
    ratio = evaluation["ratio"]
    error = (predicted - exact) / abs(exact) if exact else None
    cells = [
        summary["formation"],
        str(summary["seed"]),
        f"{population} x {summary['generations']} x {summary['trials_per_generation']}",
        f"{minutes} min {seconds:02d} s",
        f"{predicted:.3f}",
        f"{exact:.3f}{failure}",
        "" if error is None else f"{error:+.1%}",
        f"{within}/{len(pairs)}",
        "" if growth is None else f"{growth:.2f}",
        f"{classic['distance_m']:.3f}",
        f"{reference['distance_m']:.3f} ({reference['kind']})",
        "" if ratio is None else f"{ratio:.3f}",
        rhythm,
    ]
    match = _SEED_SUFFIX.match(Path(run).resolve().name)
    group = match["group"] if match else summary["formation"]
    return Run(group, exact, predicted, ratio, within, len(pairs), growth, cells)


def run_folders(path: Path) -> list[Path]:
    """``path`` itself when it is a run folder; the finished runs of a sweep's folder (the
    ``ok`` rows of its ``sweep.csv``, in order), a note on stderr for each one that failed.

    Raises:
        RunFolderError: neither a run folder nor a sweep's folder.
    """
    if RunFolder(path).started:
        return [path]
    table = path / "sweep.csv"
    if not table.is_file():
        raise RunFolderError("neither a run folder nor a sweep's folder (no sweep.csv)", file=path)
    with table.open(encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    for row in rows:
        if row["status"] != "ok":
            print(f"{path / row['run']}: left out ({row['error']})", file=sys.stderr)
    return [path / row["run"] for row in rows if row["status"] == "ok"]


def aggregate(runs: list[Run]) -> list[str]:
    """One row over the runs of one group."""
    ratios = [r.ratio for r in runs if r.ratio is not None]
    median_ratio = statistics.median(ratios) if ratios else None
    worst = min(ratios) / median_ratio if ratios and median_ratio else None
    final = sum(abs(r.predicted_m - r.exact_m) <= 0.1 * abs(r.exact_m) for r in runs)
    growths = [r.growth for r in runs if r.growth is not None]
    return [
        runs[0].group,
        str(len(runs)),
        f"{statistics.median(r.exact_m for r in runs):.3f}",
        "" if median_ratio is None else f"{median_ratio:.3f}",
        "" if worst is None else f"{worst:.3f}",
        f"{final}/{len(runs)}",
        f"{sum(r.within for r in runs)}/{sum(r.generations for r in runs)}",
        f"{statistics.median(growths):.2f}" if growths else "",
    ]


def markdown(header: tuple[str, ...], rows: list[list[str]]) -> str:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def tables(folders: list[Path]) -> str:
    """Both tables, Markdown, for the evaluated run folders."""
    runs = [read_run(folder) for folder in folders]
    groups: dict[str, list[Run]] = {}
    for run in runs:
        groups.setdefault(run.group, []).append(run)
    return (
        markdown(COLUMNS, [run.cells for run in runs])
        + "\n\n"
        + markdown(AGGREGATE_COLUMNS, [aggregate(group) for group in groups.values()])
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", type=Path, nargs="+", metavar="RUN_OR_SWEEP")
    args = parser.parse_args()
    try:
        folders = [folder for path in args.paths for folder in run_folders(path)]
        if not folders:
            parser.error("no finished run to tabulate")
        print(tables(folders))
    except QdsegaError as exc:
        parser.error(str(exc))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
