"""Print the table of evaluated runs: memo prediction against exact physics, and the reference.

Usage: .venv/bin/python tools/formation_table.py RUN [RUN ...]

Each RUN is a run folder that ``qdsega train`` finished and ``qdsega evaluate`` replayed. The
table is Markdown, one row per run: formation, world, budget, wall time of training, the
greedy policy's distance as the memo table predicted it and as exact physics measured it, the
best reference gait, the ratio learnt/reference and the rhythm (period, phase lags).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

COLUMNS = (
    "formation",
    "sim",
    "population x generations x trials",
    "training",
    "predicted (m)",
    "exact (m)",
    "reference (m)",
    "ratio",
    "rhythm",
)


def row(run: Path) -> list[str]:
    """One table row for the evaluated run folder ``run``."""
    summary = json.loads((run / "summary.json").read_text(encoding="utf-8"))
    evaluation = json.loads((run / "evaluation.json").read_text(encoding="utf-8"))
    config = (run / "config.yaml").read_text(encoding="utf-8")
    population = next(
        line.split(":")[1].strip()
        for line in config.splitlines()
        if line.strip().startswith("population:")
    )
    minutes, seconds = divmod(round(summary["wall_s"]), 60)
    predicted = evaluation["memo_prediction_m"]
    wave = evaluation.get("wave") or {}
    lags = ", ".join(f"{lag:.0f}" for lag in wave.get("phase_lag_deg", []))
    rhythm = f"period {wave.get('period_steps')}, lags [{lags}] deg" if wave else ""
    reference = evaluation["reference"]
    failure = f" ({evaluation['failure']})" if evaluation["failure"] else ""
    return [
        summary["formation"],
        summary["sim"],
        f"{population} x {summary['generations']} x {summary['trials_per_generation']}",
        f"{minutes} min {seconds:02d} s",
        "" if predicted is None else f"{predicted:.3f}",
        f"{evaluation['distance_m']:.3f}{failure}",
        f"{reference['distance_m']:.3f} ({reference['kind']})",
        "" if evaluation["ratio"] is None else f"{evaluation['ratio']:.3f}",
        rhythm,
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=Path, nargs="+", metavar="RUN")
    args = parser.parse_args()
    print("| " + " | ".join(COLUMNS) + " |")
    print("|" + "---|" * len(COLUMNS))
    for run in args.runs:
        print("| " + " | ".join(row(run)) + " |")


if __name__ == "__main__":
    main()
