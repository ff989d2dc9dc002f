"""Benchmark: wall time of the full paper protocol in the MSM, and Q-learning steps per second.

Usage: taskset -c 1 .venv/bin/python experiments/msm/benchmark_msm.py [--seed 0] [--generations G]

Trains legged12 in the MSM with the paper-legged preset (200 generations x 10000 trials, or
``--generations``) in-process into a scratch folder, after one tiny warm-up run (so compiled
code is loaded, as from the cache in later runs), and prints its wall time and steps/s.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from qdsega.description.shipped import ASSEMBLIES_DIR
from qdsega.training.config import resolve_config
from qdsega.training.run import budget_overrides, train

PRESET = "paper-legged"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--generations", type=int)
    args = parser.parse_args()
    formation = ASSEMBLIES_DIR / "legged12.yaml"
    with tempfile.TemporaryDirectory() as scratch:
        warm = budget_overrides(generations=1, trials=10, seed=0)
        train(formation, resolve_config(preset=PRESET, overrides=warm), Path(scratch) / "warm")
        budget = budget_overrides(generations=args.generations, trials=None, seed=args.seed)
        config = resolve_config(preset=PRESET, overrides=budget)
        start = time.perf_counter()
        summary = train(formation, config, Path(scratch) / "run")
        wall = time.perf_counter() - start
    print(
        f"full protocol: {summary['generations']} generations x "
        f"{summary['trials_per_generation']} trials, {summary['env_steps']} steps in "
        f"{wall:.1f} s = {summary['env_steps'] / wall:,.0f} steps/s "
        f"(greedy/optimum {summary['greedy_over_optimum']:.3f})"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
