"""Print the table of evaluated runs: prediction against exact physics, and the reference.

Usage: .venv/bin/python tools/formation_table.py RUN [RUN ...]

Each RUN is a run folder that ``qdsega train`` finished and ``qdsega evaluate`` replayed. The
table is Markdown, one row per run: formation, seed, budget, wall time of training, the final
greedy policy's distance as the learner's world predicted it and with exact physics, the
prediction's error, the share of generations whose prediction was within 10 % of their exact
replay, the last generation's exact distance over the first's, the classic and the best
reference gait, the ratio learnt/best reference and the rhythm (period, phase lags). A second
table aggregates the runs of each formation: median exact distance and ratio, worst seed's
ratio over the median, and the aims of the physics-fidelity issue.
"""

from __future__ import annotations

import argparse
import csv
import json
import statistics
from dataclasses import dataclass
from pathlib import Path

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


@dataclass(frozen=True)
class Run:
    """The facts of one evaluated run folder."""

    formation: str
    exact_m: float
    predicted_m: float
    ratio: float | None
    within: int
    generations: int
    growth: float | None
    cells: list[str]


def read_run(run: Path) -> Run:
    """The row of the evaluated run folder ``run``."""
    summary = json.loads((run / "summary.json").read_text(encoding="utf-8"))
    evaluation = json.loads((run / "evaluation.json").read_text(encoding="utf-8"))
    config = (run / "config.yaml").read_text(encoding="utf-8")
    with (run / "metrics.csv").open(encoding="utf-8") as stream:
        metrics = list(csv.DictReader(stream))
    population = next(
        line.split(":")[1].strip()
        for line in config.splitlines()
        if line.strip().startswith("population:")
    )
    pairs = [(float(m["greedy_distance_m"]), float(m["greedy_exact_m"])) for m in metrics]
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
    return Run(summary["formation"], exact, predicted, ratio, within, len(pairs), growth, cells)


def aggregate(runs: list[Run]) -> list[str]:
    """One row over the runs of one formation."""
    ratios = [r.ratio for r in runs if r.ratio is not None]
    median_ratio = statistics.median(ratios) if ratios else None
    worst = min(ratios) / median_ratio if ratios and median_ratio else None
    final = sum(abs(r.predicted_m - r.exact_m) <= 0.1 * abs(r.exact_m) for r in runs)
    growths = [r.growth for r in runs if r.growth is not None]
    return [
        runs[0].formation,
        str(len(runs)),
        f"{statistics.median(r.exact_m for r in runs):.3f}",
        "" if median_ratio is None else f"{median_ratio:.3f}",
        "" if worst is None else f"{worst:.3f}",
        f"{final}/{len(runs)}",
        f"{sum(r.within for r in runs)}/{sum(r.generations for r in runs)}",
        f"{statistics.median(growths):.2f}" if growths else "",
    ]


def markdown(header: tuple[str, ...], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def tables(folders: list[Path]) -> str:
    """Both tables, Markdown, for the evaluated run folders."""
    runs = [read_run(folder) for folder in folders]
    by_formation: dict[str, list[Run]] = {}
    for run in runs:
        by_formation.setdefault(run.formation, []).append(run)
    return (
        markdown(COLUMNS, [run.cells for run in runs])
        + "\n\n"
        + markdown(AGGREGATE_COLUMNS, [aggregate(group) for group in by_formation.values()])
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=Path, nargs="+", metavar="RUN")
    print(tables(parser.parse_args().runs))


if __name__ == "__main__":
    main()
